#pragma once
// The CPU side of docs/shading.md: turning (instance, triangle, ray) into a surface point and shading its
// local term with the formulas of shaders/shading.glsl (through core/Shading.h). No Embree here: the
// exact primary hit and local shading need only the scene data, so tests and the CPU composite use them too.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "core/Environment.h"
#include "core/Radiosity.h"
#include "core/RenderSpace.h"
#include "core/ResolvedPixel.h"
#include "core/Shading.h"
#include "rt/RayMath.h"
#include "tandem/Camera.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::rt {

// Camera-relative rendering: core/RenderSpace.h (toRenderSpace, renderAnchor), shared with the GL passes.

/// Camera::rayThroughPixel with its per-camera work (the basis, tan of the half field of view, the
/// aspect) done once instead of per pixel; the per-pixel arithmetic is the same expression, so the rays
/// are bit-identical to Camera::rayThroughPixel's (tests/rt hold it to that).
class CameraRays {
 public:
  CameraRays(const Camera& camera, glm::ivec2 size);
  /// The camera's sub-pixel jitter, which through() adds to every point.
  glm::vec2 jitter() const { return jitter_; }
  Ray through(glm::vec2 pixel) const {
    pixel += jitter_;
    float nx = pixel.x / sizeX_ * 2.0f - 1.0f;
    float ny = 1.0f - pixel.y / sizeY_ * 2.0f;
    Ray r;
    if (orthographic_) {
      r.origin = pos_ + right_ * (nx * halfH_ * aspect_) + up_ * (ny * halfH_);
      r.dir = forward_;
      return r;
    }
    r.origin = pos_;
    r.dir = glm::normalize(forward_ + right_ * (nx * tanHalf_ * aspect_) + up_ * (ny * tanHalf_));
    return r;
  }
  /// Whether the camera is a thin lens (Camera::aperture, perspective).
  bool hasLens() const { return lensRadius_ > 0.0f; }
  /// The camera's own lens point (Camera::lensUv).
  glm::vec2 lensUv() const { return lensUv_; }
  /// The frame's shutter time (Camera::timeU), the time of its camera rays.
  float time() const { return time_; }
  /// The thin lens's ray through `pixel` from lens point `lensU` ([0, 1)², squareToDisk): from that point
  /// of the lens to where the lens centre's ray meets the plane in focus. Without a lens, through(pixel).
  Ray throughLens(glm::vec2 pixel, glm::vec2 lensU) const;

 private:
  glm::vec3 pos_, forward_, right_, up_;
  glm::vec2 jitter_;
  float sizeX_, sizeY_, aspect_, tanHalf_, halfH_;
  bool orthographic_;
  float lensRadius_ = 0.0f, focus_ = 0.0f;
  glm::vec2 lensUv_{0.5f};
  float time_ = 0.5f;
};

/// The [tNear, tFar] span of a camera ray that the rasterizer keeps (between its near and far planes).
inline void cameraSpan(const Camera& camera, const Ray& ray, float& tNear, float& tFar) {
  glm::vec3 forward = glm::normalize(camera.targetW - camera.posW);
  float cosine = camera.orthographic ? 1.0f : std::max(glm::dot(ray.dir, forward), 1e-6f);
  tNear = camera.nearZ / cosine;
  tFar = std::isinf(camera.farZ) ? std::numeric_limits<float>::infinity() : camera.farZ / cosine;
}

/// Where in pixel (x, y) the reference frame's sample (sx, sy) of spp × spp lies: one sample per stratum,
/// jittered by a hash of (pixel, sample), so no RNG state is shared; with one sample, the pixel centre
/// (the point the hybrid pass sees).
inline glm::vec2 referenceSampleOffset(int x, int y, int sx, int sy, int spp) {
  if (spp <= 1) return glm::vec2(0.5f);
  auto sample = static_cast<std::uint32_t>(sy * spp + sx);
  auto ux = static_cast<std::uint32_t>(x), uy = static_cast<std::uint32_t>(y);
  return (glm::vec2(sx, sy) + glm::vec2(random01(ux, uy, sample, 0), random01(ux, uy, sample, 1))) /
         static_cast<float>(spp);
}

