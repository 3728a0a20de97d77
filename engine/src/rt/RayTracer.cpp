#include "rt/RayTracer.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <chrono>
#include <thread>

#include "rt/EmbreeScene.h"
#include "rt/Parallel.h"
#include "rt/PathTracer.h"
#include "rt/PixelTrace.h"
#include "rt/RayMath.h"
#include "rt/RayReuse.h"
#include "rt/RayTracerState.h"
#include "rt/SurfaceShading.h"
#include "rt/TileCapture.h"
#include "rt/Wavefront.h"
#include "rt/Whitted.h"
#include "tandem/Log.h"

namespace tandem::rt {

namespace {

struct AtomicCounts {
  std::atomic<std::uint64_t> primary{0}, shadow{0}, reflection{0}, refraction{0}, shadowByMap{0}, shadowKept{0},
      shadowByShaft{0};
  void add(const RayCounts& c) {
    primary += c.primary;
    shadow += c.shadow;
    reflection += c.reflection;
    refraction += c.refraction;
    shadowByMap += c.shadowByMap;
    shadowKept += c.shadowKept;
    shadowByShaft += c.shadowByShaft;
  }
  RayCounts get() const {
    return {primary.load(),     shadow.load(),     reflection.load(),   refraction.load(),
            shadowByMap.load(), shadowKept.load(), shadowByShaft.load()};
  }
};

/// Counts the tiles of one pass and tells the progress callback, if any, as each finishes. Without a
/// callback it costs one branch per tile; with one, a relaxed atomic increment (the order of calls is
/// not promised, so nothing stronger is needed).
class TileProgress {
 public:
  TileProgress(const RayPassProgressCallback& callback, int width, int height)
      : callback_(callback ? &callback : nullptr),
        tiles_(static_cast<std::uint64_t>(tileCount(width)) * static_cast<std::uint64_t>(tileCount(height))) {}
  void tileDone() {
    if (callback_) (*callback_)({done_.fetch_add(1, std::memory_order_relaxed) + 1, tiles_});
  }

