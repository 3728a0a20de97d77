#include "rt/PixelTrace.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <vector>

#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"
#include "rt/Whitted.h"

namespace tandem::rt {

namespace {

TraceRayKind traceKind(RayKind kind) {
  switch (kind) {
    case RayKind::Primary: return TraceRayKind::Primary;
    case RayKind::Shadow: return TraceRayKind::Shadow;
    case RayKind::Reflection: return TraceRayKind::Reflection;
    case RayKind::Refraction: return TraceRayKind::Refraction;
  }
  return TraceRayKind::Primary;
}

LightVisibility visibilityWithoutRay(NoShadowRay why) {
  switch (why) {
    case NoShadowRay::CastsNoShadows: return LightVisibility::CastsNoShadows;
    case NoShadowRay::CannotReach: return LightVisibility::CannotReach;
    case NoShadowRay::AtThePoint: return LightVisibility::AtThePoint;
    case NoShadowRay::MapSaysLit: return LightVisibility::MapSaysLit;
    case NoShadowRay::MapSaysShadowed: return LightVisibility::MapSaysShadowed;
    case NoShadowRay::NotFinite:
    case NoShadowRay::None: break;
  }
  return LightVisibility::NotFinite;
}

/// Builds the tree from the recursion's reports (RayRecorder's order): a stack of the rays being followed,
/// each a node of PixelTrace::nodes. Positions come in render space and are stored in world space.
class TreeRecorder final : public RayRecorder {
 public:
  TreeRecorder(PixelTrace& out, const Whitted& whitted) : out_(out), whitted_(whitted) {}

  void beginRay(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, glm::vec3 weight,
                float throughput) override {
    TraceNode n;
    n.kind = traceKind(kind);
    n.parent = stack_.empty() ? -1 : stack_.back();
    n.depth = n.parent < 0 ? 0 : node(n.parent).depth + 1;
    n.originW = world(originW);
    n.dirW = dirW;
    n.tNear = tNear;
    n.tFar = tFar;
    n.weight = weight;
    n.throughput = throughput;
    n.radiance = n.contribution = whitted_.frame().environment.radiance(dirW);  // until endRay says
    const int index = static_cast<int>(out_.nodes.size());
    out_.nodes.push_back(std::move(n));
    if (const int parent = out_.nodes.back().parent; parent >= 0) {
      TraceNode& p = node(parent);
      int& first = kind == RayKind::Refraction ? p.refractionChild : p.reflectionChild;
      if (first < 0) first = index;
      (kind == RayKind::Refraction ? p.refractionChildren : p.reflectionChildren).push_back(index);
      (kind == RayKind::Refraction ? p.refraction : p.reflection) = SecondaryRay::Traced;
    } else {
      out_.roots.push_back(index);
    }
    stack_.push_back(index);
  }

  void embreeHit(std::uint32_t, std::uint32_t, float t) override { current().t = t; }
  // A ray Embree could not be given escapes: the node stays a miss that brings the background.
  void notTraced() override {}

  void surface(const SurfaceHit& hit) override {
    TraceNode& n = current();
    n.hit = true;
    n.instance = hit.instance;
    n.triangle = hit.triangle;
    n.material = hit.material;
    n.positionW = world(hit.posW);
    n.geometricNormalW = hit.geomNormalW;
    n.shadingNormalW = hit.normalW;
    n.backFace = hit.backFace;
    n.barycentrics = glm::vec2(hit.bary.y, hit.bary.z);
    n.coverage = hit.coverage;
  }

  void noShadowRay(std::size_t light, NoShadowRay why) override {
    TraceLight l;
    l.light = static_cast<std::uint32_t>(light);
    l.visibility = visibilityWithoutRay(why);
    l.visible = why != NoShadowRay::MapSaysShadowed;  // every other reason leaves the bit set (Whitted::shadowRay)
    current().lights.push_back(l);
  }

  void shadowRay(std::size_t light, const ShadowRay& ray, bool occluded) override {
    TraceLight l;
    l.light = static_cast<std::uint32_t>(light);
    l.visibility = occluded ? LightVisibility::Occluded : LightVisibility::Unoccluded;
    l.visible = !occluded;
    l.originW = world(ray.originW);
    l.dirW = ray.dirW;
    l.tFar = ray.tFar;
    current().lights.push_back(l);
  }

  void local(const glm::vec3& color, std::uint32_t visibleLights, bool shadowRays) override {
    TraceNode& n = current();
    n.local = color;
    n.lightMask = visibleLights;
    if (shadowRays) return;
    // No shadow rays at this hit: every light is shaded as visible (the mask is all ones).
    for (std::size_t j = 0; j < whitted_.frame().lights.size(); ++j) {
      TraceLight l;
      l.light = static_cast<std::uint32_t>(j);
      l.visibility = LightVisibility::NotTraced;
      l.visible = (visibleLights >> j) & 1u;
      n.lights.push_back(l);
    }
  }

