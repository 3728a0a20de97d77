#pragma once
// Exact solids in the hybrid frame (docs/csg.md, "In the raster frame"): the raster draws an exact solid's
// proxy, and the ray pass resolves each pixel it covers by the pixel's camera ray. This is what that pass
// hands the GL for such a pixel: the record the patch pass (shaders/resolve.vert) draws into the visibility
// buffer, laid out as its std430 storage buffer reads it. Core: no GL, no Embree (rt writes it, gl reads it).
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace tandem {

/// The triangle field of a visibility id whose hit lies on an exact solid, not on a triangle: the shade pass
/// reads that hit from the exact-hits channel instead (TD_EXACT_TRIANGLE in shaders/bindings.glsl).
inline constexpr std::uint32_t kExactTriangle = 0xFFFFFFFFu;

struct ResolvedPixel {
  glm::uvec2 pixel{0u};  // x, y of the full-resolution pixel, row 0 at the top
  /// What the visibility buffer holds there now: instance + 1 and the triangle (kExactTriangle: the hit lies
  /// on the instance's exact solid), or 0 where the ray met nothing (the background shows).
  glm::uvec2 id{0u};
  /// A hit on a solid: xyz its outward unit normal (world directions), w the hit's distance along the pixel's
  /// camera ray (Camera::rayThroughPixel, a unit direction). Zero otherwise.
  glm::vec4 hit{0.0f};
  float depth = 0.0f;    // reversed-Z window depth of the hit; 0 (far) for the background
  float pad[3] = {0.0f, 0.0f, 0.0f};
};
static_assert(sizeof(ResolvedPixel) == 48 && offsetof(ResolvedPixel, hit) == 16 && offsetof(ResolvedPixel, depth) == 32,
              "ResolvedPixel is read as a std430 struct { uvec2; uvec2; vec4; float; } (shaders/resolve.vert)");

}  // namespace tandem