 private:
  const RayPassProgressCallback* callback_;
  std::uint64_t tiles_;
  std::atomic<std::uint64_t> done_{0};
};

}  // namespace

Result<std::unique_ptr<RayTracer>> RayTracer::create(int threads) {
  auto device = EmbreeDevice::create();
  if (!device) return device.error();
  auto impl = std::make_unique<RayTracerState>();
  impl->threads = threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#ifdef TANDEM_TSAN_THREADS
  // Embree's BVH builds run as TBB tasks in this arena (setScene, updateTransforms); with one slot they
  // stay on the calling thread, so TSan is not fed TBB hand-overs it cannot see (see parallelIndices).
  // The tile loops do not use the arena in this build: they run on impl->threads std::threads.
  impl->arena.initialize(1);
#else
  impl->arena.initialize(impl->threads);
#endif
  impl->device = std::move(*device);
  return std::unique_ptr<RayTracer>(new RayTracer(std::move(impl)));
}

RayTracer::RayTracer(std::unique_ptr<RayTracerState> impl) : impl_(std::move(impl)) {}
RayTracer::~RayTracer() {
  // Embree scenes before the device that made them.
  if (impl_) impl_->scene.reset();
}

int RayTracer::threads() const { return impl_->threads; }

std::size_t RayTracer::embreeBytes() const { return impl_->device ? impl_->device->bytesInUse() : 0; }
void RayTracer::setEmbreeMemoryLimit(std::size_t bytes) { impl_->device->setMemoryLimit(bytes); }
void RayTracer::setProgressCallback(RayPassProgressCallback progress) { impl_->progress = std::move(progress); }

Result<void> RayTracer::setScene(const Scene& scene, float shutter, std::optional<glm::vec3> anchor) {
  Result<std::unique_ptr<EmbreeScene>> built = Error{};
  // Inside the arena so Embree's TBB build uses the requested thread count.
  impl_->arena.execute([&] { built = EmbreeScene::build(*impl_->device, scene, shutter, anchor); });
  if (!built) {
    logError("ray pass: " + built.error().message);
    return built.error();
  }
  impl_->scene = std::move(*built);
  impl_->meshBounds = reuseMeshBounds(scene);
  impl_->planes.clear();
  for (const Mesh& mesh : scene.meshes) impl_->planes.push_back(axisPlane(mesh));
  impl_->shadowMaps.clear();  // of the old geometry
  impl_->shadowMapsStale = true;
  return {};
}

void RayTracer::updateTransforms(const Scene& scene, float shutter, std::optional<glm::vec3> anchor) {
  assert(impl_->scene && "updateTransforms before a successful setScene");
  if (!impl_->scene) return;
  impl_->arena.execute([&] { impl_->scene->updateTransforms(scene, shutter, anchor); });
  impl_->shadowMapsStale = true;
}

float RayTracer::shutter() const { return impl_->scene ? impl_->scene->shutter() : 0.0f; }
glm::vec3 RayTracer::anchor() const { return impl_->scene ? impl_->scene->anchor() : glm::vec3(0.0f); }

void RayTracer::trace(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                      const VisibilityBuffer& visibility, RayOutputs& out, const RayReuse* reuse,
                      std::span<const std::uint8_t> only) {
  assert((!reuse || (reuse->rays != &out && reuse->ids != &visibility)) && "trace: the kept frame is being written");
  assert((only.empty() || only.size() == visibility.ids.size()) && "trace: a selection of another frame size");
  hybridPass(scene, camera, settings, visibility, out, nullptr, true, reuse, only);
}

const ShadowCertainty& RayTracer::updateShadowMaps(const Scene& scene, const FrameShading& frame) {
  RayTracerState& s = *impl_;
  s.lastShadowMapMs = 0.0;
  if (s.shadowMapsStale || !s.shadowMaps.builtFor(frame)) {
    const auto start = std::chrono::steady_clock::now();
    s.arena.execute([&] { s.shadowMaps.build(scene, *s.scene, frame, s.threads); });
    s.lastShadowMapMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    s.shadowMapsStale = false;
    ++s.shadowMapBuilds;
  }
  return s.shadowMaps;
}

const ShadowCertainty* RayTracer::shadowMapsFor(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                                glm::vec3 glAnchor) {
  if (!impl_->scene || !settings.hybridShadows || impl_->scene->hasMotion() || impl_->scene->anchor() != glAnchor)
    return nullptr;
  const FrameShading frame = FrameShading::forFrame(scene, settings, camera.sampleIndex, impl_->scene->anchor(),
                                                    impl_->radiosity.get());
  const ShadowCertainty& maps = updateShadowMaps(scene, frame);
  return maps.empty() ? nullptr : &maps;
}

std::size_t RayTracer::shadowMapBuilds() const { return impl_->shadowMapBuilds; }
std::size_t RayTracer::shadowMapBytes() const { return impl_->shadowMaps.bytes(); }
double RayTracer::lastShadowMapMs() const { return impl_->lastShadowMapMs; }

void RayTracer::renderReference(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                                RayCounts& counts) {
  referencePass(scene, camera, settings, out, counts, nullptr);
}

namespace {

/// The capture policy of one tile (rt/TileCapture.h): nothing, or a recorder into the capture's tile.
template <class Capture>
struct TilePolicy;
template <>
struct TilePolicy<NoCapture> {
  static NoCapture make(RayCapture*, std::size_t) { return {}; }
};
template <>
struct TilePolicy<TileCapture> {
  static TileCapture make(RayCapture* capture, std::size_t tile) { return TileCapture(capture->tiles[tile]); }
};

void resetCapture(RayCapture* capture, int width, int height, bool primaryTraced) {
  if (!capture) return;
  capture->clear();
  capture->width = width;
  capture->height = height;
  capture->primaryTraced = primaryTraced;
  capture->tiles.resize(static_cast<std::size_t>(tileCount(width)) * static_cast<std::size_t>(tileCount(height)));
}

/// One tile of the hybrid pass: grid pixels [x0, x1) × [y0, y1).
template <class Capture>
struct HybridTiles {
  const Scene& scene;
  const EmbreeScene& embree;
  const FrameShading& frame;
  const Whitted& whitted;
  const Camera& camera;  // render space
  const CameraRays& cameraRays;
  const VisibilityBuffer& visibility;
  RayOutputs& out;
  int scale;
  bool batched;
  const ReuseGate& reuse;  // active only when batched
  std::span<const std::uint8_t> only;  // full-resolution pixels to trace (empty: all)
  std::span<const std::uint8_t> wholeHit;  // per instance: primaryNeedsWholeHit

