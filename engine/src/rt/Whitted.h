#pragma once
// Whitted recursion on Embree for one frame: shadow rays, mirror reflection, refraction with Fresnel.
// Read-only after construction, so any number of tiles trace through one instance concurrently.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "core/FrameRules.h"
#include "rt/EmbreeScene.h"
#include "rt/RayCapture.h"
#include "rt/RayMath.h"
#include "rt/ShadowCertainty.h"
#include "rt/SurfaceShading.h"
#include "tandem/FrameStats.h"
#include "tandem/Settings.h"

namespace tandem::rt {

/// Shadow rays stop this fraction short of a point light, so a light sitting on a surface (or an emitter's
/// own geometry around it) does not occlude itself; Embree promises nothing at exactly tfar.
inline constexpr float kShadowRayEnd = 1.0f - 1.0f / 4096.0f;

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
  /// Whether a hit at `depth` (bounces so far) may spawn reflection or refraction rays (Wavefront::spawn).
  bool spawnsAt(int depth) const { return depth < maxDepth && (reflections || refraction); }
  static TraceModes hybrid(const FrameSettings& s);
  static TraceModes reference(const FrameSettings& s);  // raster-made effects become rays
  static TraceModes from(const RayEffects& effects, const FrameSettings& s);
};

// whittedSum, mayReflect and mayTransmit: core/FrameRules.h (shared with the frame's plan).

/// The weights of the Whitted sum at a hit (docs/shading.md).
/// With coverage a (SurfaceHit::coverage, < 1 only for BLEND): reflect = a·wR and transmit =
/// tdTransmitWeight(a, wT, transmissionTint) = a·wT·tint + (1 − a).
/// Directions (docs/numerics.md, "Directions over the facet"): for a hit seen from in front of its facet
/// (Ng·V > 0) the reflected ray leaves over the facet (Ng·reflectDirW > 0) and the transmitted one
/// crosses it (Ng·refraction.dirW < 0), so a reflected ray always starts at the front offset origin and a
/// transmitted one at the back.
struct WhittedWeights {
  float reflect = 0.0f;          // a·wR
  glm::vec3 transmit{0.0f};      // tdTransmitWeight(a, wT, tint); wT = 0 on total internal reflection
  glm::vec3 reflectDirW{0.0f};   // the mirror direction about N, bent over the facet (tdReflectOverFacet)
  Refraction refraction;         // dirW: the refracted direction about N, bent through the facet
                                 // (tdRefractOverFacet), or straight through (−V) for a BLEND surface
                                 // that has no refracted ray of its own
  /// T is the uncovered part of a BLEND surface passing straight through (−V), not a refraction: it is
  /// never glossy.
  bool passThrough = false;
  /// The largest component of transmit: what the minContribution test and the throughput use.
  float transmitMax() const { return std::max(transmit.x, std::max(transmit.y, transmit.z)); }
};

/// Why no shadow ray was needed towards a light (Whitted::shadowRay tells a recorder). Each case but
/// MapSaysShadowed leaves the light's bit set; the passes only need the bit, PixelTrace names the case.
enum class NoShadowRay : std::uint8_t {
  None = 0,        // a ray is needed
  CastsNoShadows,  // the light's castShadows is off
  CannotReach,     // behind the surface, outside a spot cone or beyond range: it shades nothing here
  AtThePoint,      // a point light at the point itself: nothing can be between them
  NotFinite,       // the origin or direction is not finite: nothing Embree could trace
  MapSaysLit,      // hybrid shadows: the light-space map proves the ray would reach the light (bit set)
  MapSaysShadowed, // hybrid shadows: the map proves the ray would be blocked (bit clear)
};

/// A shadow ray ready for Embree, or none needed.
struct ShadowRay {
  bool needed = false;
  bool visibleWithoutRay = false;  // when !needed: the mask bit
  bool byMap = false;              // when !needed: the hybrid shadows' map answered (RayCounts::shadowByMap)
  glm::vec3 originW{0.0f};
  glm::vec3 dirW{0.0f};
  float tFar = 0.0f;
};

/// A hit's two possible ray origins (offset to the front or the back of its geometric normal), each
/// computed the first time a ray needs it: a hit's shadow rays mostly leave from the same side.
class SpawnOrigins {
 public:
  glm::vec3 towards(const ShadowPoint& hit, bool front) {
    int i = front ? 0 : 1;
    if (!made_[i]) {
      origin_[i] = spawnOrigin(hit, front ? hit.geomNormalW : -hit.geomNormalW);
      made_[i] = true;
    }
    return origin_[i];
  }

 private:
  glm::vec3 origin_[2];
  bool made_[2] = {false, false};
};