/// The point to pass to CameraRays::through for the reference frame's sample (sx, sy) of pixel (x, y) under
/// the camera's `jitter` (which through() adds): the stratified offset moved by the jitter and wrapped into
/// the pixel, so a jittered frame's spp × spp samples still cover this pixel once each (a box filter) and an
/// accumulation of jittered frames places new points instead of spilling into the neighbours.
inline glm::vec2 referenceSamplePoint(int x, int y, int sx, int sy, int spp, glm::vec2 jitter) {
  const glm::vec2 moved = referenceSampleOffset(x, y, sx, sy, spp) + jitter;
  return glm::vec2(x, y) + (moved - glm::floor(moved)) - jitter;
}

/// The reference frame's camera ray for sample (sx, sy) of pixel (x, y): through referenceSamplePoint and, with
/// a lens, from a lens point of its own (hashed per pixel and sample, moved by the camera's lensUv so the
/// frames of an accumulation draw new ones); with one sample, from the camera's own lens point, as the
/// hybrid frame's Camera::lensPinhole sees.
inline Ray referenceRay(const CameraRays& rays, int x, int y, int sx, int sy, int spp) {
  const glm::vec2 pixel = referenceSamplePoint(x, y, sx, sy, spp, rays.jitter());
  if (!rays.hasLens()) return rays.through(pixel);
  if (spp <= 1) return rays.throughLens(pixel, rays.lensUv());
  const auto sample = static_cast<std::uint32_t>(sy * spp + sx);
  const auto ux = static_cast<std::uint32_t>(x), uy = static_cast<std::uint32_t>(y);
  const glm::vec2 u = glm::vec2(random01(ux, uy, sample, 2), random01(ux, uy, sample, 3)) + rays.lensUv();
  return rays.throughLens(pixel, u - glm::floor(u));
}

/// The reference frame's shutter time for sample (sx, sy) of pixel (x, y): hashed per pixel and sample, moved
/// by the camera's timeU (so accumulated frames draw new ones); with one sample, the camera's own timeU, the
/// hybrid frame's. In [0, 1).
inline float referenceTime(const Camera& camera, int x, int y, int sx, int sy, int spp) {
  const float own = std::clamp(std::isfinite(camera.timeU) ? camera.timeU : 0.5f, 0.0f, 1.0f);
  if (spp <= 1 || !(camera.shutter > 0.0f)) return own;
  const auto sample = static_cast<std::uint32_t>(sy * spp + sx);
  const float t = random01(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), sample, 4) + own;
  return t - std::floor(t);
}

/// An instance's transforms as the ray pass uses them (the same copy Embree was given), in render space.
struct InstanceTransform {
  glm::mat4 worldFromObject{1.0f};
  glm::mat3 normalWorldFromObject{1.0f};  // inverse transpose of the upper 3x3
  // |upper 3x3| and |translation| of worldFromObject: every hit's error bound (resolveHit) needs them,
  // so they are made once per transform rather than once per hit.
  glm::mat3 absLinear{1.0f};
  glm::vec3 absTranslation{0.0f};
  glm::vec3 anchor{0.0f};  // render space's origin in world space: world-space patterns are evaluated at posW + anchor
};
/// `worldFromObject` in world space, brought to render space. A transform already in render space (a motion
/// step) takes anchor 0 and gets its `anchor` field set after.
InstanceTransform makeInstanceTransform(const glm::mat4& worldFromObject, glm::vec3 anchor = glm::vec3(0.0f));

/// A point's area-light samples: `count` a light, sample k being point base + k of the point's sequence
/// (base = the accumulation's sample index · count: the frames of an accumulation, Camera::sampleIndex, draw
/// new points of one stratified sequence).
struct LightSampling {
  int count = 1;
  std::uint32_t base = 0;
};