  void run(int x0, int y0, int x1, int y1, Capture& capture, RayCounts& counts) const {
    const TraceModes& modes = whitted.modes();
    const int width = visibility.width, height = visibility.height, gw = out.width;
    // Per-thread scratch, kept from tile to tile so a tile allocates nothing once warm.
    thread_local ShadowBatch shadows;  // the tile's primary shadow rays, in packets per light
    thread_local Wavefront::Buffers wavefrontBuffers;
    // With reuse or tile shafts, the tile's primary hits are all resolved before any shadow ray is queued:
    // the moved bounds its kept shadow rays can meet are chosen once for the tile from where its hits lie
    // (ReuseTile), and the shafts are tested once for the box of its points (ShadowBatch::prepareShafts).
    // Without, each hit's shadow rays are queued as it is resolved. The queues get the same hits in the same
    // order; reflection and refraction rays are queued as each hit is resolved either way.
    struct Primary {
      std::size_t g, pixel;
      ShadowPoint point;
      bool samePoint;
    };
    thread_local std::vector<Primary> primaries;
    thread_local ReuseTile keptTile;
    shadows.clear();
    primaries.clear();
    Wavefront wavefront(whitted, wavefrontBuffers);
    const bool keeping = reuse.active() && batched && modes.primaryShadowRays;
    const bool gathering = keeping || (batched && modes.primaryShadowRays && whitted.shafts() != nullptr);
    auto queueShadows = [&](std::size_t g, std::size_t pixel, const ShadowPoint& hit, bool samePoint) {
      if (modes.primaryShadowRays) {
        ShadowKeep keep;
        if (samePoint) keep = {&reuse, &keptTile, reuse.keepableLights(), reuse.keptMask(g), g};
        const std::size_t plane = out.lightMask.size();
        std::uint32_t* area = out.areaLights > 0 ? out.areaSamples.data() + g : nullptr;
        if (batched) {
          out.lightMask[g] = static_cast<LightMask>(
              shadows.add(whitted, frame.lights.size(), hit, g, capture, samePoint ? &keep : nullptr, area, plane,
                          visibility.proofs.empty() ? 0u : visibility.proofs[pixel]));
        } else {
          AreaSampleBits bits{};
          out.lightMask[g] = static_cast<LightMask>(whitted.lightMask(hit, counts, capture.recorder(), &bits));
          for (int a = 0; a < out.areaLights; ++a) area[static_cast<std::size_t>(a) * plane] = bits[static_cast<std::size_t>(a)];
        }
      }
    };
    glm::dvec3 keptLo(std::numeric_limits<double>::infinity()), keptHi(-std::numeric_limits<double>::infinity());
    double keptOffsetScale = 0.0;  // the largest magnitude behind the kept hits' offset origins
    for (int gy = y0; gy < y1; ++gy)
      for (int gx = x0; gx < x1; ++gx) {
        std::size_t g = static_cast<std::size_t>(gy) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(gx);
        out.lightMask[g] = 0u;
        for (int a = 0; a < out.areaLights; ++a) out.areaSamples[static_cast<std::size_t>(a) * out.lightMask.size() + g] = 0u;
        out.reflected[g] = out.transmitted[g] = glm::vec4(0.0f);
        glm::ivec2 p = fullPixelOfGridPixel(gx, gy, scale, width, height);
        const std::size_t pixel = static_cast<std::size_t>(p.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(p.x);
        glm::uvec2 id = visibility.ids[pixel];
        if (id.x == 0) continue;  // background: no light, nothing reflected or transmitted
        if (!only.empty() && only[pixel] == 0) continue;  // not this round's: as the background
        std::uint32_t instance = id.x - 1;
        // Ids come from the rasterizer of the same scene (or its resolve step); a stale one is a bug, skipped
        // in release.
        assert(embree.hasPrimary(instance, id.y) && "trace: visibility id not in the scene");
        if (!embree.hasPrimary(instance, id.y)) continue;
        Ray ray = cameraRays.through(glm::vec2(p) + 0.5f);
        ++counts.primary;
        if constexpr (Capture::kRecords) capture.rasterPrimary(ray.origin, ray.dir);
        // The GL proved every light's bit and the hit spawns no ray (TD_PROOF_COMPLETE): the light mask is the
        // proof's, and there is nothing to resolve.
        if (modes.primaryShadowRays && !visibility.proofs.empty() && (visibility.proofs[pixel] & kProofComplete) != 0) {
          const std::uint32_t proof = visibility.proofs[pixel];
          out.lightMask[g] = static_cast<LightMask>(proof & 0xFFu);
          counts.shadowByMap += static_cast<std::uint64_t>(std::popcount((proof >> kProofNeededShift) & 0xFFu));
          continue;
        }
        // The rasterizer drew the instance where the frame's shutter time puts it (Camera::timeU). Most hits
        // spawn no reflection or refraction ray: their shadow rays need only the point (ShadowPoint), not
        // the whole record with its texture coordinates, tints and eye vectors.
        const InstanceTransform& transform = embree.transformAt(instance, cameraRays.time());
        const std::uint32_t seed = shading::tdPixelSeed(p.x, p.y, 0u);  // the shade pass draws these samples too
        ShadowPoint point;
        if (wholeHit[instance]) {
          SurfaceHit hit = resolvePrimary(scene, transform, camera, id, ray);
          hit.time = cameraRays.time();
          hit.lightSeed = seed;
          wavefront.addPrimary(hit, g, counts, capture);
          point = hit;
        } else {
          point = resolvePrimaryPoint(scene, transform, id, ray);
          point.time = cameraRays.time();
          point.lightSeed = seed;
        }
        if (!gathering) {
          queueShadows(g, pixel, point, false);
          continue;
        }
        const bool samePoint = keeping && reuse.samePoint(pixel, id);
        if (samePoint) {
          keptLo = glm::min(keptLo, glm::dvec3(point.posW));
          keptHi = glm::max(keptHi, glm::dvec3(point.posW));
          keptOffsetScale = std::max({keptOffsetScale, static_cast<double>(point.posMagnitude.x),
                                      static_cast<double>(point.posMagnitude.y), static_cast<double>(point.posMagnitude.z)});
        }
        primaries.push_back({g, pixel, point, samePoint});
      }
    if (gathering) {
      if (keeping) reuse.selectForTile(keptLo, keptHi, keptOffsetScale, keptTile);
      shadows.prepareShafts(whitted, primaries.size(), [&](std::size_t i) -> const ShadowPoint& { return primaries[i].point; });
      for (const Primary& pr : primaries) queueShadows(pr.g, pr.pixel, pr.point, pr.samePoint);
    }
    shadows.trace(embree.top(), out.lightMask.data(), counts, capture);
    wavefront.run(counts, out.reflected.data(), out.transmitted.data(), capture);
    const std::size_t tile = tileIndex(x0, y0, gw);
    out.reflectedTiles[tile] = anyBits(out.reflected, x0, y0, x1, y1);
    out.transmittedTiles[tile] = anyBits(out.transmitted, x0, y0, x1, y1);
  }

  // Whether any texel of the tile is not all +0 (a -0 counts: the upload must not change a bit).
  std::uint8_t anyBits(const std::vector<glm::vec4>& channel, int x0, int y0, int x1, int y1) const {
    std::uint32_t bits = 0;
    for (int gy = y0; gy < y1; ++gy)
      for (int gx = x0; gx < x1; ++gx) {
        const glm::vec4& v = channel[static_cast<std::size_t>(gy) * static_cast<std::size_t>(out.width) +
                                     static_cast<std::size_t>(gx)];
        bits |= std::bit_cast<std::uint32_t>(v.x) | std::bit_cast<std::uint32_t>(v.y) |
                std::bit_cast<std::uint32_t>(v.z) | std::bit_cast<std::uint32_t>(v.w);
      }
    return bits != 0 ? 1 : 0;
  }
};

}  // namespace

template <class Capture>
void RayTracer::hybridPassWith(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                               const VisibilityBuffer& visibility, RayOutputs& out, RayCapture* capture,
                               bool batchedShadowRays, const RayReuse* reuse,
                               std::span<const std::uint8_t> only) {
  const EmbreeScene& embree = *impl_->scene;
  // Camera-relative rendering (docs/numerics.md): rays and lights in the Embree scene's render space.
  const Camera cam = toRenderSpace(camera, embree.anchor());
  FrameShading frame = FrameShading::forFrame(scene, settings, camera.sampleIndex, embree.anchor(), impl_->radiosity.get());
  const TraceModes modes = TraceModes::hybrid(settings);
  const ShadowCertainty* shadowMaps =
      // The maps see the scene at one time: with motion blur every shadow ray runs at its own (docs/motion-blur.md).
      settings.hybridShadows && settings.shadowProofs != ShadowProofs::Shafts && !embree.hasMotion() &&
              (modes.primaryShadowRays || modes.secondaryShadowRays)
          ? &updateShadowMaps(scene, frame)
          : nullptr;
  const CameraRays cameraRays(cam, {visibility.width, visibility.height});
  // Hybrid shadows answer a tile's rays towards a light together where nothing can meet any of them (auto
  // and shafts; cpu and gl are the maps alone).
  TileShafts shafts;
  if (settings.hybridShadows && batchedShadowRays && (modes.primaryShadowRays || modes.secondaryShadowRays) &&
      (settings.shadowProofs == ShadowProofs::Auto || settings.shadowProofs == ShadowProofs::Shafts))
    shafts.build(scene, embree, impl_->meshBounds, impl_->planes, cameraRays.time());
  Whitted whitted(scene, embree, frame, modes, shadowMaps, shafts.active() ? &shafts : nullptr);
  const ReuseGate gate = reuse && batchedShadowRays && modes.primaryShadowRays
                             ? ReuseGate(*reuse, scene, embree, impl_->meshBounds, frame.lights,
                                         visibility.ids.size(), out.lightMask.size())
                             : ReuseGate();
  std::vector<std::uint8_t> wholeHit(scene.instances.size());
  for (std::size_t i = 0; i < wholeHit.size(); ++i)
    wholeHit[i] = primaryNeedsWholeHit(scene, frame, static_cast<std::uint32_t>(i), modes.spawnsAt(0));
  const HybridTiles<Capture> tiles{scene,     embree, frame, whitted, cam, cameraRays, visibility, out,
                                   std::max(1, settings.rayScale), batchedShadowRays, gate, only, wholeHit};
  AtomicCounts total;
  resetCapture(capture, out.width, out.height, false);
  TileProgress progress(impl_->progress, out.width, out.height);
  impl_->arena.execute([&] {
    forEachTile(impl_->threads, out.width, out.height, [&](int x0, int y0, int x1, int y1) {
      Capture tileCapture = TilePolicy<Capture>::make(capture, tileIndex(x0, y0, out.width));
      RayCounts counts;
      tiles.run(x0, y0, x1, y1, tileCapture, counts);
      total.add(counts);
      progress.tileDone();
    });
  });
  out.counts = total.get();
  // Cost follows the scene: an effect that traced no ray leaves its channel empty. The mask is the primary
  // points' only: with raster shadows, the shadow rays of secondary hits leave it to the shadow maps.
  // Kept answers count as the rays they stand for: the mask is cleared exactly when a frame without reuse
  // would clear it. A tile shaft's answers may include tests that needed no ray: a frame whose every light
  // is out of reach keeps an all-lit mask here where tracing clears it, which shades the same.
  if (out.counts.shadow + out.counts.shadowByMap + out.counts.shadowKept + out.counts.shadowByShaft == 0 ||
      !whitted.modes().primaryShadowRays) {
    out.lightMask.clear();
    out.areaSamples.clear();
    out.areaLights = 0;
    out.areaLightBits = 0;
  }
  if (out.counts.reflection == 0) out.reflected.clear(), out.reflectedTiles.clear();
  if (out.counts.refraction == 0) out.transmitted.clear(), out.transmittedTiles.clear();
}

void RayTracer::hybridPass(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                           const VisibilityBuffer& visibility, RayOutputs& out, RayCapture* capture,
                           bool batchedShadowRays, const RayReuse* reuse, std::span<const std::uint8_t> only) {
  assert(impl_->scene && "trace before a successful setScene");
  assert(visibility.ids.size() == static_cast<std::size_t>(visibility.width) * static_cast<std::size_t>(visibility.height));
  const int scale = std::max(1, settings.rayScale);
  out.width = gridSize(visibility.width, scale);
  out.height = gridSize(visibility.height, scale);
  out.threads = impl_->threads;
  out.counts = {};
  const std::size_t n = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
  // Sized here, filled by the tiles (every grid pixel is written there, in parallel): a serial
  // assign() of the ~30 MB of a 1280×720 frame would cost more than a few percent of the pass.
  out.lightMask.resize(n);
  out.areaLights = 0;
  out.areaLightBits = 0;
  if (TraceModes::hybrid(settings).primaryShadowRays) {
    const std::vector<const Light*> lights = scene.directLights();
    for (std::size_t j = 0; j < lights.size(); ++j)
      if (isAreaLight(lights[j]->type)) {
        ++out.areaLights;
        out.areaLightBits |= 1u << j;
      }
  }
  out.areaSamples.resize(static_cast<std::size_t>(out.areaLights) * n);
  out.reflected.resize(n);
  out.transmitted.resize(n);
  const std::size_t tiles = static_cast<std::size_t>(tileCount(out.width)) * static_cast<std::size_t>(tileCount(out.height));
  out.reflectedTiles.resize(tiles);
  out.transmittedTiles.resize(tiles);
  out.tileSize = kTile;
  if (!impl_->scene || n == 0) {
    out.lightMask.clear();
    out.areaSamples.clear();
    out.areaLights = 0;
    out.areaLightBits = 0;
    out.reflected.clear();
    out.transmitted.clear();
    out.reflectedTiles.clear();
    out.transmittedTiles.clear();
    return;
  }
  // One branch per frame: the frame's loops are compiled without any capture code.
  if (capture)
    hybridPassWith<TileCapture>(scene, camera, settings, visibility, out, capture, batchedShadowRays, reuse, only);
  else
    hybridPassWith<NoCapture>(scene, camera, settings, visibility, out, nullptr, batchedShadowRays, reuse, only);
}

template <class Capture>
void RayTracer::referencePassWith(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                  ImageF& out, RayCounts& counts, RayCapture* capture) {
  const int width = settings.width, height = settings.height;
  const EmbreeScene& embree = *impl_->scene;
  const Camera cam = toRenderSpace(camera, embree.anchor());  // camera-relative, as in trace()
  const FrameShading frame =
      FrameShading::forFrame(scene, settings, camera.sampleIndex, embree.anchor(), impl_->radiosity.get());
  const bool paths = settings.gi == GlobalIllumination::Path;
  Whitted whitted(scene, embree, frame, TraceModes::reference(settings));
  const PathTracer pathTracer(whitted);
  const int spp = std::max(1, settings.referenceSpp);
  const CameraRays cameraRays(cam, {width, height});
  AtomicCounts total;
  resetCapture(capture, width, height, true);
  TileProgress progress(impl_->progress, width, height);

  impl_->arena.execute([&] {
    forEachTile(impl_->threads, width, height, [&](int x0, int y0, int x1, int y1) {
      Capture tileCapture = TilePolicy<Capture>::make(capture, tileIndex(x0, y0, width));
      const auto rec = tileCapture.recorder();
      RayCounts c;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          glm::vec3 sum(0.0f);
          for (int sy = 0; sy < spp; ++sy)
            for (int sx = 0; sx < spp; ++sx) {
              Ray ray = referenceRay(cameraRays, x, y, sx, sy, spp);
              const float time = referenceTime(camera, x, y, sx, sy, spp);
              float tNear, tFar;
              cameraSpan(cam, ray, tNear, tFar);
              ++c.primary;
              rec.beginRay(RayKind::Primary, ray.origin, ray.dir, tNear, tFar, glm::vec3(1.0f), 1.0f);
              std::uint32_t instance, triangle;
              if (!whitted.intersect(ray.origin, ray.dir, tNear, tFar, time, instance, triangle, rec)) {
                sum += frame.environment.radiance(ray.dir);
                continue;
              }
              SurfaceHit hit = resolveHit(scene, embree.transformAt(instance, time), instance, triangle, ray, tNear);
              hit.time = time;
              // With one sample per pixel, the hybrid frame's seed: the same light samples as its pixel.
              hit.lightSeed = shading::tdPixelSeed(x, y, static_cast<std::uint32_t>(sy * spp + sx));
              // Accumulated frames draw new paths: the sample index runs on across frames.
              const std::uint32_t sample = camera.sampleIndex * static_cast<std::uint32_t>(spp * spp) +
                                           static_cast<std::uint32_t>(sy * spp + sx);
              sum += paths ? pathTracer.radiance(hit, x, y, sample, c) : whitted.shade(hit, 0, 1.0f, c, rec);
            }
          out.at(x, y) = sum / static_cast<float>(spp * spp);
        }
      total.add(c);
      progress.tileDone();
    });
  });
  counts = total.get();
}

void RayTracer::referencePass(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                              RayCounts& counts, RayCapture* capture) {
  assert(impl_->scene && "renderReference before a successful setScene");
  out.width = settings.width;
  out.height = settings.height;
  out.rgb.assign(static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height), scene.background);
  counts = {};
  if (!impl_->scene) return;
  if (capture)
    referencePassWith<TileCapture>(scene, camera, settings, out, counts, capture);
  else
    referencePassWith<NoCapture>(scene, camera, settings, out, counts, nullptr);
}