class Whitted;
class TileShafts;

/// What the Whitted recursion reports as it runs, in order, so that a recorder can rebuild the ray tree
/// of one pixel (rt/PixelTrace.h) or record every ray it traces (the bench's capture, rt/TileCapture.h).
/// The recursion takes the recorder as a template parameter: the passes instantiate it with NoRecorder,
/// whose members are empty and inline, so their loops compile to what they were without it (no call, no
/// branch); PixelTrace and the capture instantiate it with this interface.
///
/// Per ray: beginRay, then notTraced when Embree cannot be asked or embreeHit when it answers a hit, then
/// (on a hit) surface, a shadowRay or noShadowRay per light when the hit's shadows are by rays, local,
/// then either weights with a skipped or a nested ray per secondary kind, or noSecondaryRays; endRay
/// closes it. A miss goes straight from beginRay (or embreeHit) to endRay.
class RayRecorder {
 public:
  /// A ray about to be followed: its kind, its span, the weight its radiance gets in the sum of the hit
  /// it leaves (wR, or the wT vector) and the throughput of its path including that weight.
  virtual void beginRay(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar,
                        glm::vec3 weight, float throughput) = 0;
  /// Embree's nearest hit of the current ray.
  virtual void embreeHit(std::uint32_t instance, std::uint32_t triangle, float t) = 0;
  /// The current ray was not given to Embree (an origin or direction that is not finite): it escapes.
  virtual void notTraced() = 0;
  /// The surface point the current ray resolved to (the one it is shaded at).
  virtual void surface(const SurfaceHit& hit) = 0;
  /// Direct light `light` at the current hit needs no shadow ray, and why (its bit is set).
  virtual void noShadowRay(std::size_t light, NoShadowRay why) = 0;
  /// The shadow ray towards direct light `light` at the current hit, and Embree's answer.
  virtual void shadowRay(std::size_t light, const ShadowRay& ray, bool occluded) = 0;
  /// The local term at the current hit, shaded with `visibleLights`; `shadowRays` says whether the mask
  /// came from shadow rays (else every light counts as visible to the rays).
  virtual void local(const glm::vec3& color, std::uint32_t visibleLights, bool shadowRays) = 0;
  /// The weights of the current hit's Whitted sum, before its secondary rays are decided.
  virtual void weights(const WhittedWeights& w) = 0;
  /// A secondary ray of the current hit that is not traced; `weight` (wR or max wT) and the path's
  /// `throughput` are the numbers the decision was made on.
  virtual void skipped(RayKind kind, float weight, float throughput) = 0;
  /// The current hit spawns no secondary ray at all: the depth limit, or neither effect is by rays.
  virtual void noSecondaryRays(const Whitted& whitted, const SurfaceHit& hit) = 0;
  /// The current ray's radiance (shaded hit, or the background) and what it adds to its parent's sum
  /// (weight ⊙ radiance, the exact value the recursion adds).
  virtual void endRay(glm::vec3 radiance, glm::vec3 weighted) = 0;

 protected:
  ~RayRecorder() = default;  // not owned through this interface
};

/// The passes' recorder: nothing, inlined away. Passed by value, it is not even an argument (an empty
/// class takes no register), so the recursion's code is what it was without a recorder: GCC 12 -O3 emits
/// the same instructions for it as for the recursion before recorders existed. (Vectors the recursion
/// keeps using go by reference: local's colour by value made GCC keep it in other registers.)
struct NoRecorder {
  void beginRay(RayKind, glm::vec3, glm::vec3, float, float, glm::vec3, float) const {}
  void embreeHit(std::uint32_t, std::uint32_t, float) const {}
  void notTraced() const {}
  void surface(const SurfaceHit&) const {}
  void noShadowRay(std::size_t, NoShadowRay) const {}
  void shadowRay(std::size_t, const ShadowRay&, bool) const {}
  void local(const glm::vec3&, std::uint32_t, bool) const {}
  void weights(const WhittedWeights&) const {}
  void skipped(RayKind, float, float) const {}
  void noSecondaryRays(const Whitted&, const SurfaceHit&) const {}
  void endRay(glm::vec3, glm::vec3) const {}
};