/// Per-frame shading records: lights and materials packed as GL packs them (override applied), toon
/// ramps baked, Ia. Built once per frame, read by every thread.
struct FrameShading {
  std::vector<shading::GpuLight> lights;  // Scene::directLights() order: index j = light-mask bit j
  std::vector<shading::GpuMaterial> materials;
  std::vector<std::array<float, TD_TOON_RAMP_SIZE>> toonRamps;
  glm::vec3 ambient{0.0f};     // Ia
  /// The radiosity solution, which replaces the ambient term where it covers a surface: shadeLocal adds C·H
  /// there instead of ka·Ia, at every hit, primary and secondary (docs/radiosity.md). Null: none.
  const RadiosityField* radiosity = nullptr;
  /// What escaped rays see (radiance(dir)) and the environment's share of the ambient term (ambient(N)).
  EnvironmentLookup environment;
  int areaLights = 0;          // area lights among `lights` (GpuLight::shapeU.w numbers them)
  /// Area-light samples per point this frame at the primary hits (FrameSettings::lightSamples) and at the
  /// hits past them, the light the spatiotemporal filter leaves as drawn (unfilteredLightSamples()).
  LightSampling primaryLight, deeperLight;
  /// The sampling at a hit `depth` bounces past the camera's ray.
  const LightSampling& lightAt(int depth) const { return depth == 0 ? primaryLight : deeperLight; }
  /// Glossy rays per primary hit this frame (FrameSettings::glossSamples) and their sequence index's start
  /// (sampleIndex · glossSamples), as for the light samples.
  int glossSamples = 1;
  std::uint32_t glossBase = 0;
  /// Light positions in render space (see toRenderSpace).
  FrameShading(const Scene& scene, std::optional<ShadingModel> shadingOverride, glm::vec3 anchor = glm::vec3(0.0f));
  /// Sets primaryLight and deeperLight for a frame drawing `primary` and `deeper` area-light samples per
  /// point, its accumulation sample `sampleIndex` (Camera::sampleIndex).
  void setLightSampling(int primary, int deeper, std::uint32_t sampleIndex);
  /// Sets glossSamples and glossBase likewise.
  void setGlossSampling(int samples, std::uint32_t sampleIndex);
  /// Material m's roughness (Material::roughness; 0: mirror reflection and sharp refraction).
  std::vector<float> roughness;
  /// A frame's shading records as the ray passes use them: the settings' override, their area-light and
  /// glossy sampling at the camera's `sampleIndex`, and what stands for diffuse interreflection: the
  /// radiosity solution when given (not with gi = Path), or nothing at all for the path tracer (its paths
  /// are the interreflection), or the ambient term.
  static FrameShading forFrame(const Scene& scene, const FrameSettings& settings, std::uint32_t sampleIndex,
                               glm::vec3 anchor, const RadiosityField* radiosity);
  bool castsShadows(std::size_t light) const { return lights[light].radiance.w > 0.5f; }
  int lightType(std::size_t light) const { return static_cast<int>(lights[light].posType.w + 0.5f); }
  bool isArea(std::size_t light) const { return shading::tdIsAreaLight(lightType(light)); }
  int areaSlot(std::size_t light) const { return static_cast<int>(lights[light].shapeU.w + 0.5f); }
};

/// Phong-lobe exponent of a roughness: glTF's α = roughness², e = 2/α² − 2 (Walter et al. 2007, the
/// Beckmann ↔ Phong match); infinite (a mirror) at 0.
float glossExponent(float roughness);

/// A direction of the glossy lobe of `roughness` around the unit `axis` (the mirror or refracted direction)
/// for the point u of the unit square: cos θ = u.x^(1/(e+1)) (importance sampled: every sample weighs 1/N),
/// φ = 2π·u.y. A direction on the wrong side of the facet (dot with `side`, ±geomNormalW, not > 0) is
/// mirrored across it, so the lobe's energy stays on its side. At roughness 0, `axis` itself.
glm::vec3 glossyDirection(glm::vec3 axis, float roughness, glm::vec2 u, glm::vec3 side);

