#include "rt/RayTracerBench.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <type_traits>
#include <vector>

#include <embree3/rtcore.h>

#include "core/Timer.h"
#include "rt/Parallel.h"
#include "rt/RayTracerState.h"
#include "rt/Whitted.h"

namespace tandem::rt {

void RayTracerBench::trace(RayTracer& tracer, const Scene& scene, const Camera& camera, const FrameSettings& settings,
                           const VisibilityBuffer& visibility, RayOutputs& out, const BenchTrace& how) {
  tracer.hybridPass(scene, camera, settings, visibility, out, how.capture, how.batchedShadowRays);
}

void RayTracerBench::renderReference(RayTracer& tracer, const Scene& scene, const Camera& camera,
                                     const FrameSettings& settings, ImageF& out, RayCounts& counts,
                                     RayCapture& capture) {
  tracer.referencePass(scene, camera, settings, out, counts, &capture);
}

namespace {
constexpr unsigned kInvalid = RTC_INVALID_GEOMETRY_ID;

// Captured rays keep no shutter time: re-traced at the middle of the shutter (a timing, not an image).
bool toEmbree(const CapturedRay& c, RTCRay& r) { return makeEmbreeRay(r, c.origin, c.dir, c.tnear, c.tfar, 0.5f); }
bool toEmbree(const CapturedRay& c, RTCRayHit& rh) {
  rh.hit.geomID = kInvalid;
  rh.hit.instID[0] = kInvalid;
  return makeEmbreeRay(rh.ray, c.origin, c.dir, c.tnear, c.tfar, 0.5f);
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

// Packets: lane k of RTCRay8 / RTCRayHit8 from a ray made by toEmbree, traced, and its answer.
void setLane(RTCRay8& p, int k, const RTCRay& r) { setPacketLane(p, k, r); }
void setLane(RTCRayHit8& p, int k, const RTCRayHit& rh) {
  setPacketLane(p.ray, k, rh.ray);
  p.hit.geomID[k] = kInvalid;
  p.hit.instID[0][k] = kInvalid;
}
void tracePacket(const int* valid, RTCScene scene, RTCIntersectContext& ctx, RTCRay8& p) {
  rtcOccluded8(valid, scene, &ctx, &p);
}
void tracePacket(const int* valid, RTCScene scene, RTCIntersectContext& ctx, RTCRayHit8& p) {
  rtcIntersect8(valid, scene, &ctx, &p);
}
bool answered(const RTCRay8& p, int k) { return p.tfar[k] < 0.0f; }
bool answered(const RTCRayHit8& p, int k) { return p.hit.geomID[k] != kInvalid && p.hit.instID[0][k] != kInvalid; }

/// One tile's rays in packets of kPacket, grouped by CapturedRay::group (stable: capture order within a
/// group), as ShadowBatch::trace sends a tile's shadow rays.
template <class EmbreeRay, class Packet>
std::uint64_t retracePackets(RTCScene scene, RTCIntersectContext& ctx, const std::vector<CapturedRay>& rays,
                             std::uint64_t& traced) {
  thread_local std::vector<const CapturedRay*> order;
  order.clear();
  for (const CapturedRay& c : rays)
    if (c.traced) order.push_back(&c);
  std::stable_sort(order.begin(), order.end(), [](const CapturedRay* a, const CapturedRay* b) { return a->group < b->group; });
  std::uint64_t mismatches = 0;
  Packet packet{};
  alignas(32) int valid[kPacket];
  const CapturedRay* lane[kPacket];
  for (std::size_t next = 0; next < order.size();) {
    int lanes = 0;
    for (; lanes < kPacket && next < order.size(); ++next) {
      EmbreeRay r;
      if (!toEmbree(*order[next], r)) continue;
      setLane(packet, lanes, r);
      lane[lanes++] = order[next];
    }
    for (int k = 0; k < kPacket; ++k) valid[k] = k < lanes ? -1 : 0;
    if (lanes == 0) break;
    tracePacket(valid, scene, ctx, packet);
    traced += static_cast<std::uint64_t>(lanes);
    for (int k = 0; k < lanes; ++k) mismatches += answered(packet, k) != lane[k]->hit;
  }
  return mismatches;
}

/// One tile's rays of one kind through Embree; returns the answers that differ from the capture. The
/// conversion to Embree's layout is part of the floor: any caller of Embree pays it.
template <class EmbreeRay>
std::uint64_t retraceTile(RTCScene scene, const std::vector<CapturedRay>& rays, RetraceApi api,
                          std::uint64_t& traced) {
  std::uint64_t mismatches = 0;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  if (api == RetraceApi::Packet) {
    if constexpr (std::is_same_v<EmbreeRay, RTCRay>) return retracePackets<RTCRay, RTCRay8>(scene, ctx, rays, traced);
    else return retracePackets<RTCRayHit, RTCRayHit8>(scene, ctx, rays, traced);
  }
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

RetraceStats RayTracerBench::retrace(RayTracer& tracer, const RayCapture& capture, const RetraceOptions& options) {
  RayTracerState& impl = *tracer.impl_;
  assert(impl.scene && "retrace before a successful setScene");
  RetraceStats stats;
  if (!impl.scene) return stats;
  RTCScene top = impl.scene->top();
  for (std::size_t k = 0; k < kRayKinds; ++k) {
    auto kind = static_cast<RayKind>(k);
    if (!options.kinds[k] || (kind == RayKind::Primary && !capture.primaryTraced)) continue;
    if (capture.count(kind) == 0) continue;
    std::atomic<std::uint64_t> traced{0}, mismatches{0};
    Timer timer;
    impl.arena.execute([&] {
      parallelIndices(impl.threads, capture.tiles.size(), [&](std::size_t i) {
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