void RayTracer::setRadiosity(std::shared_ptr<const RadiosityField> field) { impl_->radiosity = std::move(field); }

PixelTrace RayTracer::tracePixel(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                 const VisibilityBuffer& visibility, int gx, int gy) const {
  assert(impl_->scene && "tracePixel before a successful setScene");
  assert(gx >= 0 && gy >= 0 && gx < gridSize(visibility.width, std::max(1, settings.rayScale)) &&
         gy < gridSize(visibility.height, std::max(1, settings.rayScale)) && "tracePixel: outside the ray grid");
  if (!impl_->scene) return {};
  // Hybrid shadows with the maps the last pass used (a stale map would still be exact, but not the frame's).
  const ShadowCertainty* maps = nullptr;
  if (settings.hybridShadows && !impl_->scene->hasMotion() && !impl_->shadowMapsStale &&
      impl_->shadowMaps.builtFor(FrameShading(scene, settings.shadingOverride, impl_->scene->anchor())))
    maps = &impl_->shadowMaps;
  return traceHybridPixel(scene, *impl_->scene, camera, settings, visibility, gx, gy, maps, impl_->radiosity.get());
}

PixelTrace RayTracer::tracePixelReference(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                          int x, int y) const {
  assert(impl_->scene && "tracePixelReference before a successful setScene");
  if (!impl_->scene) return {};
  return traceReferencePixel(scene, *impl_->scene, camera, settings, x, y, impl_->radiosity.get());
}

