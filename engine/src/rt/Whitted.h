#pragma once
// Whitted recursion on Embree for one frame: shadow rays, mirror reflection, refraction with Fresnel.
// Read-only after construction, so any number of tiles trace through one instance concurrently.
#include <cstdint>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"
#include "tandem/FrameStats.h"
#include "tandem/Settings.h"

namespace tandem::rt {

/// Which effects rays produce this frame, from the settings (hybrid or reference).
struct TraceModes {
  bool primaryShadowRays = false;    // lightMask of the primary point by rays
  bool secondaryShadowRays = false;  // shadows at secondary hits (there is no shadow map on the CPU)
  bool reflections = false;
  bool refraction = false;
  int maxDepth = 0;
  float minContribution = 0.0f;
  FresnelMode fresnel = FresnelMode::Exact;
  bool fresnelWeighted = true;
  static TraceModes hybrid(const FrameSettings& s);
  static TraceModes reference(const FrameSettings& s);  // raster-made effects become rays
};

/// The weights of the Whitted sum at a hit (docs/shading.md).
struct WhittedWeights {
  float reflect = 0.0f;   // wR
  float transmit = 0.0f;  // wT (0 on total internal reflection)
  Refraction refraction;
};

/// A shadow ray ready for Embree, or none needed.
struct ShadowRay {
  bool needed = false;
  bool visibleWithoutRay = false;  // when !needed: the mask bit
  glm::vec3 originW{0.0f};
  glm::vec3 dirW{0.0f};
  float tFar = 0.0f;
};

class Whitted {
 public:
  Whitted(const Scene& scene, const EmbreeScene& embree, const FrameShading& frame, TraceModes modes)
      : scene_(scene), embree_(embree), frame_(frame), modes_(modes) {}

  /// The shadow ray from hit towards direct light j (or why none is needed).
  ShadowRay shadowRay(const SurfaceHit& hit, std::size_t light) const;
  /// All direct lights' visibility bits at hit, one rtcOccluded1 per needed ray.
  std::uint32_t lightMask(const SurfaceHit& hit, RayCounts& counts) const;
  WhittedWeights weights(const SurfaceHit& hit) const;
  /// S and T of the Whitted sum at `hit` (depth = bounces so far, throughput = product of weights so
  /// far), already multiplied by wR and wT; zero where the ray is not traced.
  void secondary(const SurfaceHit& hit, int depth, float throughput, glm::vec3& reflected, glm::vec3& transmitted,
                 bool& tracedReflection, bool& tracedRefraction, RayCounts& counts) const;
  /// Full colour of a hit: local (shadows by rays when asked) + wR·S + wT·T.
  glm::vec3 shade(const SurfaceHit& hit, int depth, float throughput, RayCounts& counts) const;
  /// Radiance arriving along a ray: the shaded nearest hit, or the background.
  glm::vec3 radiance(glm::vec3 originW, glm::vec3 dirW, int depth, float throughput, RayCounts& counts) const;
  /// Nearest hit of a ray in (tNear, tFar); false when it escapes or the ray is not finite.
  bool intersect(glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, std::uint32_t& instance,
                 std::uint32_t& triangle) const;

  const TraceModes& modes() const { return modes_; }

 private:
  const Scene& scene_;
  const EmbreeScene& embree_;
  const FrameShading& frame_;
  TraceModes modes_;
};

/// Fills an Embree ray; false (and nothing to trace) when any component is NaN or infinite, which
/// Debian's Embree does not filter out.
bool makeEmbreeRay(RTCRay& ray, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar);

}  // namespace tandem::rt
