#include "rt/RayTracer.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <limits>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "rt/EmbreeScene.h"
#include "rt/PixelTrace.h"
#include "rt/RayCapture.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"
#include "rt/Whitted.h"
#include "tandem/Log.h"
#include "core/Timer.h"

namespace tandem::rt {

namespace {

// Square tiles of ray-grid pixels: the unit of parallel work, and of one batched shadow-ray call.
constexpr int kTile = 16;

struct AtomicCounts {
  std::atomic<std::uint64_t> primary{0}, shadow{0}, reflection{0}, refraction{0};
  void add(const RayCounts& c) {
    primary += c.primary;
    shadow += c.shadow;
    reflection += c.reflection;
    refraction += c.refraction;
  }
  RayCounts get() const { return {primary.load(), shadow.load(), reflection.load(), refraction.load()}; }
};

// ThreadSanitizer builds (tools/test.sh --tsan) run the parallel loops on plain std::threads: Debian's
// libtbb is not built with -fsanitize=thread, so TSan never sees the synchronisation inside it and reports
// every hand-over in TBB's inlined partitioner as a race, burying anything real. std::thread's start and
// join and the atomic counter below are visible to TSan, so our own code (the tile bodies, the shared
// outputs and counters) is still checked, on the same number of threads. Normal builds keep TBB.
#if defined(__SANITIZE_THREAD__)
#define TANDEM_TSAN_THREADS 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TANDEM_TSAN_THREADS 1
#endif
#endif

/// Runs body(i) for i in [0, n) on `threads` threads (TBB: inside the caller's arena), in any order.
template <class Body>
void parallelIndices(int threads, std::size_t n, Body&& body) {
#ifdef TANDEM_TSAN_THREADS
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) body(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
#else
  (void)threads;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
#endif
}

/// Runs body(x0, y0, x1, y1) for every tile of a width × height grid, in parallel. The order tiles run
/// in does not matter: every pixel depends on nothing but its own inputs.
template <class Body>
void forEachTile(int threads, int width, int height, Body&& body) {
  int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
  parallelIndices(threads, static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY), [&](std::size_t i) {
    int t = static_cast<int>(i);
    int x0 = (t % tilesX) * kTile, y0 = (t / tilesX) * kTile;
    body(x0, y0, std::min(x0 + kTile, width), std::min(y0 + kTile, height));
  });
}

/// Counts the tiles of one pass and tells the progress callback, if any, as each finishes. Without a
/// callback it costs one branch per tile; with one, a relaxed atomic increment (the order of calls is
/// not promised, so nothing stronger is needed).
class TileProgress {
 public:
  TileProgress(const RayPassProgressCallback& callback, int width, int height)
      : callback_(callback ? &callback : nullptr),
        tiles_(static_cast<std::uint64_t>((width + kTile - 1) / kTile) *
               static_cast<std::uint64_t>((height + kTile - 1) / kTile)) {}
  void tileDone() {
    if (callback_) (*callback_)({done_.fetch_add(1, std::memory_order_relaxed) + 1, tiles_});
  }

 private:
  const RayPassProgressCallback* callback_;
  std::uint64_t tiles_;
  std::atomic<std::uint64_t> done_{0};
};

}  // namespace

struct RayTracer::Impl {
  int threads = 1;
  tbb::task_arena arena;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> scene;
  bool batchedShadows = true;
  RayCapture* capture = nullptr;  // bench hook (setRayCapture)
  RayPassProgressCallback progress;  // setProgressCallback
};

namespace {
int tileCount(int n) { return (n + kTile - 1) / kTile; }
/// Row-major tile index of the tile starting at (x0, y0): the RayCapture tile order.
std::size_t tileIndex(int x0, int y0, int width) {
  return static_cast<std::size_t>(y0 / kTile) * static_cast<std::size_t>(tileCount(width)) +
         static_cast<std::size_t>(x0 / kTile);
}
void resetCapture(RayCapture* capture, int width, int height, bool primaryTraced) {
  if (!capture) return;
  capture->clear();
  capture->width = width;
  capture->height = height;
  capture->primaryTraced = primaryTraced;
  capture->tiles.resize(static_cast<std::size_t>(tileCount(width)) * static_cast<std::size_t>(tileCount(height)));
}
}  // namespace

