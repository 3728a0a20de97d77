#pragma once
// The batched forms of the Whitted pass that the frame runs: a tile's shadow rays in one Embree call, and
// its reflection and refraction rays breadth first, one call per depth. Both take the capture policy of
// rt/TileCapture.h as a template parameter (instantiated for NoCapture and TileCapture only).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "rt/RayBuffers.h"
#include "rt/SurfaceShading.h"
#include "rt/TileShafts.h"
#include "rt/Whitted.h"
#include "tandem/FrameStats.h"

namespace tandem::rt {

/// Shadow rays gathered from many hits and traced in packets of kPacket rays towards one light: each ray
/// answers one (slot, light bit). Reused across tiles (clear() keeps the capacity), so a tile allocates
/// nothing.
class ReuseGate;
struct ReuseTile;

/// The shadow bits of one primary hit that the frame before may have answered already (rt/RayReuse.h).
struct ShadowKeep {
  const ReuseGate* gate = nullptr;
  const ReuseTile* tile = nullptr;  // the moved bounds the tile's rays can meet, per light
  std::uint32_t lights = 0;  // lights whose bit may be kept
  std::uint32_t bits = 0;    // the kept frame's mask
  std::size_t grid = 0;      // the hit's grid pixel (an area light's kept sample bits, ReuseGate::keptArea)
};

class ShadowBatch {
 public:
  void clear();
  /// Queues the shadow rays of `hit` (Whitted::shadowRay, light order), answering into masks[slot];
  /// returns the bits of the lights that are visible without a ray.
  /// With `keep`, a needed ray that passes clear of everything that moved takes the kept bit instead.
  /// Area lights: a ray per sample (Whitted::areaShadowRay), whose bit goes to area[slot · areaStride]
  /// for the light's area slot; add() sets those words to the samples visible without a ray.
  /// `proof`: the GL's shadow proofs of this (primary) hit (VisibilityBuffer::proofs): where bit 8 + j is
  /// set, light j's ray is answered by bit j without being traced (counted in shadowByMap). `depth`: the
  /// hit's bounces past the camera's ray (its area-light samples: FrameShading::lightAt).
  template <class Capture>
  std::uint32_t add(const Whitted& whitted, std::size_t lights, const ShadowPoint& hit, std::size_t slot,
                    Capture& capture, const ShadowKeep* keep = nullptr, std::uint32_t* area = nullptr,
                    std::size_t areaStride = 1, std::uint32_t proof = 0, int depth = 0);
  /// Traces the queued rays and ORs the bit of every unoccluded one into masks[its slot].
  template <class Capture>
  void trace(RTCScene scene, LightMask* masks, RayCounts& counts, Capture& capture);
  // The same with nothing recorded (the frame's policy, rt/TileCapture.h).
  std::uint32_t add(const Whitted& whitted, std::size_t lights, const ShadowPoint& hit, std::size_t slot);
  void trace(RTCScene scene, LightMask* masks, RayCounts& counts);
  /// Hybrid shadows' tile shafts (rt/TileShafts.h, Whitted::shafts()): before the points `at(0 .. count)`
  /// are added, their shafts towards each light are tested once; add() then answers lit, without setting a
  /// ray up, each point's test towards a light its shaft is clear to. Without it (or without shafts) every
  /// needed ray is traced (or answered by the maps).
  template <class At>
  void prepareShafts(const Whitted& whitted, std::size_t count, At at);

