#include "rt/Whitted.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>


namespace tandem::rt {

using namespace tandem::shading;


TraceModes TraceModes::hybrid(const FrameSettings& s) { return from(hybridRayEffects(s), s); }

TraceModes TraceModes::reference(const FrameSettings& s) { return from(referenceRayEffects(s), s); }

TraceModes TraceModes::from(const RayEffects& e, const FrameSettings& s) {
  TraceModes m;
  m.primaryShadowRays = e.primaryShadows;
  m.secondaryShadowRays = e.secondaryShadows;
  m.reflections = e.reflections;
  m.refraction = e.refraction;
  m.maxDepth = s.maxDepth;
  m.minContribution = s.minContribution;
  m.fresnel = s.fresnel;
  m.fresnelWeighted = s.fresnelWeighted;
  return m;
}

bool makeEmbreeRay(RTCRay& ray, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, float time) {
  if (!isFinite(originW) || !isFinite(dirW) || std::isnan(tNear) || std::isnan(tFar) || !(tFar >= tNear)) return false;
  ray.org_x = originW.x;
  ray.org_y = originW.y;
  ray.org_z = originW.z;
  ray.tnear = tNear;
  ray.dir_x = dirW.x;
  ray.dir_y = dirW.y;
  ray.dir_z = dirW.z;
  ray.time = embreeTime(time);
  ray.tfar = tFar;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  return true;
}

void setPacketLane(RTCRay8& packet, int k, const RTCRay& ray) {
  packet.org_x[k] = ray.org_x;
  packet.org_y[k] = ray.org_y;
  packet.org_z[k] = ray.org_z;
  packet.tnear[k] = ray.tnear;
  packet.dir_x[k] = ray.dir_x;
  packet.dir_y[k] = ray.dir_y;
  packet.dir_z[k] = ray.dir_z;
  packet.time[k] = ray.time;
  packet.tfar[k] = ray.tfar;
  packet.mask[k] = ray.mask;
  packet.id[k] = ray.id;
  packet.flags[k] = ray.flags;
}

template <class Recorder>
ShadowRay Whitted::shadowRay(const ShadowPoint& hit, std::size_t light, SpawnOrigins& origins, Recorder rec) const {
  ShadowRay r = shadowRayUnanswered(hit, light, origins, rec);
  if (r.needed && shadowMaps_) answerByMap(hit, light, r, rec);
  return r;
}

template <class Recorder>
ShadowRay Whitted::shadowRayUnanswered(const ShadowPoint& hit, std::size_t light, SpawnOrigins& origins,
                                       Recorder rec) const {
  if (!frame_.castsShadows(light)) return noShadowRay(light, NoShadowRay::CastsNoShadows, rec);
  glm::vec3 toLight;
  float dist;
  const glm::vec3 e = tdLightIncident(frame_.lights[light], hit.posW, toLight, dist);
  return rayTowards(hit, light, e, toLight, dist, origins, rec);
}

template <class Recorder>
ShadowRay Whitted::areaShadowRay(const ShadowPoint& hit, std::size_t light, const LightSampling& sampling, int k,
                                 SpawnOrigins& origins, Recorder rec) const {
  if (!frame_.castsShadows(light)) return noShadowRay(light, NoShadowRay::CastsNoShadows, rec);
  glm::vec3 toLight;
  float dist;
  const glm::vec3 e = areaLightSample(frame_, sampling, light, hit.lightSeed, hit.posW, k, toLight, dist);
  return rayTowards(hit, light, e, toLight, dist, origins, rec);
}

template <class Recorder>
ShadowRay Whitted::noShadowRay(std::size_t light, NoShadowRay why, Recorder rec) const {
  ShadowRay r;
  r.visibleWithoutRay = true;
  rec.noShadowRay(light, why);
  return r;
}

template <class Recorder>
ShadowRay Whitted::rayTowards(const ShadowPoint& hit, std::size_t light, glm::vec3 e, glm::vec3 toLight, float dist,
                              SpawnOrigins& origins, Recorder rec) const {
  const GpuMaterial& m = frame_.materials[hit.material];
  bool flat = static_cast<int>(m.krKtIorModel.w + 0.5f) == TD_MODEL_FLAT;
  // The light is tested against the normal the model shades with, as in the shading formula.
  glm::vec3 n = flat ? hit.geomNormalW : hit.normalW;
  if (!tdLightReaches(e, toLight, n)) return noShadowRay(light, NoShadowRay::CannotReach, rec);
  // A distance that is not > 0 (NaN included) and not a directional light's -1: the light (or the area
  // light's sample) sits on the point, and nothing can be between them.
  if (!(dist < 0.0f) && (!(dist > 0.0f) || !std::isfinite(dist))) return noShadowRay(light, NoShadowRay::AtThePoint, rec);
  ShadowRay r;
  // Leave from the side of the geometric surface the ray goes to (W&B offset, never a fixed epsilon).
  r.originW = origins.towards(hit, glm::dot(toLight, hit.geomNormalW) >= 0.0f);
  // The direction and distance from the hit itself (tdLightIncident's): the offset origin is a few ULPs of
  // the hit away, far inside the 1/4096 of the distance the ray stops short of the light.
  r.dirW = toLight;
  r.tFar = dist < 0.0f ? std::numeric_limits<float>::infinity() : dist * kShadowRayEnd;  // < 0: directional
  r.needed = isFinite(r.originW) && isFinite(r.dirW);
  r.visibleWithoutRay = !r.needed;
  if (!r.needed) rec.noShadowRay(light, NoShadowRay::NotFinite);
  return r;
}

template <class Recorder>
void Whitted::answerByMap(const ShadowPoint& hit, std::size_t light, ShadowRay& r, Recorder rec) const {
  if (!shadowMaps_) return;
  // Hybrid shadows: an answer the map proves is the ray's own (rt/ShadowCertainty.h).
  ShadowAnswer answer = shadowMaps_->classify(light, hit, r.originW, r.dirW, r.tFar);
  if (answer == ShadowAnswer::Unknown) return;
  r.needed = false;
  r.byMap = true;
  r.visibleWithoutRay = answer == ShadowAnswer::Lit;
  rec.noShadowRay(light, r.visibleWithoutRay ? NoShadowRay::MapSaysLit : NoShadowRay::MapSaysShadowed);
}

template <class Recorder>
std::uint32_t Whitted::lightMask(const ShadowPoint& hit, RayCounts& counts, Recorder rec, AreaSampleBits* area,
                                 int depth) const {
  const LightSampling& sampling = frame_.lightAt(depth);
  std::uint32_t mask = 0;
  SpawnOrigins origins;
  auto occluded = [&](const ShadowRay& s) {
    RTCRay ray;
    makeEmbreeRay(ray, s.originW, s.dirW, 0.0f, s.tFar, hit.time);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1(embree_.top(), &ctx, &ray);
    ++counts.shadow;
    return ray.tfar < 0.0f;  // Embree marks an occluded ray by tfar = -inf
  };
  for (std::size_t j = 0; j < frame_.lights.size(); ++j) {
    if (frame_.isArea(j)) {
      std::uint32_t bits = 0;
      for (int k = 0; k < sampling.count; ++k) {
        ShadowRay s = areaShadowRay(hit, j, sampling, k, origins, rec);
        bool visible = s.visibleWithoutRay;
        if (s.needed) {
          visible = !occluded(s);
          rec.shadowRay(j, s, !visible);
        }
        if (visible) bits |= 1u << k;
      }
      if (bits != 0) mask |= 1u << j;
      if (area) (*area)[static_cast<std::size_t>(frame_.areaSlot(j))] = bits;
      continue;
    }
    ShadowRay s = shadowRay(hit, j, origins, rec);
    if (!s.needed) {
      if (s.visibleWithoutRay) mask |= 1u << j;
      if (s.byMap) ++counts.shadowByMap;
      continue;
    }
    const bool blocked = occluded(s);
    if (!blocked) mask |= 1u << j;
    rec.shadowRay(j, s, blocked);
  }
  return mask;
}

WhittedWeights Whitted::weights(const SurfaceHit& hit) const {
  WhittedWeights w;
  const GpuMaterial& m = frame_.materials[hit.material];
  float kr = m.krKtIorModel.x, kt = m.krKtIorModel.y, ior = m.krKtIorModel.z;
  if (kt > 0.0f) {
    // Inside/outside from the geometric normal: arriving at a back face means leaving the medium.
    float etaI = hit.backFace ? ior : 1.0f;
    float etaT = hit.backFace ? 1.0f : ior;
    w.refraction = refractDielectric(hit.toEyeW, hit.normalW, etaI, etaT, modes_.fresnel);
    // Snell about the shading normal can point back out of the facet at a silhouette: such a ray would
    // start behind the surface it was meant to cross.
    if (!w.refraction.totalInternal)
      w.refraction.dirW = tdRefractOverFacet(w.refraction.dirW, hit.toEyeW, hit.geomNormalW, etaI / etaT);
  }
  // The mirror about the shading normal can point into the object at a silhouette, where a closed mesh
  // would trap the ray until the depth limit.
  w.reflectDirW = tdReflectOverFacet(hit.toEyeW, hit.normalW, hit.geomNormalW);
  const SumWeights sum = whittedSum(kr, kt, w.refraction.fresnel, w.refraction.totalInternal, modes_.fresnelWeighted);
  const float wR = sum.reflect, wT = sum.transmit;
  // Coverage (docs/shading.md, BLEND): the covered fraction a shades and reflects, the rest 1 − a passes
  // straight through. Without a refracted ray of its own (kt = 0 or TIR) that part is T along −V, IOR 1.
  const float a = hit.coverage;
  if (a < 1.0f && (kt <= 0.0f || w.refraction.totalInternal)) {
    w.refraction.dirW = -hit.toEyeW;  // crosses the facet: Ng faces V
    w.refraction.totalInternal = false;
    w.passThrough = true;
  }
  w.reflect = a * wR;
  w.transmit = tdTransmitWeight(a, wT, scene_.materials[hit.material].transmissionTint);
  return w;
}

template <class Recorder>
void Whitted::secondary(const SurfaceHit& hit, int depth, float throughput, glm::vec3& reflected,
                        glm::vec3& transmitted, bool& tracedReflection, bool& tracedRefraction,
                        RayCounts& counts, Recorder rec) const {
  reflected = transmitted = glm::vec3(0.0f);
  tracedReflection = tracedRefraction = false;
  if (depth >= modes_.maxDepth || (!modes_.reflections && !modes_.refraction)) {
    rec.noSecondaryRays(*this, hit);
    return;
  }
  WhittedWeights w = weights(hit);
  rec.weights(w);
  // Reflected rays leave from the front of the facet and transmitted ones from its back: the directions
  // are on those sides by construction (WhittedWeights).
  // A glossy material (roughness > 0) samples its rays from the lobe around each direction: glossSamples of
  // them at the primary hit, one deeper (docs/glossy.md); each weighs 1/N of the sum.
  const float rough = frame_.roughness[hit.material];
  const int samples = glossRays(hit.material, depth);
  if (modes_.reflections && w.reflect > 0.0f && throughput * w.reflect >= modes_.minContribution) {
    const glm::vec3 origin = spawnOrigin(hit, hit.geomNormalW);
    const glm::vec3 weight(w.reflect / static_cast<float>(samples));
    tracedReflection = true;
    for (int k = 0; k < samples; ++k) {
      const glm::vec3 dir = glossyRayDirection(hit, w.reflectDirW, rough, kGlossReflectStream, k, hit.geomNormalW);
      ++counts.reflection;
      rec.beginRay(RayKind::Reflection, origin, dir, 0.0f, std::numeric_limits<float>::infinity(), weight,
                   throughput * w.reflect);
      const glm::vec3 s = radiance(origin, dir, hit.time, depth + 1, throughput * w.reflect, counts, rec);
      const glm::vec3 ws = weight * s;
      reflected += ws;
      rec.endRay(s, ws);
    }
  } else {
    rec.skipped(RayKind::Reflection, w.reflect, throughput);
  }
  const float wT = w.transmitMax();
  if (modes_.refraction && wT > 0.0f && throughput * wT >= modes_.minContribution) {
    const glm::vec3 origin = spawnOrigin(hit, -hit.geomNormalW);
    // Light passing an uncovered BLEND surface goes straight on: no lobe.
    const int rays = w.passThrough ? 1 : samples;
    const float lobe = w.passThrough ? 0.0f : rough;
    const glm::vec3 weight = w.transmit / static_cast<float>(rays);
    tracedRefraction = true;
    for (int k = 0; k < rays; ++k) {
      const glm::vec3 dir = glossyRayDirection(hit, w.refraction.dirW, lobe, kGlossRefractStream, k, -hit.geomNormalW);
      ++counts.refraction;
      rec.beginRay(RayKind::Refraction, origin, dir, 0.0f, std::numeric_limits<float>::infinity(), weight,
                   throughput * wT);
      const glm::vec3 t = radiance(origin, dir, hit.time, depth + 1, throughput * wT, counts, rec);
      const glm::vec3 wt = weight * t;
      transmitted += wt;
      rec.endRay(t, wt);
    }
  } else {
    rec.skipped(RayKind::Refraction, wT, throughput);
  }
}

template <class Recorder>
glm::vec3 Whitted::shade(const SurfaceHit& hit, int depth, float throughput, RayCounts& counts, Recorder rec) const {
  bool shadowRays = depth == 0 ? modes_.primaryShadowRays : modes_.secondaryShadowRays;
  AreaSampleBits area{};
  std::uint32_t mask = shadowRays ? lightMask(hit, counts, rec, &area, depth) : ~0u;
  glm::vec3 color = shadeLocal(scene_, frame_, embree_.transformAt(hit.instance, hit.time), hit, mask,
                               shadowRays ? &area : nullptr, depth);
  rec.local(color, mask, shadowRays);
  glm::vec3 reflected, transmitted;
  bool tracedR, tracedT;
  secondary(hit, depth, throughput, reflected, transmitted, tracedR, tracedT, counts, rec);
  return color + reflected + transmitted;
}

template <class Recorder>
bool Whitted::intersect(glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, float time,
                        std::uint32_t& instance, std::uint32_t& triangle, Recorder rec) const {
  RTCRayHit rh;
  if (!makeEmbreeRay(rh.ray, originW, dirW, tNear, tFar, time)) {
    rec.notTraced();
    return false;
  }
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(embree_.top(), &ctx, &rh);
  bool missed = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID;
  if (missed) return false;
  instance = rh.hit.instID[0];
  triangle = rh.hit.primID;
  rec.embreeHit(instance, triangle, rh.ray.tfar);
  return embree_.hasTriangle(instance, triangle);
}

template <class Recorder>
glm::vec3 Whitted::radiance(glm::vec3 originW, glm::vec3 dirW, float time, int depth, float throughput,
                            RayCounts& counts, Recorder rec) const {
  std::uint32_t instance, triangle;
  if (!intersect(originW, dirW, 0.0f, std::numeric_limits<float>::infinity(), time, instance, triangle, rec))
    return frame_.environment.radiance(dirW);
  Ray ray{originW, dirW};
  SurfaceHit hit = resolveHit(scene_, embree_.transformAt(instance, time), instance, triangle, ray);
  hit.time = time;
  rec.surface(hit);
  return shade(hit, depth, throughput, counts, rec);
}

// The passes' instantiation (no recorder) and PixelTrace's (through RayRecorder); no others.
template ShadowRay Whitted::shadowRay(const ShadowPoint&, std::size_t, SpawnOrigins&, NoRecorder) const;
template ShadowRay Whitted::shadowRay(const ShadowPoint&, std::size_t, SpawnOrigins&, Recording) const;
template ShadowRay Whitted::shadowRayUnanswered(const ShadowPoint&, std::size_t, SpawnOrigins&, NoRecorder) const;
template ShadowRay Whitted::shadowRayUnanswered(const ShadowPoint&, std::size_t, SpawnOrigins&, Recording) const;
template void Whitted::answerByMap(const ShadowPoint&, std::size_t, ShadowRay&, NoRecorder) const;
template void Whitted::answerByMap(const ShadowPoint&, std::size_t, ShadowRay&, Recording) const;
template std::uint32_t Whitted::lightMask(const ShadowPoint&, RayCounts&, NoRecorder, AreaSampleBits*, int) const;
template std::uint32_t Whitted::lightMask(const ShadowPoint&, RayCounts&, Recording, AreaSampleBits*, int) const;
template ShadowRay Whitted::areaShadowRay(const ShadowPoint&, std::size_t, const LightSampling&, int, SpawnOrigins&,
                                          NoRecorder) const;
template ShadowRay Whitted::areaShadowRay(const ShadowPoint&, std::size_t, const LightSampling&, int, SpawnOrigins&,
                                          Recording) const;
template void Whitted::secondary(const SurfaceHit&, int, float, glm::vec3&, glm::vec3&, bool&, bool&, RayCounts&,
                                 NoRecorder) const;
template void Whitted::secondary(const SurfaceHit&, int, float, glm::vec3&, glm::vec3&, bool&, bool&, RayCounts&,
                                 Recording) const;
template glm::vec3 Whitted::shade(const SurfaceHit&, int, float, RayCounts&, NoRecorder) const;
template glm::vec3 Whitted::shade(const SurfaceHit&, int, float, RayCounts&, Recording) const;
template glm::vec3 Whitted::radiance(glm::vec3, glm::vec3, float, int, float, RayCounts&, NoRecorder) const;
template glm::vec3 Whitted::radiance(glm::vec3, glm::vec3, float, int, float, RayCounts&, Recording) const;
template bool Whitted::intersect(glm::vec3, glm::vec3, float, float, float, std::uint32_t&, std::uint32_t&,
                                 NoRecorder) const;
template bool Whitted::intersect(glm::vec3, glm::vec3, float, float, float, std::uint32_t&, std::uint32_t&,
                                 Recording) const;

}  // namespace tandem::rt
