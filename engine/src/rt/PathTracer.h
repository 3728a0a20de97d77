#pragma once
// The reference frame's ground truth with diffuse interreflection (FrameSettings::gi = Path,
// `--preset reference --gi path`; docs/path-tracing.md): paths through the same scene description and
// shading model as the Whitted reference, so radiosity and the two-pass frame can be measured against it.
#include <cstdint>

#include "rt/Whitted.h"

namespace tandem::rt {

/// At every hit of a path, the Whitted local term with its shadow rays (next-event estimation: each light's
/// diffuse and Phong terms, area lights by their samples, the emission; no ambient term, which the
/// interreflection replaces), then one continuation chosen at random in proportion to its weight: a diffuse
/// bounce (cosine-weighted about the shading normal, weight the surface colour, the BRDF kd/π under the
/// Phong convention that a light adds kd·E·cosθ), the Whitted reflection (wR, glossy about the mirror
/// direction for a rough material) or the refraction (wT). Russian roulette after kMinBounces keeps the
/// estimate unbiased; kMaxBounces only guards a scene whose weights add up to 1 or more.
class PathTracer {
 public:
  explicit PathTracer(const Whitted& whitted) : w_(whitted) {}

  /// Radiance towards the camera from the primary hit `hit`. The path's random numbers are a hash of
  /// (x, y, sample, dimension): the same image on any thread count.
  glm::vec3 radiance(SurfaceHit hit, int x, int y, std::uint32_t sample, RayCounts& counts) const;

  static constexpr int kMinBounces = 3;
  static constexpr int kMaxBounces = 256;

 private:
  const Whitted& w_;
};

/// A cosine-weighted direction about unit `n` from u ∈ [0, 1)² (pdf cosθ/π).
glm::vec3 cosineDirection(glm::vec3 n, glm::vec2 u);

}  // namespace tandem::rt
