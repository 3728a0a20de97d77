#pragma once
// Ray capture: the exact rays one frame of the ray pass traced, per kind and per tile, in trace order,
// with what Embree answered. The bench re-traces them with no shading (RayTracerBench::retrace) to
// measure the floor of the ray pass: how fast the same rays go through Embree alone (docs/bench.md,
// "Ceiling"). The passes record into it through the policy of rt/TileCapture.h, only when the bench asks
// (rt/RayTracerBench.h): the frame's passes are compiled without it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/FrameStats.h"

namespace tandem::rt {

enum class RayKind : std::uint8_t { Primary = 0, Shadow = 1, Reflection = 2, Refraction = 3 };
inline constexpr std::size_t kRayKinds = 4;
const char* toString(RayKind kind);

/// One ray as the pass handed it to Embree, and the answer it got.
struct CapturedRay {
  glm::vec3 origin{0.0f};
  float tnear = 0.0f;
  glm::vec3 dir{0.0f};
  float tfar = 0.0f;
  /// Occlusion rays (shadow): occluded. Intersection rays: hit a triangle of the scene.
  bool hit = false;
  /// False when the pass counted the ray but Embree was not called (a non-finite origin or direction,
  /// which makeEmbreeRay refuses): re-tracing skips it too.
  bool traced = true;
  /// Shadow rays: the light they head for (the pass traces a tile's rays towards one light together, in
  /// packets, and so may the floor). 0 for other kinds.
  std::uint8_t group = 0;
};

struct RayCaptureTile {
  std::array<std::vector<CapturedRay>, kRayKinds> rays;  // index = RayKind
};

struct RayCapture {
  /// Tiles of the grid the pass ran on, row-major (tile t covers 16×16 pixels starting at
  /// ((t % tilesX)·16, (t / tilesX)·16)), so the order does not depend on the thread schedule.
  std::vector<RayCaptureTile> tiles;
  int width = 0;   // grid the pass ran on
  int height = 0;
  /// True when primary rays went through Embree (reference mode). In the hybrid pass the primary hit
  /// is the rasterized triangle intersected on the CPU: the ray is recorded (it is counted in
  /// RayCounts::primary) but was not traced by Embree.
  bool primaryTraced = false;

  void clear();
  std::size_t count(RayKind kind) const;
  RayCounts counts() const;
};

/// How a kind is re-traced: one rtc*1 call per ray, one rtc*1M call per tile (Embree's stream API), or
/// rtc*8 packets of a tile's rays, grouped by CapturedRay::group in capture order (as the pass traces
/// its shadow rays).
enum class RetraceApi : std::uint8_t { Single = 0, Stream = 1, Packet = 2 };
inline constexpr int kRetraceApis = 3;
const char* toString(RetraceApi api);

struct RetraceOptions {
  std::array<RetraceApi, kRayKinds> api{RetraceApi::Single, RetraceApi::Stream, RetraceApi::Single,
                                        RetraceApi::Single};
  /// Which kinds to re-trace. Primary rays are skipped when the capture says they were not traced.
  std::array<bool, kRayKinds> kinds{true, true, true, true};
};

struct RetraceStats {
  std::array<double, kRayKinds> ms{};              // wall time per kind (each kind is its own parallel pass)
  std::array<std::uint64_t, kRayKinds> rays{};     // rays sent to Embree
  std::array<std::uint64_t, kRayKinds> mismatches{};  // hit/miss answers that differ from the capture
  double totalMs() const { return ms[0] + ms[1] + ms[2] + ms[3]; }
};

}  // namespace tandem::rt
