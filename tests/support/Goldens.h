#pragma once
// When golden images may be rewritten: only when the test binary is run with --update-goldens, which the build's
// `update-goldens` target passes (cmake --build build --target update-goldens). The environment variable the
// tests once read, left set in a shell, made every golden test overwrite its golden and skip — so a set
// TANDEM_UPDATE_GOLDENS now fails the test instead, naming the target.
#include <algorithm>
#include <cstdlib>
#include <string>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "tandem/Image.h"

namespace tandem::test {

// ---- How a frame is compared with its golden (tests/golden/README.md has the measurements) ----
// A GL may turn a float into an 8-bit level as either of the two nearest levels (GL 4.5 §2.3.5.1; NVIDIA
// rounds values at or near a half step down where llvmpipe rounds up: 1.9 % of a Whitted frame's values, all
// by one level), and a GPU's pow and fused multiply-adds move values by a small part of a level, more only at
// the sharpest highlights. What a golden must catch moves a few hundred pixels by several levels (flat shading
// forced, Schlick's Fresnel, one bounce less) or every pixel a little (exposure, a tone-map constant). So:
//   - at most 0.1 % of pixels with a channel more than 2 levels off;
//   - each channel's mean difference within 0.25 of a level.
// A perceptual mean (FLIP) adds the one-level noise of a GPU's rounding up over the whole frame to as much as a
// forced flat shading (0.0030 against 0.0011): it is reported, not judged.
inline constexpr int kGoldenLevels = 2;
inline constexpr double kGoldenFractionOver = 0.001;
inline constexpr double kGoldenMeanShift = 0.25;

struct GoldenDiff {
  double fractionOver = 0.0;  // pixels with a channel more than kGoldenLevels off
  int maxDiff = 0;            // the largest channel difference, in levels
  glm::dvec3 meanSigned{0.0}; // per channel, frame − golden, in levels
};

inline GoldenDiff compareToGolden(const Image& frame, const Image& golden) {
  GoldenDiff d;
  if (frame.width != golden.width || frame.height != golden.height || frame.rgba.size() != golden.rgba.size()) {
    d.fractionOver = 1.0;
    return d;
  }
  std::size_t over = 0;
  glm::dvec3 sum(0.0);
  for (std::size_t i = 0; i < frame.rgba.size(); i += 4) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int diff = int(frame.rgba[i + static_cast<std::size_t>(c)]) - int(golden.rgba[i + static_cast<std::size_t>(c)]);
      sum[c] += diff;
      worst = std::max(worst, std::abs(diff));
    }
    d.maxDiff = std::max(d.maxDiff, worst);
    if (worst > kGoldenLevels) ++over;
  }
  const double pixels = double(frame.rgba.size() / 4);
  d.fractionOver = double(over) / pixels;
  d.meanSigned = sum / pixels;
  return d;
}

/// Empty when `d` is within the golden tolerance; otherwise which bound it breaks and by how much.
inline std::string goldenMismatch(const GoldenDiff& d) {
  std::string why;
  if (d.fractionOver > kGoldenFractionOver)
    why += std::to_string(100.0 * d.fractionOver) + " % of pixels more than 2 levels off (at most 0.1 %, largest " +
           std::to_string(d.maxDiff) + "); ";
  for (int c = 0; c < 3; ++c)
    if (std::abs(d.meanSigned[c]) > kGoldenMeanShift)
      why += "channel " + std::to_string(c) + " shifted by " + std::to_string(d.meanSigned[c]) + " levels on average (at most 0.25); ";
  return why;
}

inline bool updatingGoldens() {
  for (const std::string& arg : ::testing::internal::GetArgvs())
    if (arg == "--update-goldens") return true;
  return false;
}

/// Empty when golden tests may run; otherwise why not (a stray TANDEM_UPDATE_GOLDENS).
inline std::string strayGoldenUpdate() {
  if (std::getenv("TANDEM_UPDATE_GOLDENS") == nullptr) return {};
  return "TANDEM_UPDATE_GOLDENS is set, but goldens are rewritten only by `cmake --build build --target "
         "update-goldens` (unset it to compare)";
}

}  // namespace tandem::test
