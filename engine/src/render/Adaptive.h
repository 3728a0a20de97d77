#pragma once
// Adaptive anti-aliasing's decisions (FrameSettings::aa = Adaptive, docs/antialiasing.md), pure logic for the
// Renderer's accumulation and for unit tests without GL: which pixels a round samples again, and which of
// them need their rays traced.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Settings.h"

namespace tandem {

/// A pixel's luminance as the display shows it (exposure, tone map, then a square root for ≈ sRGB), so a
/// threshold means about the same visible step in dark and bright parts.
float displayLuminance(glm::vec3 linear, const FrameSettings& s);

/// Marks every pixel within `radius` (a square: 8 neighbours at 1) of a marked one.
void dilate(std::vector<std::uint8_t>& mask, int width, int height, int radius);

/// The pixels the next adaptive round samples: those whose samples so far (count > 0) span more than
/// `threshold` in display luminance (hi − lo), and their 8 neighbours — a thin feature can miss all of a
/// pixel's first samples, but rarely those of the pixels beside it. `traced`: those, grown by 2·rayScale
/// pixels, where a coarse ray grid's samples blend into them. False (and nothing marked) when no pixel disagrees.
bool adaptiveRound(const std::vector<float>& lo, const std::vector<float>& hi, const std::vector<std::uint32_t>& count,
                   int width, int height, float threshold, int rayScale, std::vector<std::uint8_t>& refine,
                   std::vector<std::uint8_t>& traced);

}  // namespace tandem
