#pragma once
// Sample sequences shared by the frame's anti-aliasing and its tests (no GL, no Embree).
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "core/Shading.h"

namespace tandem {

/// The (0, 2)-sequence in base 2 (Sobol's first two dimensions) as 32-bit fixed point, point i: its one
/// definition is shaders/shading.glsl's tdSobol02Bits (the area lights' samples in the GL and the ray pass read
/// it there). Every aligned block of 2^k points is a (0, k, 2)-net: one point in each of the 2^k dyadic boxes
/// of any shape (2^k × 1 columns, 1 × 2^k rows, 2 × 2^(k-1) cells, ...).
inline glm::uvec2 sobol02(std::uint32_t i) { return shading::tdSobol02Bits(i); }

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

/// A bijection of the 32-bit indices that keeps every aligned block of 2^k indices an aligned block of 2^k
/// (output bit j depends only on input bits j..31), shuffling the order inside each block by `seed`: the
/// nested uniform shuffle (Owen's scrambling applied to the index, Burley 2020). A (0, 2)-sequence read at
/// shuffled indices is still a net in every prefix of 2^k points, and two such reads with different seeds
/// pair their points at random: a second, decorrelated 2-D sequence for the same sample index.
inline std::uint32_t nestedShuffle(std::uint32_t index, std::uint32_t seed) {
  // Mirror the bits so that the steps below, which carry only towards the high bits (addition,
  // multiplication by an odd number, x ^= x << s: each a bijection), carry from high to low index bits.
  auto mirror = [](std::uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
    v = ((v >> 8) & 0x00FF00FFu) | ((v & 0x00FF00FFu) << 8);
    return (v >> 16) | (v << 16);
  };
  std::uint32_t x = mirror(index);
  x += seed;
  x *= 0x2C1B3C6Du | 1u;
  x ^= x << 9;
  x += seed * 0x297A2D39u;
  x *= 0x9E3779B1u;
  x ^= x << 13;
  x *= 0x85EBCA77u;
  return mirror(x);
}

/// Concentric map of the unit square onto the unit disk (Shirley and Chiu 1997): it keeps strata
/// compact and areas proportional, so a stratified square gives a stratified disk. (0.5, 0.5) is the centre.
inline glm::vec2 squareToDisk(glm::vec2 u) {
  const glm::vec2 p = 2.0f * u - 1.0f;
  if (p.x == 0.0f && p.y == 0.0f) return glm::vec2(0.0f);
  constexpr float kQuarterPi = 0.78539816339f;
  float r, phi;
  if (std::abs(p.x) > std::abs(p.y)) {
    r = p.x;
    phi = kQuarterPi * (p.y / p.x);
  } else {
    r = p.y;
    phi = 2.0f * kQuarterPi - kQuarterPi * (p.x / p.y);
  }
  return r * glm::vec2(std::cos(phi), std::sin(phi));
}

/// The lens point of accumulated sample `index` (Camera::lensUv) in [0, 1)²: the (0, 2)-sequence at
/// nestedShuffle'd indices, so every 2^k samples from a multiple of 2^k cover the lens as a net while each
/// pairs with an unrelated sub-pixel offset (subpixelJitter reads the same sequence in order).
inline glm::vec2 lensSample(std::uint32_t index) {
  const glm::uvec2 u = sobol02(nestedShuffle(index, 0x6A09E667u));
  return glm::vec2(u >> 8u) * (1.0f / 16777216.0f);  // 24 bits: exact in float, < 1
}

/// The shutter time of accumulated sample `index` (Camera::timeU) in [0, 1): van der Corput's sequence at
/// nestedShuffle'd indices (its own seed), so every 2^k samples from a multiple of 2^k fall one in each
/// 1/2^k of the shutter, in an order unrelated to the sub-pixel offsets and the lens points.
inline float timeSample(std::uint32_t index) {
  return static_cast<float>(sobol02(nestedShuffle(index, 0xBB67AE85u)).x >> 8) * (1.0f / 16777216.0f);
}

}  // namespace tandem