Result<std::unique_ptr<RayTracer>> RayTracer::create(int threads) {
  auto device = EmbreeDevice::create();
  if (!device) return device.error();
  auto impl = std::make_unique<Impl>();
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

RayTracer::RayTracer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RayTracer::~RayTracer() {
  // Embree scenes before the device that made them.
  if (impl_) impl_->scene.reset();
}

int RayTracer::threads() const { return impl_->threads; }

std::size_t RayTracer::embreeBytes() const { return impl_->device ? impl_->device->bytesInUse() : 0; }
void RayTracer::setBatchedShadowRays(bool batched) { impl_->batchedShadows = batched; }
void RayTracer::setEmbreeMemoryLimit(std::size_t bytes) { impl_->device->setMemoryLimit(bytes); }
void RayTracer::setRayCapture(RayCapture* capture) { impl_->capture = capture; }
void RayTracer::setProgressCallback(RayPassProgressCallback progress) { impl_->progress = std::move(progress); }

Result<void> RayTracer::setScene(const Scene& scene) {
  Result<std::unique_ptr<EmbreeScene>> built = Error{};
  // Inside the arena so Embree's TBB build uses the requested thread count.
  impl_->arena.execute([&] { built = EmbreeScene::build(*impl_->device, scene); });
  if (!built) {
    logError("ray pass: " + built.error().message);
    return built.error();
  }
  impl_->scene = std::move(*built);
  return {};
}

void RayTracer::updateTransforms(const Scene& scene) {
  assert(impl_->scene && "updateTransforms before a successful setScene");
  if (!impl_->scene) return;
  impl_->arena.execute([&] { impl_->scene->updateTransforms(scene); });
}

void RayTracer::trace(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                      const VisibilityBuffer& visibility, RayOutputs& out) {
  assert(impl_->scene && "trace before a successful setScene");
  assert(visibility.ids.size() == static_cast<std::size_t>(visibility.width) * static_cast<std::size_t>(visibility.height));
  const int scale = std::max(1, settings.rayScale);
  const int width = visibility.width, height = visibility.height;
  const int gw = gridSize(width, scale), gh = gridSize(height, scale);
  out.width = gw;
  out.height = gh;
  out.threads = impl_->threads;
  out.counts = {};
  const std::size_t n = static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh);
  // Sized here, filled by the tiles (every grid pixel is written there, in parallel): a serial
  // assign() of the ~30 MB of a 1280×720 frame would cost more than a few percent of the pass.
  out.lightMask.resize(n);
  out.reflected.resize(n);
  out.transmitted.resize(n);
  if (!impl_->scene || n == 0) {
    out.lightMask.clear();
    out.reflected.clear();
    out.transmitted.clear();
    return;
  }

  const EmbreeScene& embree = *impl_->scene;
  // Camera-relative rendering (docs/numerics.md): rays and lights in the Embree scene's render space.
  const Camera cam = toRenderSpace(camera, embree.anchor());
  FrameShading frame(scene, settings.shadingOverride, embree.anchor());
  Whitted whitted(scene, embree, frame, TraceModes::hybrid(settings));
  const TraceModes& modes = whitted.modes();
  const bool batched = impl_->batchedShadows;
  const CameraRays cameraRays(cam, {width, height});
  AtomicCounts total;
  RayCapture* const capturing = impl_->capture;
  resetCapture(capturing, gw, gh, false);
  TileProgress progress(impl_->progress, gw, gh);

  impl_->arena.execute([&] {
    forEachTile(impl_->threads, gw, gh, [&](int x0, int y0, int x1, int y1) {
      capture::TileScope captureScope(capturing, tileIndex(x0, y0, gw));
      RayCounts counts;
      // Per-thread scratch, kept from tile to tile so a tile allocates nothing once warm.
      thread_local ShadowBatch shadows;  // the tile's primary shadow rays, one rtcOccluded1M
      thread_local Wavefront::Buffers wavefrontBuffers;
      shadows.clear();
      Wavefront wavefront(whitted, wavefrontBuffers);
      for (int gy = y0; gy < y1; ++gy)
        for (int gx = x0; gx < x1; ++gx) {
          std::size_t g = static_cast<std::size_t>(gy) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(gx);
          out.lightMask[g] = 0u;
          out.reflected[g] = out.transmitted[g] = glm::vec4(0.0f);
          glm::ivec2 p = fullPixelOfGridPixel(gx, gy, scale, width, height);
          glm::uvec2 id = visibility.ids[static_cast<std::size_t>(p.y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(p.x)];
          if (id.x == 0) continue;  // background: no light, nothing reflected or transmitted
          std::uint32_t instance = id.x - 1;
          // Ids come from the rasterizer of the same scene; a stale one is a bug, skipped in release.
          assert(embree.hasTriangle(instance, id.y) && "trace: visibility id not in the scene");
          if (!embree.hasTriangle(instance, id.y)) continue;
          Ray ray = cameraRays.through(glm::vec2(p) + 0.5f);
          SurfaceHit hit = resolveHit(scene, embree.transform(instance), instance, id.y, ray);
          ++counts.primary;
          // Bench hook: counted, but intersected on the CPU against the known triangle, not by Embree.
          capture::record(RayKind::Primary, ray.origin, ray.dir, 0.0f, std::numeric_limits<float>::infinity());
          capture::resolvePending(true, false);
          if (modes.primaryShadowRays)
            out.lightMask[g] = batched ? shadows.add(whitted, frame.lights.size(), hit, g) : whitted.lightMask(hit, counts);
          // (wR·S, 1) and (wT·T, 1) of a visible pixel: zero until the wavefront writes a traced one.
          out.reflected[g] = out.transmitted[g] = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
          wavefront.addPrimary(hit, g, counts);
        }
      shadows.trace(embree.top(), out.lightMask.data(), counts);
      wavefront.run(counts, out.reflected.data(), out.transmitted.data());
      total.add(counts);
      progress.tileDone();
    });
  });

  out.counts = total.get();
  // Cost follows the scene: an effect that traced no ray leaves its channel empty. The mask is the primary
  // points' only: with raster shadows, the shadow rays of secondary hits leave it to the shadow maps.
  if (out.counts.shadow == 0 || !modes.primaryShadowRays) out.lightMask.clear();
  if (out.counts.reflection == 0) out.reflected.clear();
  if (out.counts.refraction == 0) out.transmitted.clear();
}

void RayTracer::renderReference(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                                RayCounts& counts) {
  assert(impl_->scene && "renderReference before a successful setScene");
  const int width = settings.width, height = settings.height;
  out.width = width;
  out.height = height;
  out.rgb.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), scene.background);
  counts = {};
  if (!impl_->scene) return;
  const EmbreeScene& embree = *impl_->scene;
  const Camera cam = toRenderSpace(camera, embree.anchor());  // camera-relative, as in trace()
  FrameShading frame(scene, settings.shadingOverride, embree.anchor());
  Whitted whitted(scene, embree, frame, TraceModes::reference(settings));
  const int spp = std::max(1, settings.referenceSpp);
  const CameraRays cameraRays(cam, {width, height});
  AtomicCounts total;
  RayCapture* const capturing = impl_->capture;
  resetCapture(capturing, width, height, true);
  TileProgress progress(impl_->progress, width, height);

  impl_->arena.execute([&] {
    forEachTile(impl_->threads, width, height, [&](int x0, int y0, int x1, int y1) {
      capture::TileScope captureScope(capturing, tileIndex(x0, y0, width));
      RayCounts c;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          glm::vec3 sum(0.0f);
          for (int sy = 0; sy < spp; ++sy)
            for (int sx = 0; sx < spp; ++sx) {
              Ray ray = cameraRays.through(glm::vec2(x, y) + referenceSampleOffset(x, y, sx, sy, spp));
              float tNear, tFar;
              cameraSpan(cam, ray, tNear, tFar);
              ++c.primary;
              capture::record(RayKind::Primary, ray.origin, ray.dir, tNear, tFar);  // answered by intersect()
              std::uint32_t instance, triangle;
              if (!whitted.intersect(ray.origin, ray.dir, tNear, tFar, instance, triangle)) {
                sum += frame.background;
                continue;
              }
              SurfaceHit hit = resolveHit(scene, embree.transform(instance), instance, triangle, ray);
              sum += whitted.shade(hit, 0, 1.0f, c);
            }
          out.at(x, y) = sum / static_cast<float>(spp * spp);
        }
      total.add(c);
      progress.tileDone();
    });
  });
  counts = total.get();
}