namespace {

/// The reversed-Z window depth the rasterizer writes for render-space point `posW` seen by `camera` (in render
/// space): VisibilityPass's clipFromWorldRelative applied to the point relative to the camera.
float windowDepth(const Camera& camera, glm::ivec2 size, glm::vec3 posW) {
  const glm::mat4 viewRotation = glm::mat4(glm::mat3(camera.viewFromWorld()));
  const glm::vec4 clip = camera.clipFromView(size) * viewRotation * glm::vec4(posW - camera.posW, 1.0f);
  const float depth = clip.z / clip.w;
  return std::isfinite(depth) ? std::clamp(depth, 0.0f, 1.0f) : 0.0f;
}

/// Whether a render-space camera's near plane reaches into `box` (render space): the rasterizer then
/// clips the proxy's near side, and a solid inside may stand in front of what it draws.
bool nearPlaneReaches(const Camera& camera, glm::ivec2 size, const ReuseBox& box) {
  // The farthest point of the near plane's rectangle from the camera position, a bound on how far the
  // clipped region reaches.
  const float aspect = static_cast<float>(size.x) / static_cast<float>(size.y);
  float reach;
  if (camera.orthographic) {
    const float h = 0.5f * camera.orthoHeight;
    reach = std::sqrt(camera.nearZ * camera.nearZ + h * h * (1.0f + aspect * aspect));
  } else {
    const float t = std::tan(glm::radians(camera.yFovDeg) * 0.5f);
    reach = camera.nearZ * std::sqrt(1.0f + t * t * (1.0f + aspect * aspect)) * 1.01f;
  }
  const glm::dvec3 p(camera.posW);
  const double r = static_cast<double>(reach);
  return p.x >= box.lo.x - r && p.x <= box.hi.x + r && p.y >= box.lo.y - r && p.y <= box.hi.y + r &&
         p.z >= box.lo.z - r && p.z <= box.hi.z + r;
}

}  // namespace