/// PixelTrace's recorder: forwards each report to a RayRecorder (one pointer, passed by value).
class Recording {
 public:
  explicit Recording(RayRecorder& to) : to_(&to) {}
  void beginRay(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, glm::vec3 weight,
                float throughput) const {
    to_->beginRay(kind, originW, dirW, tNear, tFar, weight, throughput);
  }
  void embreeHit(std::uint32_t instance, std::uint32_t triangle, float t) const { to_->embreeHit(instance, triangle, t); }
  void notTraced() const { to_->notTraced(); }
  void surface(const SurfaceHit& hit) const { to_->surface(hit); }
  void noShadowRay(std::size_t light, NoShadowRay why) const { to_->noShadowRay(light, why); }
  void shadowRay(std::size_t light, const ShadowRay& ray, bool occluded) const { to_->shadowRay(light, ray, occluded); }
  void local(const glm::vec3& color, std::uint32_t visibleLights, bool shadowRays) const {
    to_->local(color, visibleLights, shadowRays);
  }
  void weights(const WhittedWeights& w) const { to_->weights(w); }
  void skipped(RayKind kind, float weight, float throughput) const { to_->skipped(kind, weight, throughput); }
  void noSecondaryRays(const Whitted& whitted, const SurfaceHit& hit) const { to_->noSecondaryRays(whitted, hit); }
  void endRay(glm::vec3 radiance, glm::vec3 weighted) const { to_->endRay(radiance, weighted); }

 private:
  RayRecorder* to_;
};

class Whitted {
 public:
  /// `shadowMaps` (hybrid shadows): answers the shadow rays it can prove, at every hit; null: all traced.
  Whitted(const Scene& scene, const EmbreeScene& embree, const FrameShading& frame, TraceModes modes,
          const ShadowCertainty* shadowMaps = nullptr, const TileShafts* shafts = nullptr)
      : scene_(scene), embree_(embree), frame_(frame), modes_(modes), shadowMaps_(shadowMaps), shafts_(shafts) {}

  /// The shadow ray from hit towards direct light j (or why none is needed); `origins` is shared by the
  /// calls for one hit, so its lights reuse the offset origins.
  ShadowRay shadowRay(const ShadowPoint& hit, std::size_t light, SpawnOrigins& origins) const {
    return shadowRay(hit, light, origins, NoRecorder{});
  }
  /// All direct lights' visibility bits at hit, one rtcOccluded1 per needed ray. An area light's bit is set
  /// where any of its samples (FrameShading::lightAt(depth)) is visible; `area` (when given) gets each area
  /// light's sample bits.
  std::uint32_t lightMask(const ShadowPoint& hit, RayCounts& counts, AreaSampleBits* area = nullptr,
                          int depth = 0) const {
    return lightMask(hit, counts, NoRecorder{}, area, depth);
  }
  /// The shadow ray from hit towards sample k of area light j drawing `sampling` (areaLightSample), or why
  /// none is needed. No map answers it: a shadow map from the light's centre proves nothing about its other
  /// points.
  template <class Recorder>
  ShadowRay areaShadowRay(const ShadowPoint& hit, std::size_t light, const LightSampling& sampling, int k,
                          SpawnOrigins& origins, Recorder rec) const;
  WhittedWeights weights(const SurfaceHit& hit) const;
  /// S and T of the Whitted sum at `hit` (depth = bounces so far, throughput = product of weights so
  /// far), already multiplied by wR and wT; zero where the ray is not traced.
  void secondary(const SurfaceHit& hit, int depth, float throughput, glm::vec3& reflected, glm::vec3& transmitted,
                 bool& tracedReflection, bool& tracedRefraction, RayCounts& counts) const {
    secondary(hit, depth, throughput, reflected, transmitted, tracedReflection, tracedRefraction, counts, NoRecorder{});
  }
  /// Full colour of a hit: local (shadows by rays when asked) + wR·S + wT·T.
  glm::vec3 shade(const SurfaceHit& hit, int depth, float throughput, RayCounts& counts) const {
    return shade(hit, depth, throughput, counts, NoRecorder{});
  }
  /// Radiance arriving along a ray: the shaded nearest hit, or the background.
  /// `time`: the ray's within the shutter (SurfaceHit::time).
  glm::vec3 radiance(glm::vec3 originW, glm::vec3 dirW, float time, int depth, float throughput, RayCounts& counts) const {
    return radiance(originW, dirW, time, depth, throughput, counts, NoRecorder{});
  }
  /// Nearest hit of a ray in (tNear, tFar) at shutter time `time`; false when it escapes or the ray is not finite.
  bool intersect(glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, std::uint32_t& instance,
                 std::uint32_t& triangle, float time = 0.5f) const {
    return intersect(originW, dirW, tNear, tFar, time, instance, triangle, NoRecorder{});
  }

