#pragma once
// Sample sequences shared by the frame's anti-aliasing and its tests (no GL, no Embree).
#include <cstdint>

#include <glm/glm.hpp>

namespace tandem {

/// The (0, 2)-sequence in base 2 (Sobol's first two dimensions) as 32-bit fixed point: x is i with its
/// bits mirrored (van der Corput), y the second Sobol dimension, whose generator is Pascal's triangle
/// mod 2. Every aligned block of 2^k points is a (0, k, 2)-net: one point in each of the 2^k dyadic boxes
/// of any shape (2^k × 1 columns, 1 × 2^k rows, 2 × 2^(k-1) cells, ...).
inline glm::uvec2 sobol02(std::uint32_t i) {
  std::uint32_t x = 0, y = 0;
  std::uint32_t vx = 1u << 31, vy = 1u << 31;
  for (; i != 0; i >>= 1, vx >>= 1, vy ^= vy >> 1)
    if ((i & 1u) != 0) x ^= vx, y ^= vy;
  return {x, y};
}

/// The sub-pixel offset of anti-aliasing sample `index` (Camera::jitterPx), within ±0.5 pixel: the
/// (0, 2)-sequence under the digital shift (XOR) by (5/8, 7/8), which keeps the net property and moves the
/// points off the pixel's corners and centre: every 4 samples from a multiple of 4 are 4 rooks, the first
/// four (1/8, 3/8), (-3/8, -1/8), (3/8, -3/8), (-1/8, 1/8), in 4 distinct columns and 4 distinct rows a
/// quarter pixel apart, the classic 4-sample pattern (a rotated grid's property) for near-horizontal and
/// near-vertical edges. So no band of a pixel wider than a quarter goes unsampled by the adaptive test's
/// first four, and an accumulation may stop after any number of samples. A frame without anti-aliasing
/// samples the centre instead; one jittered sample is a sub-pixel shift of it, not the same frame.
inline glm::vec2 subpixelJitter(std::uint32_t index) {
  const glm::uvec2 u = sobol02(index) ^ glm::uvec2(0xA0000000u, 0xE0000000u);
  return glm::vec2(u) * (1.0f / 4294967296.0f) - 0.5f;
}

}  // namespace tandem