/// The sample streams glossy rays draw from (tdLightSampleU's light argument, clear of the lights' 0..7).
inline constexpr int kGlossReflectStream = 16, kGlossRefractStream = 17;

/// The sample-visibility bits of a point's area lights: word a (an area slot, GpuLight::shapeU.w) has bit k
/// set where sample k of that light is unoccluded.
using AreaSampleBits = std::array<std::uint32_t, kMaxLights>;

/// What a point's shadow rays read (Whitted's shadow rays, SpawnOrigins, the hybrid shadows' classify): the
/// leading part of every SurfaceHit, and all the ray pass keeps of a primary hit that spawns no reflection or
/// refraction ray (resolvePrimaryPoint), so most pixels never fill a whole SurfaceHit.
struct ShadowPoint {
  std::uint32_t instance = 0;
  std::uint32_t triangle = 0;
  std::uint32_t material = 0;
  /// Seed of the point's area-light samples (tdLightSampleU): resolveHit makes it from the point itself
  /// (secondary hits); a primary hit gets its pixel's (tdPixelSeed), which the shade pass can make too.
  std::uint32_t lightSeed = 0;
  /// When within the shutter the ray that found it ran (Camera::timeU; 0.5 without motion blur): the rays
  /// it spawns run then too, and a moving instance is where that time puts it (EmbreeScene::transformAt).
  float time = 0.5f;
  glm::vec3 posW{0.0f};              // b0·p0 + b1·p1 + b2·p2
  glm::vec3 posMagnitude{0.0f};      // bound of the magnitudes behind posW (offsetRayOrigin's error scale)
  glm::vec3 geomNormalW{0.0f, 1.0f, 0.0f};  // Ng, unit, flipped towards the viewer (two-sided lighting)
  glm::vec3 normalW{0.0f, 1.0f, 0.0f};      // N, unit, flipped with Ng
};

/// A surface point, from docs/shading.md "Inputs at a hit".
struct SurfaceHit : ShadowPoint {
  std::uint32_t vertex[3] = {0, 0, 0};
  glm::vec3 bary{1.0f, 0.0f, 0.0f};  // b0, b1, b2
  glm::vec3 vertexW[3];              // p0, p1, p2 in world space
  bool backFace = false;             // the ray arrived against the counter-clockwise front (Ng was flipped)
  glm::vec3 toEyeW{0.0f, 0.0f, 1.0f};       // V: unit, towards the ray origin
  glm::vec3 eyeW{0.0f};              // the ray origin (Gouraud's per-vertex V)
  glm::vec2 uv{0.0f};                // after uvTransform
  float pattern = 0.0f;              // the material's procedural texture at the point (tdPattern), in [0, 1]
  glm::vec3 tint{1.0f};              // texture × vertex colour
  glm::vec3 emissionTint{1.0f};      // emissive texture (sRGB-decoded), multiplies the emission
  float coverage = 1.0f;             // BLEND: tdCoverage of the kd texture's alpha; 1 otherwise
};

/// Sample k of area light `light` seen from `posW` for a point with `seed` drawing `sampling`: tdAreaLightSample
/// at sequence point sampling.base + k. The shadow rays and the shading of that sample both come from here.
inline glm::vec3 areaLightSample(const FrameShading& frame, const LightSampling& sampling, std::size_t light,
                                 std::uint32_t seed, glm::vec3 posW, int k, glm::vec3& toLight, float& dist) {
  const glm::vec2 u =
      shading::tdLightSampleU(seed, static_cast<int>(light), sampling.base + static_cast<std::uint32_t>(k));
  return shading::tdAreaLightSample(frame.lights[light], frame.lightType(light), posW, u, toLight, dist);
}