  // The same, reporting to a recorder; instantiated for NoRecorder and Recording only.
  template <class Recorder>
  ShadowRay shadowRay(const ShadowPoint& hit, std::size_t light, SpawnOrigins& origins, Recorder rec) const;
  /// shadowRay in two steps, for a caller that may know the answer already (a ray kept from the last frame,
  /// rt/RayReuse.h): the ray or why none is needed, without asking the hybrid shadows' maps; then the maps'
  /// answer, when they have one (r.needed becomes false).
  template <class Recorder>
  ShadowRay shadowRayUnanswered(const ShadowPoint& hit, std::size_t light, SpawnOrigins& origins, Recorder rec) const;
  template <class Recorder>
  void answerByMap(const ShadowPoint& hit, std::size_t light, ShadowRay& r, Recorder rec) const;
  template <class Recorder>
  std::uint32_t lightMask(const ShadowPoint& hit, RayCounts& counts, Recorder rec, AreaSampleBits* area = nullptr,
                          int depth = 0) const;
  template <class Recorder>
  void secondary(const SurfaceHit& hit, int depth, float throughput, glm::vec3& reflected, glm::vec3& transmitted,
                 bool& tracedReflection, bool& tracedRefraction, RayCounts& counts, Recorder rec) const;
  template <class Recorder>
  glm::vec3 shade(const SurfaceHit& hit, int depth, float throughput, RayCounts& counts, Recorder rec) const;
  template <class Recorder>
  glm::vec3 radiance(glm::vec3 originW, glm::vec3 dirW, float time, int depth, float throughput, RayCounts& counts,
                     Recorder rec) const;
  template <class Recorder>
  bool intersect(glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, float time, std::uint32_t& instance,
                 std::uint32_t& triangle, Recorder rec) const;

  const TraceModes& modes() const { return modes_; }
  const Scene& scene() const { return scene_; }
  const EmbreeScene& embree() const { return embree_; }
  const FrameShading& frame() const { return frame_; }
  const ShadowCertainty* shadowMaps() const { return shadowMaps_; }
  /// Hybrid shadows' tile shafts for the batched passes (rt/TileShafts.h; ShadowBatch): null when off.
  const TileShafts* shafts() const { return shafts_; }
  /// Ray k of a hit's glossy reflection or refraction (stream kGlossReflectStream / kGlossRefractStream)
  /// around `axis`, on the side `side` of the facet: the frame's sample glossBase + k of the hit's seed;
  /// `axis` itself at roughness 0.
  glm::vec3 glossyRayDirection(const SurfaceHit& hit, glm::vec3 axis, float roughness, int stream, int k,
                               glm::vec3 side) const {
    if (!(roughness > 0.0f)) return axis;
    const glm::vec2 u = shading::tdLightSampleU(hit.lightSeed, stream, frame_.glossBase + static_cast<std::uint32_t>(k));
    return glossyDirection(axis, roughness, u, side);
  }
  /// Rays per glossy reflection or refraction at `depth` for material `material` (1 unless glossy and primary).
  int glossRays(std::uint32_t material, int depth) const {
    return frame_.roughness[material] > 0.0f && depth == 0 ? frame_.glossSamples : 1;
  }

 private:
  /// The shadow ray towards a light (or an area light's sample) whose radiance, direction and distance at
  /// the hit are e, toLight and dist (dist < 0: directional), or why none is needed.
  template <class Recorder>
  ShadowRay rayTowards(const ShadowPoint& hit, std::size_t light, glm::vec3 e, glm::vec3 toLight, float dist,
                       SpawnOrigins& origins, Recorder rec) const;
  template <class Recorder>
  ShadowRay noShadowRay(std::size_t light, NoShadowRay why, Recorder rec) const;

  const Scene& scene_;
  const EmbreeScene& embree_;
  const FrameShading& frame_;
  TraceModes modes_;
  const ShadowCertainty* shadowMaps_;
  const TileShafts* shafts_;
};

/// Fills an Embree ray; false (and nothing to trace) when any component is NaN or infinite, which
/// Debian's Embree does not filter out.
bool makeEmbreeRay(RTCRay& ray, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, float time);
/// A ray's time as Embree takes it: within [0, 1], 0.5 (mid-shutter) when not finite (makeEmbreeRay's).
inline float embreeTime(float time) { return std::clamp(std::isfinite(time) ? time : 0.5f, 0.0f, 1.0f); }

/// Packets of this many rays (rtcOccluded8 / rtcIntersect8): AVX2's width; 16-wide packets measured no
/// faster on this project's 2-core machine, which has AVX-512 (docs/bench.md).
inline constexpr int kPacket = 8;
/// Copies a ray made by makeEmbreeRay into lane k of a packet.
void setPacketLane(RTCRay8& packet, int k, const RTCRay& ray);

}  // namespace tandem::rt