  void weights(const WhittedWeights& w) override {
    current().sumEvaluated = true;
    recordWeights(w);
  }

  void skipped(RayKind kind, float weight, float /*throughput: the node's own*/) override {
    const TraceModes& modes = whitted_.modes();
    const bool byRays = kind == RayKind::Refraction ? modes.refraction : modes.reflections;
    // The reasons in the order Whitted::secondary's condition tests them.
    SecondaryRay why = !byRays               ? SecondaryRay::NotByRays
                       : !(weight > 0.0f)    ? SecondaryRay::NoWeight
                                             : SecondaryRay::BelowMinContribution;
    (kind == RayKind::Refraction ? current().refraction : current().reflection) = why;
  }

  void noSecondaryRays(const Whitted& whitted, const SurfaceHit& hit) override {
    // The sum is not evaluated; its weights are still worth showing (a raster frame's glass, the last bounce).
    recordWeights(whitted.weights(hit));
    TraceNode& n = current();
    const TraceModes& modes = whitted.modes();
    n.reflection = modes.reflections ? SecondaryRay::DepthLimit : SecondaryRay::NotByRays;
    n.refraction = modes.refraction ? SecondaryRay::DepthLimit : SecondaryRay::NotByRays;
  }

  void endRay(glm::vec3 radiance, glm::vec3 weighted) override {
    TraceNode& n = current();
    n.radiance = radiance;
    n.contribution = weighted;
    // The parent's sum of this kind, from zero in the order the rays were traced (Whitted::secondary's).
    if (n.parent >= 0) (n.kind == TraceRayKind::Refraction ? node(n.parent).transmitted : node(n.parent).reflected) += weighted;
    stack_.pop_back();
  }

  /// The primary ray of a hybrid frame: its hit comes from the visibility buffer, not from Embree.
  void primaryHit(const SurfaceHit& hit, const Ray& ray) {
    current().t = glm::dot(hit.posW - ray.origin, ray.dir);
    surface(hit);
  }

 private:
  TraceNode& node(int i) { return out_.nodes[static_cast<std::size_t>(i)]; }
  TraceNode& current() {
    assert(!stack_.empty() && "a recorder event outside a ray");
    return node(stack_.back());
  }
  glm::vec3 world(glm::vec3 renderSpace) const { return renderSpace + whitted_.embree().anchor(); }
  void recordWeights(const WhittedWeights& w) {
    TraceNode& n = current();
    // Refraction's F is that of the refracted interface; a surface without kt has none.
    const bool transmits = whitted_.frame().materials[n.material].krKtIorModel.y > 0.0f;
    n.fresnel = transmits ? w.refraction.fresnel : 0.0f;
    n.totalInternal = transmits && w.refraction.totalInternal;
    n.reflectWeight = w.reflect;
    n.transmitWeight = w.transmit;
  }