/// Exact hit of `ray` on triangle `triangle` of `instance`: watertight barycentrics (clamped onto the
/// triangle when the ray grazes past it), the position interpolated from the world-space vertices. An
/// instance whose mesh has an exact solid (Mesh::exact) is hit on the solid instead, at its first crossing
/// past `tNear` (the triangle, its raster proxy's, only where the ray passes by the solid).
SurfaceHit resolveHit(const Scene& scene, const InstanceTransform& transform, std::uint32_t instance,
                      std::uint32_t triangle, const Ray& ray, float tNear = 0.0f);

/// The exact primary hit of a hybrid frame's pixel from its visibility id (instance + 1, triangle) and its camera
/// ray: resolveHit on the triangle, or on the instance's exact solid from the camera's near plane on (where the
/// resolve step found it, RayTracer::resolveExact). `renderCamera` in render space, as the ray.
inline SurfaceHit resolvePrimary(const Scene& scene, const InstanceTransform& transform, const Camera& renderCamera,
                                 glm::uvec2 id, const Ray& ray) {
  const std::uint32_t instance = id.x - 1;
  float tNear = 0.0f, tFar = 0.0f;
  if (scene.meshes[scene.instances[instance].mesh].exact) cameraSpan(renderCamera, ray, tNear, tFar);
  return resolveHit(scene, transform, instance, id.y, ray, tNear);
}

/// A surface that neither reflects nor transmits (kr, kt <= 0 in its GpuMaterial's krKtIorModel) and is fully
/// covered has zero Whitted weights (whittedSum; tdTransmitWeight with a = 1): it spawns no reflection or
/// refraction ray. Wavefront::spawn skips such hits, and primaryNeedsWholeHit gives them the lean point.
inline bool spawnsNoRay(const glm::vec4& krKtIorModel, float coverage) {
  return !(krKtIorModel.x > 0.0f) && !(krKtIorModel.y > 0.0f) && coverage >= 1.0f;
}

/// Whether a primary hit on `instance` needs its whole SurfaceHit in the ray pass: its material may spawn
/// reflection or refraction rays (with `secondaryRays`: kr, kt > 0 in the frame's materials, or BLEND, whose
/// coverage may be below 1), or its normal or point comes from more than the triangle (an exact solid, a
/// normal map, a procedural bump). Otherwise resolvePrimaryPoint gives all the pass reads of it.
bool primaryNeedsWholeHit(const Scene& scene, const FrameShading& frame, std::uint32_t instance, bool secondaryRays);

/// The ShadowPoint of resolvePrimary's hit, to the bit, for an instance primaryNeedsWholeHit says false of:
/// the same vertices, barycentrics, position, error scale and normals, without the rest of the record.
ShadowPoint resolvePrimaryPoint(const Scene& scene, const InstanceTransform& transform, glm::uvec2 id, const Ray& ray);

/// The origin of a ray leaving `hit` towards the side of unit normal `side` (±geomNormalW): offset by the
/// hit's own rounding error (RayMath.h, the scale-aware offsetRayOrigin).
inline glm::vec3 spawnOrigin(const ShadowPoint& hit, glm::vec3 side) {
  return offsetRayOrigin(hit.posW, side, hit.posMagnitude);
}

/// Local shading (docs/shading.md "Local shading"): emission + ambient + Σj visj·Lj, where visj is bit j
/// of `visibleLights`; unlit materials give C + emission. An area light's Lj is the mean over the samples of
/// frame.lightAt(depth) (`depth`: bounces past the camera's ray), each counted where its bit in `areaSamples`
/// (by area slot) is set; without `areaSamples`, every sample of a visible area light counts (no shadows, or
/// none traced).
glm::vec3 shadeLocal(const Scene& scene, const FrameShading& frame, const InstanceTransform& transform,
                     const SurfaceHit& hit, std::uint32_t visibleLights, const AreaSampleBits* areaSamples = nullptr,
                     int depth = 0);

/// Bilinear sample of level 0 with repeat wrapping; sRGB texels are decoded before filtering, as GL's
/// sRGB textures do. Row 0 of the data is v = 0.
glm::vec4 sampleBilinear(const Texture& texture, glm::vec2 uv);

}  // namespace tandem::rt