PixelTrace RayTracer::tracePixel(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                 const VisibilityBuffer& visibility, int gx, int gy) const {
  assert(impl_->scene && "tracePixel before a successful setScene");
  assert(gx >= 0 && gy >= 0 && gx < gridSize(visibility.width, std::max(1, settings.rayScale)) &&
         gy < gridSize(visibility.height, std::max(1, settings.rayScale)) && "tracePixel: outside the ray grid");
  if (!impl_->scene) return {};
  return traceHybridPixel(scene, *impl_->scene, camera, settings, visibility, gx, gy);
}

PixelTrace RayTracer::tracePixelReference(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                          int x, int y) const {
  assert(impl_->scene && "tracePixelReference before a successful setScene");
  if (!impl_->scene) return {};
  return traceReferencePixel(scene, *impl_->scene, camera, settings, x, y);
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
          if (!makeEmbreeRay(rh.ray, ray.origin, ray.dir, tNear, tFar)) continue;
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

namespace tandem::rt {

namespace {
constexpr unsigned kInvalid = RTC_INVALID_GEOMETRY_ID;

bool toEmbree(const CapturedRay& c, RTCRay& r) { return makeEmbreeRay(r, c.origin, c.dir, c.tnear, c.tfar); }
bool toEmbree(const CapturedRay& c, RTCRayHit& rh) {
  rh.hit.geomID = kInvalid;
  rh.hit.instID[0] = kInvalid;
  return makeEmbreeRay(rh.ray, c.origin, c.dir, c.tnear, c.tfar);
}
bool answered(const RTCRay& r) { return r.tfar < 0.0f; }  // occluded: Embree sets tfar = -inf
bool answered(const RTCRayHit& rh) { return rh.hit.geomID != kInvalid && rh.hit.instID[0] != kInvalid; }
void traceOne(RTCScene scene, RTCIntersectContext& ctx, RTCRay& r) { rtcOccluded1(scene, &ctx, &r); }
void traceOne(RTCScene scene, RTCIntersectContext& ctx, RTCRayHit& rh) { rtcIntersect1(scene, &ctx, &rh); }
void traceMany(RTCScene scene, RTCIntersectContext& ctx, RTCRay* r, unsigned n) {
  rtcOccluded1M(scene, &ctx, r, n, sizeof(RTCRay));
}
void traceMany(RTCScene scene, RTCIntersectContext& ctx, RTCRayHit* rh, unsigned n) {
  rtcIntersect1M(scene, &ctx, rh, n, sizeof(RTCRayHit));
}

/// One tile's rays of one kind through Embree; returns the answers that differ from the capture. The
/// conversion to Embree's layout is part of the floor: any caller of Embree pays it.
template <class EmbreeRay>
std::uint64_t retraceTile(RTCScene scene, const std::vector<CapturedRay>& rays, RetraceApi api,
                          std::uint64_t& traced) {
  std::uint64_t mismatches = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  if (api == RetraceApi::Single) {
    for (const CapturedRay& c : rays) {
      if (!c.traced) continue;
      EmbreeRay r;
      if (!toEmbree(c, r)) continue;
      traceOne(scene, ctx, r);
      ++traced;
      mismatches += answered(r) != c.hit;
    }
    return mismatches;
  }
  // Stream: one call per tile, from a per-thread buffer so no tile allocates. Incoherent flag, as in
  // the ray pass (the coherent flag hangs Debian's Embree 3.13.5, see RayTracer::trace).
  thread_local std::vector<EmbreeRay> buffer;
  thread_local std::vector<const CapturedRay*> source;
  buffer.clear();
  source.clear();
  for (const CapturedRay& c : rays) {
    if (!c.traced) continue;
    buffer.emplace_back();
    if (!toEmbree(c, buffer.back())) {
      buffer.pop_back();
      continue;
    }
    source.push_back(&c);
  }
  if (buffer.empty()) return 0;
  traceMany(scene, ctx, buffer.data(), static_cast<unsigned>(buffer.size()));
  traced += buffer.size();
  for (std::size_t i = 0; i < buffer.size(); ++i) mismatches += answered(buffer[i]) != source[i]->hit;
  return mismatches;
}
}  // namespace

RetraceStats RayTracer::retrace(const RayCapture& capture, const RetraceOptions& options) {
  assert(impl_->scene && "retrace before a successful setScene");
  RetraceStats stats;
  if (!impl_->scene) return stats;
  RTCScene top = impl_->scene->top();
  for (std::size_t k = 0; k < kRayKinds; ++k) {
    auto kind = static_cast<RayKind>(k);
    if (!options.kinds[k] || (kind == RayKind::Primary && !capture.primaryTraced)) continue;
    if (capture.count(kind) == 0) continue;
    std::atomic<std::uint64_t> traced{0}, mismatches{0};
    Timer timer;
    impl_->arena.execute([&] {
      parallelIndices(impl_->threads, capture.tiles.size(), [&](std::size_t i) {
        const std::vector<CapturedRay>& rays = capture.tiles[i].rays[k];
        if (rays.empty()) return;
        std::uint64_t t = 0;
        std::uint64_t m = kind == RayKind::Shadow ? retraceTile<RTCRay>(top, rays, options.api[k], t)
                                                  : retraceTile<RTCRayHit>(top, rays, options.api[k], t);
        traced += t;
        mismatches += m;
      });
    });
    stats.ms[k] = timer.ms();
    stats.rays[k] = traced.load();
    stats.mismatches[k] = mismatches.load();
  }
  return stats;
}

}  // namespace tandem::rt
