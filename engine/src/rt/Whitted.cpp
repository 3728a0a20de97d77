#include "rt/Whitted.h"

#include <cmath>
#include <limits>
#include <utility>

#include "rt/RayCapture.h"

namespace tandem::rt {

using namespace tandem::shading;

namespace {
// Shadow rays stop this fraction short of a point light, so a light sitting on a surface (or an
// emitter's own geometry around it) does not occlude itself; Embree promises nothing at exactly tfar.
constexpr float kShadowRayEnd = 1.0f - 1.0f / 4096.0f;
}  // namespace

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

bool makeEmbreeRay(RTCRay& ray, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar) {
  if (!isFinite(originW) || !isFinite(dirW) || std::isnan(tNear) || std::isnan(tFar) || !(tFar >= tNear)) return false;
  ray.org_x = originW.x;
  ray.org_y = originW.y;
  ray.org_z = originW.z;
  ray.tnear = tNear;
  ray.dir_x = dirW.x;
  ray.dir_y = dirW.y;
  ray.dir_z = dirW.z;
  ray.time = 0.0f;
  ray.tfar = tFar;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
  return true;
}

template <class Recorder>
ShadowRay Whitted::shadowRay(const SurfaceHit& hit, std::size_t light, SpawnOrigins& origins, Recorder rec) const {
  ShadowRay r;
  const GpuLight& l = frame_.lights[light];
  if (!frame_.castsShadows(light)) {
    r.visibleWithoutRay = true;
    rec.noShadowRay(light, NoShadowRay::CastsNoShadows);
    return r;
  }
  const GpuMaterial& m = frame_.materials[hit.material];
  bool flat = static_cast<int>(m.krKtIorModel.w + 0.5f) == TD_MODEL_FLAT;
  // The light is tested against the normal the model shades with, as in the shading formula.
  glm::vec3 n = flat ? hit.geomNormalW : hit.normalW;
  glm::vec3 toLight;
  float dist;
  glm::vec3 e = tdLightIncident(l, hit.posW, toLight, dist);
  if (!tdLightReaches(e, toLight, n)) {
    r.visibleWithoutRay = true;
    rec.noShadowRay(light, NoShadowRay::CannotReach);
    return r;
  }
  // Leave from the side of the geometric surface the ray goes to (W&B offset, never a fixed epsilon).
  r.originW = origins.towards(hit, glm::dot(toLight, hit.geomNormalW) >= 0.0f);
  if (dist < 0.0f) {  // directional
    r.dirW = toLight;
    r.tFar = std::numeric_limits<float>::infinity();
  } else {
    if (!(dist > 0.0f) || !std::isfinite(dist)) {
      r.visibleWithoutRay = true;  // the light sits on the point: nothing can be between them
      rec.noShadowRay(light, NoShadowRay::AtThePoint);
      return r;
    }
    // The direction and distance from the hit itself (tdLightIncident's): the offset origin is a few
    // ULPs of the hit away, far inside the 1/4096 of the distance the ray stops short of the light.
    r.dirW = toLight;
    r.tFar = dist * kShadowRayEnd;
  }
  r.needed = isFinite(r.originW) && isFinite(r.dirW);
  r.visibleWithoutRay = !r.needed;
  if (!r.needed) rec.noShadowRay(light, NoShadowRay::NotFinite);
  return r;
}

template <class Recorder>
std::uint32_t Whitted::lightMask(const SurfaceHit& hit, RayCounts& counts, Recorder rec) const {
  std::uint32_t mask = 0;
  SpawnOrigins origins;
  for (std::size_t j = 0; j < frame_.lights.size(); ++j) {
    ShadowRay s = shadowRay(hit, j, origins, rec);
    if (!s.needed) {
      if (s.visibleWithoutRay) mask |= 1u << j;
      continue;
    }
    RTCRay ray;
    makeEmbreeRay(ray, s.originW, s.dirW, 0.0f, s.tFar);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    capture::record(RayKind::Shadow, s.originW, s.dirW, 0.0f, s.tFar);  // bench hook, no-op by default
    rtcOccluded1(embree_.top(), &ctx, &ray);
    ++counts.shadow;
    // Embree marks an occluded ray by tfar = -inf.
    if (ray.tfar >= 0.0f) mask |= 1u << j;
    capture::resolvePending(ray.tfar < 0.0f);
    rec.shadowRay(j, s, ray.tfar < 0.0f);
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
  if (modes_.reflections && w.reflect > 0.0f && throughput * w.reflect >= modes_.minContribution) {
    const glm::vec3 dir = w.reflectDirW, origin = spawnOrigin(hit, hit.geomNormalW);
    ++counts.reflection;
    // Bench hook: the ray radiance() traces next (intersect() stores its answer).
    capture::record(RayKind::Reflection, origin, dir, 0.0f, std::numeric_limits<float>::infinity());
    tracedReflection = true;
    rec.beginRay(RayKind::Reflection, origin, dir, 0.0f, std::numeric_limits<float>::infinity(),
                 glm::vec3(w.reflect), throughput * w.reflect);
    const glm::vec3 s = radiance(origin, dir, depth + 1, throughput * w.reflect, counts, rec);
    reflected = w.reflect * s;
    rec.endRay(s, reflected);
  } else {
    rec.skipped(RayKind::Reflection, w.reflect, throughput);
  }
  const float wT = w.transmitMax();
  if (modes_.refraction && wT > 0.0f && throughput * wT >= modes_.minContribution) {
    const glm::vec3 dir = w.refraction.dirW, origin = spawnOrigin(hit, -hit.geomNormalW);
    ++counts.refraction;
    capture::record(RayKind::Refraction, origin, dir, 0.0f, std::numeric_limits<float>::infinity());
    tracedRefraction = true;
    rec.beginRay(RayKind::Refraction, origin, dir, 0.0f, std::numeric_limits<float>::infinity(), w.transmit,
                 throughput * wT);
    const glm::vec3 t = radiance(origin, dir, depth + 1, throughput * wT, counts, rec);
    transmitted = w.transmit * t;
    rec.endRay(t, transmitted);
  } else {
    rec.skipped(RayKind::Refraction, wT, throughput);
  }
}

template <class Recorder>
glm::vec3 Whitted::shade(const SurfaceHit& hit, int depth, float throughput, RayCounts& counts, Recorder rec) const {
  bool shadowRays = depth == 0 ? modes_.primaryShadowRays : modes_.secondaryShadowRays;
  std::uint32_t mask = shadowRays ? lightMask(hit, counts, rec) : ~0u;
  glm::vec3 color = shadeLocal(scene_, frame_, embree_.transform(hit.instance), hit, mask);
  rec.local(color, mask, shadowRays);
  glm::vec3 reflected, transmitted;
  bool tracedR, tracedT;
  secondary(hit, depth, throughput, reflected, transmitted, tracedR, tracedT, counts, rec);
  return color + reflected + transmitted;
}

template <class Recorder>
bool Whitted::intersect(glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, std::uint32_t& instance,
                        std::uint32_t& triangle, Recorder rec) const {
  RTCRayHit rh;
  if (!makeEmbreeRay(rh.ray, originW, dirW, tNear, tFar)) {
    capture::resolvePending(false, false);
    return false;
  }
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(embree_.top(), &ctx, &rh);
  bool missed = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID;
  capture::resolvePending(!missed);  // bench hook: Embree's answer for the recorded ray
  if (missed) return false;
  instance = rh.hit.instID[0];
  triangle = rh.hit.primID;
  rec.embreeHit(instance, triangle, rh.ray.tfar);
  return embree_.hasTriangle(instance, triangle);
}

template <class Recorder>
glm::vec3 Whitted::radiance(glm::vec3 originW, glm::vec3 dirW, int depth, float throughput, RayCounts& counts,
                            Recorder rec) const {
  std::uint32_t instance, triangle;
  if (!intersect(originW, dirW, 0.0f, std::numeric_limits<float>::infinity(), instance, triangle, rec))
    return frame_.background;
  Ray ray{originW, dirW};
  SurfaceHit hit = resolveHit(scene_, embree_.transform(instance), instance, triangle, ray);
  rec.surface(hit);
  return shade(hit, depth, throughput, counts, rec);
}

// The passes' instantiation (no recorder) and PixelTrace's (through RayRecorder); no others.
template ShadowRay Whitted::shadowRay(const SurfaceHit&, std::size_t, SpawnOrigins&, NoRecorder) const;
template ShadowRay Whitted::shadowRay(const SurfaceHit&, std::size_t, SpawnOrigins&, Recording) const;
template std::uint32_t Whitted::lightMask(const SurfaceHit&, RayCounts&, NoRecorder) const;
template std::uint32_t Whitted::lightMask(const SurfaceHit&, RayCounts&, Recording) const;
template void Whitted::secondary(const SurfaceHit&, int, float, glm::vec3&, glm::vec3&, bool&, bool&, RayCounts&,
                                 NoRecorder) const;
template void Whitted::secondary(const SurfaceHit&, int, float, glm::vec3&, glm::vec3&, bool&, bool&, RayCounts&,
                                 Recording) const;
template glm::vec3 Whitted::shade(const SurfaceHit&, int, float, RayCounts&, NoRecorder) const;
template glm::vec3 Whitted::shade(const SurfaceHit&, int, float, RayCounts&, Recording) const;
template glm::vec3 Whitted::radiance(glm::vec3, glm::vec3, int, float, RayCounts&, NoRecorder) const;
template glm::vec3 Whitted::radiance(glm::vec3, glm::vec3, int, float, RayCounts&, Recording) const;
template bool Whitted::intersect(glm::vec3, glm::vec3, float, float, std::uint32_t&, std::uint32_t&,
                                 NoRecorder) const;
template bool Whitted::intersect(glm::vec3, glm::vec3, float, float, std::uint32_t&, std::uint32_t&,
                                 Recording) const;

void ShadowBatch::clear() {
  rays_.clear();
  slots_.clear();
  bits_.clear();
  captured_.clear();
}

std::uint32_t ShadowBatch::add(const Whitted& whitted, std::size_t lights, const SurfaceHit& hit, std::size_t slot) {
  std::uint32_t visible = 0;
  SpawnOrigins origins;
  for (std::size_t j = 0; j < lights; ++j) {
    ShadowRay s = whitted.shadowRay(hit, j, origins);
    if (!s.needed) {
      if (s.visibleWithoutRay) visible |= 1u << j;
      continue;
    }
    rays_.emplace_back();
    makeEmbreeRay(rays_.back(), s.originW, s.dirW, 0.0f, s.tFar);  // finite: shadowRay checked
    slots_.push_back(slot);
    bits_.push_back(1u << j);
    if (capture::active()) captured_.push_back(capture::recordDeferred(RayKind::Shadow, s.originW, s.dirW, 0.0f, s.tFar));
  }
  return visible;
}

void ShadowBatch::trace(RTCScene scene, std::uint32_t* masks, RayCounts& counts) {
  if (rays_.empty()) return;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  // Left incoherent on purpose: with RTC_INTERSECT_CONTEXT_FLAG_COHERENT, Debian's Embree 3.13.5
  // never returned from one tile's batch (tests/rt GlassSlab after the grazing-light scenes).
  rtcOccluded1M(scene, &ctx, rays_.data(), static_cast<unsigned>(rays_.size()), sizeof(RTCRay));
  counts.shadow += rays_.size();
  // Embree marks an occluded ray by tfar = -inf.
  for (std::size_t i = 0; i < rays_.size(); ++i)
    if (rays_[i].tfar >= 0.0f) masks[slots_[i]] |= bits_[i];
  for (std::size_t i = 0; i < captured_.size(); ++i) capture::setHit(RayKind::Shadow, captured_[i], rays_[i].tfar < 0.0f);
}

Wavefront::Wavefront(const Whitted& whitted, Buffers& buffers) : whitted_(whitted), b_(buffers) {
  b_.nodes.clear();
}

void Wavefront::addPrimary(const SurfaceHit& hit, std::size_t pixel, RayCounts& counts) {
  spawn(hit, 0, 1.0f, -1, pixel, counts);
}

// Whitted::secondary's decisions, queuing the rays instead of recursing into them.
void Wavefront::spawn(const SurfaceHit& hit, int depth, float throughput, std::int64_t parent, std::size_t pixel,
                      RayCounts& counts) {
  const TraceModes& modes = whitted_.modes();
  if (depth >= modes.maxDepth || (!modes.reflections && !modes.refraction)) return;
  WhittedWeights w = whitted_.weights(hit);
  auto queue = [&](RayKind kind, glm::vec3 dir, glm::vec3 weight, float weightMax) {
    // The sides of Whitted::secondary: reflection in front of the facet, transmission behind it.
    Buffers::Node& n = b_.nodes.emplace_back();
    n.origin = spawnOrigin(hit, kind == RayKind::Refraction ? -hit.geomNormalW : hit.geomNormalW);
    n.dir = dir;
    n.weight = weight;
    n.throughput = throughput * weightMax;
    n.parent = parent;
    n.pixel = pixel;
    n.refraction = kind == RayKind::Refraction;
    if (capture::active())
      n.captured = capture::recordDeferred(kind, n.origin, dir, 0.0f, std::numeric_limits<float>::infinity());
  };
  if (modes.reflections && w.reflect > 0.0f && throughput * w.reflect >= modes.minContribution) {
    ++counts.reflection;
    queue(RayKind::Reflection, w.reflectDirW, glm::vec3(w.reflect), w.reflect);
  }
  const float wT = w.transmitMax();
  if (modes.refraction && wT > 0.0f && throughput * wT >= modes.minContribution) {
    ++counts.refraction;
    queue(RayKind::Refraction, w.refraction.dirW, w.transmit, wT);
  }
}

void Wavefront::run(RayCounts& counts, glm::vec4* reflected, glm::vec4* transmitted) {
  const TraceModes& modes = whitted_.modes();
  const EmbreeScene& embree = whitted_.embree();
  const FrameShading& frame = whitted_.frame();
  const std::size_t lights = frame.lights.size();
  // Breadth first: the rays of depth d are nodes [begin, end); their hits append depth d + 1.
  std::size_t begin = 0;
  for (int depth = 1; begin < b_.nodes.size(); ++depth) {
    const std::size_t end = b_.nodes.size();
    b_.rays.clear();
    b_.rayNodes.clear();
    for (std::size_t i = begin; i < end; ++i) {
      Buffers::Node& n = b_.nodes[i];
      n.local = frame.background;  // until a hit says otherwise
      RTCRayHit rh;
      if (!makeEmbreeRay(rh.ray, n.origin, n.dir, 0.0f, std::numeric_limits<float>::infinity())) {
        if (capture::active()) capture::setHit(n.refraction ? RayKind::Refraction : RayKind::Reflection, n.captured, false, false);
        continue;
      }
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      b_.rays.push_back(rh);
      b_.rayNodes.push_back(i);
    }
    if (!b_.rays.empty()) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);  // incoherent, as for shadow rays (see ShadowBatch::trace)
      rtcIntersect1M(embree.top(), &ctx, b_.rays.data(), static_cast<unsigned>(b_.rays.size()), sizeof(RTCRayHit));
    }
    b_.hits.clear();
    b_.hitNodes.clear();
    for (std::size_t k = 0; k < b_.rays.size(); ++k) {
      const RTCRayHit& rh = b_.rays[k];
      Buffers::Node& n = b_.nodes[b_.rayNodes[k]];
      bool missed = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID;
      if (capture::active()) capture::setHit(n.refraction ? RayKind::Refraction : RayKind::Reflection, n.captured, !missed);
      if (missed || !embree.hasTriangle(rh.hit.instID[0], rh.hit.primID)) continue;
      n.hit = true;
      b_.hits.push_back(resolveHit(whitted_.scene(), embree.transform(rh.hit.instID[0]), rh.hit.instID[0], rh.hit.primID,
                                   Ray{n.origin, n.dir}));
      b_.hitNodes.push_back(b_.rayNodes[k]);
    }
    // Shadow rays of every hit of this depth (Whitted::shade: secondary hits use rays when asked).
    b_.masks.assign(b_.hits.size(), ~0u);
    if (modes.secondaryShadowRays) {
      b_.shadows.clear();
      for (std::size_t h = 0; h < b_.hits.size(); ++h) b_.masks[h] = b_.shadows.add(whitted_, lights, b_.hits[h], h);
      b_.shadows.trace(embree.top(), b_.masks.data(), counts);
    }
    for (std::size_t h = 0; h < b_.hits.size(); ++h) {
      const SurfaceHit& hit = b_.hits[h];
      std::size_t node = b_.hitNodes[h];
      b_.nodes[node].local = shadeLocal(whitted_.scene(), frame, embree.transform(hit.instance), hit, b_.masks[h]);
      spawn(hit, depth, b_.nodes[node].throughput, static_cast<std::int64_t>(node), b_.nodes[node].pixel, counts);
    }
    begin = end;
  }
  // Bottom up: children come after their parent, so walking back finishes every node's S and T before
  // its own sum, which is the recursion's expression: colour + wR·S + wT·T (background on a miss).
  for (std::size_t i = b_.nodes.size(); i-- > 0;) {
    const Buffers::Node& n = b_.nodes[i];
    glm::vec3 radiance = n.hit ? n.local + n.reflected + n.transmitted : n.local;
    glm::vec3 weighted = n.weight * radiance;
    if (n.parent >= 0) {
      Buffers::Node& p = b_.nodes[static_cast<std::size_t>(n.parent)];
      (n.refraction ? p.transmitted : p.reflected) = weighted;
    } else {
      (n.refraction ? transmitted : reflected)[n.pixel] = glm::vec4(weighted, 1.0f);
    }
  }
}

}  // namespace tandem::rt