  PixelTrace& out_;
  const Whitted& whitted_;
  std::vector<int> stack_;
};

/// The parts of the pixel's sum from its primary rays: the one ray's (hybrid, one sample), else the means
/// over the samples (the light mask is the first sample's).
void summarise(PixelTrace& trace) {
  if (trace.roots.empty()) return;
  trace.lightMask = trace.nodes[static_cast<std::size_t>(trace.roots.front())].lightMask;
  trace.local = trace.reflected = trace.transmitted = glm::vec3(0.0f);
  for (int root : trace.roots) {
    const TraceNode& primary = trace.nodes[static_cast<std::size_t>(root)];
    trace.local += primary.local;
    trace.reflected += primary.reflected;
    trace.transmitted += primary.transmitted;
  }
  if (trace.roots.size() == 1) return;
  const float n = static_cast<float>(trace.roots.size());
  trace.local /= n;
  trace.reflected /= n;
  trace.transmitted /= n;
}

}  // namespace

PixelTrace traceHybridPixel(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                            const FrameSettings& settings, const VisibilityBuffer& visibility, int gx, int gy,
                            const ShadowCertainty* shadowMaps, const RadiosityField* radiosity) {
  PixelTrace trace;
  const int scale = std::max(1, settings.rayScale);
  const int width = visibility.width, height = visibility.height;
  trace.width = width;
  trace.height = height;
  trace.rayScale = scale;
  trace.settings = settings;
  trace.rayPass = true;
  trace.gridX = gx;
  trace.gridY = gy;
  // RayTracer::trace's set-up and per-pixel steps, for this one pixel.
  const Camera cam = toRenderSpace(camera, embree.anchor());
  const FrameShading frame = FrameShading::forFrame(scene, settings, camera.sampleIndex, embree.anchor(), radiosity);
  Whitted whitted(scene, embree, frame, TraceModes::hybrid(settings), shadowMaps);
  const CameraRays cameraRays(cam, {width, height});
  const glm::ivec2 p = fullPixelOfGridPixel(gx, gy, scale, width, height);
  trace.x = trace.tracedX = p.x;
  trace.y = trace.tracedY = p.y;
  const glm::uvec2 id = visibility.ids[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(p.x)];
  const Ray ray = cameraRays.through(glm::vec2(p) + 0.5f);
  TreeRecorder rec(trace, whitted);
  const Recording recorder(rec);  // the recursion's one recording instantiation
  rec.beginRay(RayKind::Primary, ray.origin, ray.dir, 0.0f, std::numeric_limits<float>::infinity(), glm::vec3(1.0f),
               1.0f);
  // Background (or an id not in the scene, which the pass skips too): no ray pass output, the sky.
  if (id.x == 0 || !embree.hasPrimary(id.x - 1, id.y)) {
    const glm::vec3 sky = frame.environment.radiance(ray.dir);
    rec.endRay(sky, sky);
    trace.color = sky;
    trace.lightMask = 0u;  // the pass writes 0 there
    return trace;
  }
  const std::uint32_t instance = id.x - 1;
  const float time = std::clamp(std::isfinite(camera.timeU) ? camera.timeU : 0.5f, 0.0f, 1.0f);
  SurfaceHit hit = resolvePrimary(scene, embree.transformAt(instance, time), cam, id, ray);
  hit.time = time;
  hit.lightSeed = shading::tdPixelSeed(p.x, p.y, 0u);  // the pass's seed for this pixel
  ++trace.rays.primary;
  rec.primaryHit(hit, ray);
  // Depth 0 of the recursion is the hybrid pass's primary hit: shadow rays when they are by rays, the local
  // term (the GL's, by its CPU twin), and the depth-0 secondary rays the wavefront follows.
  const glm::vec3 c = whitted.shade(hit, 0, 1.0f, trace.rays, recorder);
  rec.endRay(c, c);
  summarise(trace);
  trace.color = c;
  return trace;
}

PixelTrace traceReferencePixel(const Scene& scene, const EmbreeScene& embree, const Camera& camera,
                               const FrameSettings& settings, int x, int y, const RadiosityField* radiosity) {
  PixelTrace trace;
  const int width = settings.width, height = settings.height;
  trace.x = trace.gridX = trace.tracedX = x;
  trace.y = trace.gridY = trace.tracedY = y;
  trace.width = width;
  trace.height = height;
  trace.reference = true;
  trace.settings = settings;
  // RayTracer::renderReference's set-up and sample loop, for this one pixel.
  const Camera cam = toRenderSpace(camera, embree.anchor());
  const FrameShading frame = FrameShading::forFrame(scene, settings, camera.sampleIndex, embree.anchor(), radiosity);
  Whitted whitted(scene, embree, frame, TraceModes::reference(settings));
  const int spp = std::max(1, settings.referenceSpp);
  trace.samples = spp * spp;
  const CameraRays cameraRays(cam, {width, height});
  TreeRecorder rec(trace, whitted);
  const Recording recorder(rec);
  glm::vec3 sum(0.0f);
  for (int sy = 0; sy < spp; ++sy)
    for (int sx = 0; sx < spp; ++sx) {
      Ray ray = referenceRay(cameraRays, x, y, sx, sy, spp);
      const float time = referenceTime(camera, x, y, sx, sy, spp);
      float tNear, tFar;
      cameraSpan(cam, ray, tNear, tFar);
      ++trace.rays.primary;
      rec.beginRay(RayKind::Primary, ray.origin, ray.dir, tNear, tFar, glm::vec3(1.0f), 1.0f);
      // renderReference's sample: the camera ray within the camera's span, then the hit's full shading.
      std::uint32_t instance, triangle;
      glm::vec3 c = frame.environment.radiance(ray.dir);
      if (whitted.intersect(ray.origin, ray.dir, tNear, tFar, time, instance, triangle, recorder)) {
        SurfaceHit hit = resolveHit(scene, embree.transformAt(instance, time), instance, triangle, ray, tNear);
        hit.time = time;
        hit.lightSeed = shading::tdPixelSeed(x, y, static_cast<std::uint32_t>(sy * spp + sx));
        rec.surface(hit);
        c = whitted.shade(hit, 0, 1.0f, trace.rays, recorder);
      }
      rec.endRay(c, c);
      sum += c;
    }
  summarise(trace);
  trace.color = sum / static_cast<float>(spp * spp);
  return trace;
}

}  // namespace tandem::rt