void RayTracer::resolveExact(const Scene& scene, const Camera& camera, VisibilityBuffer& visibility,
                             std::vector<ResolvedPixel>& out, RayCounts& counts) {
  out.clear();
  assert(impl_->scene && "resolveExact before a successful setScene");
  if (!impl_->scene || !impl_->scene->anyExact()) return;
  const EmbreeScene& embree = *impl_->scene;
  const int width = visibility.width, height = visibility.height;
  assert(visibility.ids.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  const glm::ivec2 size(width, height);
  const Camera cam = toRenderSpace(camera, embree.anchor());
  const CameraRays cameraRays(cam, size);
  const float time = cameraRays.time();
  // The camera within a proxy's bounds: the raster may show what lies behind a solid in front of it.
  bool everyPixel = false;
  for (std::size_t i = 0; i < scene.instances.size() && !everyPixel; ++i) {
    if (!embree.isExact(i)) continue;
    ReuseBox box;
    if (ReuseGate::instanceBox(impl_->meshBounds[scene.instances[i].mesh], embree.transformAt(i, time).worldFromObject,
                               glm::dvec3(0.0), box))
      everyPixel = nearPlaneReaches(cam, size, box);
  }
  const std::size_t tiles = static_cast<std::size_t>(tileCount(width)) * static_cast<std::size_t>(tileCount(height));
  std::vector<std::vector<ResolvedPixel>> perTile(tiles);
  std::atomic<std::uint64_t> rays{0};
  RTCScene top = embree.top();
  impl_->arena.execute([&] {
    forEachTile(impl_->threads, width, height, [&](int x0, int y0, int x1, int y1) {
      std::vector<ResolvedPixel>& records = perTile[tileIndex(x0, y0, width)];
      std::uint64_t traced = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          glm::uvec2& id = visibility.ids[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                          static_cast<std::size_t>(x)];
          if (!everyPixel && (id.x == 0 || !embree.isExact(id.x - 1))) continue;
          // The hybrid pass's camera ray for this pixel, within the rasterizer's span.
          const Ray ray = cameraRays.through(glm::vec2(x, y) + 0.5f);
          float tNear, tFar;
          cameraSpan(cam, ray, tNear, tFar);
          ResolvedPixel r;
          r.pixel = glm::uvec2(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
          ++traced;
          RTCRayHit rh;
          if (makeEmbreeRay(rh.ray, ray.origin, ray.dir, tNear, tFar, time)) {
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcIntersect1(top, &ctx, &rh);
            if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
              const std::uint32_t instance = rh.hit.instID[0];
              float t = rh.ray.tfar;
              r.id = glm::uvec2(instance + 1, rh.hit.primID);
              if (embree.isExact(instance)) {
                // The user geometry found the solid's crossing (core/Solids, in double): its t, and its outward
                // normal in the instance's object space (Embree leaves instanced normals there).
                const glm::vec3 n = embree.transformAt(instance, time).normalWorldFromObject *
                                    glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
                const float len = glm::length(n);
                r.id.y = kExactTriangle;
                r.hit = glm::vec4(len > 0.0f && std::isfinite(len) ? n / len : -ray.dir, t);
              }
              r.depth = windowDepth(cam, size, ray.origin + t * ray.dir);
              // A hit the depth cannot tell from the far plane would read as background in the GL.
              if (!(r.depth > 0.0f)) r.depth = std::numeric_limits<float>::min();
            }
          }
          if (!everyPixel || r.id != id) records.push_back(r);
          // The GL's shadow proofs were of the raster's hit: a pixel given another keeps none.
          if (r.id != id && !visibility.proofs.empty())
            visibility.proofs[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = 0;
          id = r.id;
        }
      rays.fetch_add(traced, std::memory_order_relaxed);
    });
  });
  counts.resolved += rays.load();
  std::size_t total = 0;
  for (const auto& t : perTile) total += t.size();
  out.reserve(total);
  // Tile order is not pixel order; the records' order does not matter to the GL, only their determinism.
  for (const auto& t : perTile) out.insert(out.end(), t.begin(), t.end());
}

void RayTracer::castVisibility(const Camera& camera, int width, int height, VisibilityBuffer& out) {
  assert(impl_->scene && "castVisibility before a successful setScene");
  out.width = width;
  out.height = height;
  out.ids.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), glm::uvec2(0));
  if (!impl_->scene) return;
  RTCScene top = impl_->scene->top();
  const Camera cam = toRenderSpace(camera, impl_->scene->anchor());  // camera-relative, as in trace()
  const CameraRays cameraRays(cam, {width, height});
  impl_->arena.execute([&] {
    forEachTile(impl_->threads, width, height, [&](int x0, int y0, int x1, int y1) {
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          Ray ray = cameraRays.through(glm::vec2(x, y) + 0.5f);
          float tNear, tFar;
          cameraSpan(cam, ray, tNear, tFar);
          RTCRayHit rh;
          if (!makeEmbreeRay(rh.ray, ray.origin, ray.dir, tNear, tFar, cameraRays.time())) continue;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          rtcIntersect1(top, &ctx, &rh);
          if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID) continue;
          out.ids[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] =
              glm::uvec2(rh.hit.instID[0] + 1, rh.hit.primID);
        }
    });
  });
}

}  // namespace tandem::rt
