#pragma once
// How the passes record rays for the bench's capture (rt/RayCapture.h), as a compile-time policy: the
// frame's passes are instantiated with NoCapture, whose members are empty and inline, so their loops hold
// no capture code at all; RayTracerBench instantiates them with TileCapture, one per tile.
//
// The recursion (Whitted::intersect, lightMask) reports its rays through the RayRecorder interface, which
// TileCapture implements; the batched passes (ShadowBatch, Wavefront), whose answers come later from one
// Embree call for many rays, record through deferred() and answer().
#include <cstddef>

#include <glm/glm.hpp>

#include "rt/RayCapture.h"
#include "rt/Whitted.h"

namespace tandem::rt {

/// The frame's policy: nothing is recorded.
struct NoCapture {
  static constexpr bool kRecords = false;
  std::size_t deferred(RayKind, glm::vec3, glm::vec3, float, float, std::uint8_t = 0) const { return 0; }
  void answer(RayKind, std::size_t, bool, bool = true) const {}
  /// The recorder the recursion takes under this policy.
  NoRecorder recorder() const { return {}; }
};

/// Records one tile's rays, in trace order, with Embree's answers. Lives on the stack of the tile's body.
class TileCapture final : public RayRecorder {
 public:
  static constexpr bool kRecords = true;
  explicit TileCapture(RayCaptureTile& tile) : tile_(tile) {}
  TileCapture(const TileCapture&) = delete;
  TileCapture& operator=(const TileCapture&) = delete;

  /// A ray whose answer comes later (batched): returns its index among the tile's rays of `kind`.
  std::size_t deferred(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, std::uint8_t group = 0);
  /// The answer of a deferred ray; traced = false: Embree was not called for it.
  void answer(RayKind kind, std::size_t index, bool hit, bool traced = true);
  /// A hybrid frame's primary ray: counted, but intersected on the CPU against the rasterized triangle,
  /// not by Embree.
  void rasterPrimary(glm::vec3 originW, glm::vec3 dirW);
  /// The recorder the recursion takes under this policy (forwards to this object).
  Recording recorder() { return Recording(*this); }

  // RayRecorder: the recursion's rays. A ray begun is answered by embreeHit or notTraced, or stays a
  // miss; shadow rays come whole.
  void beginRay(RayKind kind, glm::vec3 originW, glm::vec3 dirW, float tNear, float tFar, glm::vec3 weight,
                float throughput) override;
  void embreeHit(std::uint32_t instance, std::uint32_t triangle, float t) override;
  void notTraced() override;
  void shadowRay(std::size_t light, const ShadowRay& ray, bool occluded) override;
  void surface(const SurfaceHit&) override {}
  void noShadowRay(std::size_t, NoShadowRay) override {}
  void local(const glm::vec3&, std::uint32_t, bool) override {}
  void weights(const WhittedWeights&) override {}
  void skipped(RayKind, float, float) override {}
  void noSecondaryRays(const Whitted&, const SurfaceHit&) override {}
  void endRay(glm::vec3, glm::vec3) override {}

 private:
  CapturedRay* pending();
  RayCaptureTile& tile_;
  // The ray begun last: Embree answers it before the recursion begins another.
  bool hasPending_ = false;
  RayKind pendingKind_ = RayKind::Primary;
  std::size_t pendingIndex_ = 0;
};

}  // namespace tandem::rt
