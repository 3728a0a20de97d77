#pragma once
// The bench's and the tests' way into the ray pass (never the frame's): the pass with every ray it traces
// recorded (rt/RayCapture.h, recorded by the policy of rt/TileCapture.h, so the frame's own loops hold no
// capture code), the hybrid pass with one rtcOccluded1 per shadow ray instead of batches, and the raw
// re-trace of a capture that measures the floor of the pass (docs/bench.md, "Ceiling").
//
//   RayCapture capture;
//   RayTracerBench::trace(*tracer, scene, camera, settings, visibility, out, {&capture});
//   RetraceStats floor = RayTracerBench::retrace(*tracer, capture);
#include "rt/RayCapture.h"
#include "rt/RayTracer.h"

namespace tandem::rt {

/// How RayTracerBench::trace runs the hybrid pass.
struct BenchTrace {
  /// Non-null: every ray the pass traces is recorded here (cleared first). The caller owns it.
  RayCapture* capture = nullptr;
  /// Primary shadow rays per tile through one rtcOccluded1M call (true, as in the frame) or one
  /// rtcOccluded1 per ray. Both give identical masks.
  bool batchedShadowRays = true;
};

class RayTracerBench {
 public:
  /// RayTracer::trace, run as `how` says.
  static void trace(RayTracer& tracer, const Scene& scene, const Camera& camera, const FrameSettings& settings,
                    const VisibilityBuffer& visibility, RayOutputs& out, const BenchTrace& how);
  /// RayTracer::renderReference, recording every ray into `capture` (cleared first).
  static void renderReference(RayTracer& tracer, const Scene& scene, const Camera& camera,
                              const FrameSettings& settings, ImageF& out, RayCounts& counts, RayCapture& capture);
  /// Re-traces a capture through raw Embree, no shading, on the tracer's threads and scene (which must be
  /// the scene the capture was taken on): each kind a parallel pass over the capture's tiles with the API
  /// the options name. Reports time, rays and answers that differ from the capture's.
  static RetraceStats retrace(RayTracer& tracer, const RayCapture& capture, const RetraceOptions& options = {});
};

}  // namespace tandem::rt