 private:
  // A point, spot or directional light's shadow ray as its packet lane will hold it: written once by
  // add(), copied into the packet by trace() (no RTCRay in between: the rays are kept per light, in the
  // order they were added, which is the order the packets take them in).
  struct LaneRay {
    glm::vec3 org;
    float tfar;
    glm::vec3 dir;
    float time;
    std::uint32_t slot;
  };
  // Tile shafts (rt/TileShafts.h): per instance of the points given to prepareShafts, the box of those
  // points and the lights towards which nothing else can meet a ray from any of them.
  struct ShaftGroup {
    std::uint32_t instance = 0;
    glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    float lift = 0.0f;         // bound of the offset origins' distance from their points
    std::uint32_t lit = 0;     // bit j: light j's rays from these points are answered lit
  };
  // The lights each group's shaft is clear towards (prepareShafts' second half).
  void decideShafts(const Whitted& whitted);
  // The group of `instance` (lastGroup_ set to it), or groups_.size() when it has none.
  std::size_t findGroup(std::uint32_t instance);
  // The lights whose shadow tests of `hit` its group's shaft answers (bit j: light j).
  std::uint32_t litByShaft(const ShadowPoint& hit);
  const TileShafts* shafts_ = nullptr;  // Whitted::shafts() of the last prepareShafts
  std::vector<ShaftGroup> groups_;
  std::size_t lastGroup_ = 0;  // consecutive points mostly share their instance
  std::uint64_t byShaft_ = 0;  // shadow tests the shafts answered since the last trace()
  std::array<std::vector<LaneRay>, kMaxLights> byLight_;
  std::array<std::vector<std::size_t>, kMaxLights> capturedByLight_;  // under a recording Capture: capture indices
  // Area lights' rays, traced one by one (trace() says why).
  std::vector<RTCRay> areaRays_;
  std::vector<std::size_t> areaSlots_;
  std::vector<std::uint32_t> areaBits_;
  std::vector<std::uint32_t*> areaWords_;  // the word each ray's sample bit goes to
  std::vector<std::uint8_t> samples_;      // each ray's sample number
  std::vector<std::size_t> areaCaptured_;  // under a recording Capture: each ray's index there
  std::uint64_t byMap_ = 0;            // rays the hybrid shadows' maps answered since the last trace()
  std::uint64_t kept_ = 0;             // rays answered by the frame before since the last trace()
};

template <class At>
void ShadowBatch::prepareShafts(const Whitted& whitted, std::size_t count, At at) {
  groups_.clear();
  lastGroup_ = 0;
  shafts_ = whitted.shafts();
  if (!shafts_) return;
  // The points by instance: their box, and how far their offset origins may lie from them.
  for (std::size_t i = 0; i < count; ++i) {
    const ShadowPoint& p = at(i);
    if (!shafts_->joins(p.instance) || p.triangle == kExactTriangle || p.time != shafts_->time()) continue;
    if (findGroup(p.instance) == groups_.size()) groups_.push_back({p.instance});
    ShaftGroup& g = groups_[lastGroup_];
    g.lo = glm::min(g.lo, p.posW);
    g.hi = glm::max(g.hi, p.posW);
    g.lift = std::max(g.lift, offsetLift(p.posW, p.posMagnitude));
  }
  decideShafts(whitted);
}

/// The reflection and refraction rays of a tile's primary hits, traced breadth first (a wavefront):
/// every ray of one depth goes to Embree in one rtcIntersect1M call (measured about 1.8× faster than
/// rtcIntersect1 per ray on the Whitted scene), the shadow rays of their hits in a ShadowBatch, and
/// the hits spawn the next depth. It traces exactly the rays Whitted::secondary's recursion would (the
/// same decisions on the same numbers) and sums them in the recursion's order, bottom up over the path
/// tree, so S and T are bit-identical to the recursive result and do not depend on the thread count.
class Wavefront {
 public:
  /// Scratch kept between tiles (one per thread): the path tree and the per-depth batches.
  struct Buffers {
    struct Node {
      glm::vec3 origin{0.0f};
      glm::vec3 dir{0.0f};
      float time = 0.5f;        // within the shutter: its parent hit's (SurfaceHit::time)
      glm::vec3 weight{0.0f};   // wR or wT of the parent's Whitted sum (WhittedWeights), over N for a glossy hit's N rays
      float throughput = 0.0f;  // product of the weights (largest component) from the primary hit
      std::int64_t parent = -1;  // node index; -1: a primary hit's ray, whose S or T goes to `pixel`
      std::size_t pixel = 0;
      std::size_t captured = 0;  // under a recording Capture: the ray's index there
      bool refraction = false;   // T rather than S of its parent
      bool hit = false;
      glm::vec3 local{0.0f};     // shaded local colour of the hit, or the background on a miss
      // The hit's rays (its children): nodes [firstChild, firstChild + children), reflections first, queued
      // together by spawn (a glossy hit has several of each kind).
      std::size_t firstChild = 0;
      std::uint32_t children = 0;
      glm::vec3 weighted{0.0f};  // weight ⊙ the ray's radiance: what it adds to its parent's sum
    };
    std::vector<Node> nodes;
    std::vector<RTCRayHit> rays;
    std::vector<std::size_t> rayNodes;
    std::vector<SurfaceHit> hits;
    std::vector<std::size_t> hitNodes;
    std::vector<LightMask> masks;
    std::vector<AreaSampleBits> area;  // the hits' area-light sample bits
    ShadowBatch shadows;
  };

  Wavefront(const Whitted& whitted, Buffers& buffers);
  /// Queues the depth-0 reflection and refraction rays of a primary hit (counted now, as the
  /// recursion counts them), whose weighted S and T go to `pixel` of the output arrays.
  template <class Capture>
  void addPrimary(const SurfaceHit& hit, std::size_t pixel, RayCounts& counts, Capture& capture);
  /// Traces depth after depth, then writes (wR·S, 1) and (wT·T, 1) of every pixel that traced the ray.
  template <class Capture>
  void run(RayCounts& counts, glm::vec4* reflected, glm::vec4* transmitted, Capture& capture);
  // The same with nothing recorded (the frame's policy, rt/TileCapture.h).
  void addPrimary(const SurfaceHit& hit, std::size_t pixel, RayCounts& counts);
  void run(RayCounts& counts, glm::vec4* reflected, glm::vec4* transmitted);

 private:
  template <class Capture>
  void spawn(const SurfaceHit& hit, int depth, float throughput, std::int64_t parent, std::size_t pixel,
             RayCounts& counts, Capture& capture);
  const Whitted& whitted_;
  Buffers& b_;
};

}  // namespace tandem::rt
