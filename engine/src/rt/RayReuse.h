#pragma once
// Reuse across frames when the camera stood still and something moved (FrameSettings::reuseRays,
// docs/reuse.md). The frame before left its ids and ray results; a grid pixel that sees the same triangle
// of an instance that did not move has the same primary hit to the bit (the same camera ray through the
// same pixel, resolved against the same transform), so its shadow ray towards a light that did not change
// is the same ray. Its answer can change only if an instance that moved can meet it; one whose path stays
// clear of every moved instance's bounds, where it was and where it is, keeps the last frame's bit.
// Reflection and refraction are not kept: their paths wander the whole scene.
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/Shading.h"
#include "rt/RayBuffers.h"
#include "tandem/Scene.h"

namespace tandem::rt {

class EmbreeScene;

/// What the Renderer knows of the frame before: what it kept and what changed since. The kept frame had
/// the same camera, frame size and ray settings (the caller's promise, asserted where it can be).
struct RayReuse {
  const VisibilityBuffer* ids = nullptr;  // its ids, full resolution
  const RayOutputs* rays = nullptr;       // its results on the same ray grid
  /// Instances whose transform changed since: index and the worldFromObject the kept frame drew it with.
  std::vector<std::pair<std::uint32_t, glm::mat4>> moved;
  std::uint32_t changedLights = 0;  // bit j: direct light j (Scene::directLights() order) is not what it was
};

/// Axis-aligned bounds in render space, in double.
struct ReuseBox {
  glm::dvec3 lo{0.0}, hi{0.0};
};

/// Per tile of the ray grid and per light: the moved bounds that a shadow ray from the tile's kept hits
/// towards that light can meet (ReuseGate::selectForTile). Scratch kept by each thread.
struct ReuseTile {
  std::vector<std::uint32_t> boxes[kMaxLights];
};

/// The tiles' questions, built once per trace() from a RayReuse.
class ReuseGate {
 public:
  ReuseGate() = default;
  /// `meshBounds`: object-space bounds per mesh (lo, hi; lo > hi when the mesh is empty).
  /// `pixels` and `gridPixels`: this frame's full-resolution and ray-grid sizes (a kept frame of another
  /// size keeps nothing).
  /// `lights`: the frame's direct lights in render space (FrameShading::lights).
  ReuseGate(const RayReuse& reuse, const Scene& scene, const EmbreeScene& embree,
            const std::vector<ReuseBox>& meshBounds, const std::vector<shading::GpuLight>& lights, std::size_t pixels,
            std::size_t gridPixels);

  /// Whether any shadow bit can be kept at all this frame.
  bool active() const { return active_; }
  /// Lights whose bits may be kept (those that did not change).
  std::uint32_t keepableLights() const { return keepable_; }
  /// Whether the hit of full-resolution pixel `pixel` with ids `id` is the kept frame's, to the bit.
  bool samePoint(std::size_t pixel, glm::uvec2 id) const {
    return active_ && reuse_->ids->ids[pixel] == id && id.x != 0 && !moved_[id.x - 1];
  }
  /// The kept frame's light mask of grid pixel g.
  std::uint32_t keptMask(std::size_t g) const { return reuse_->rays->lightMask[g]; }
  /// The kept frame's sample bits of area light `slot` at grid pixel g (RayOutputs::areaSamples): the same
  /// point draws the same samples (its pixel's seed, the same sample index and count), so a sample's ray
  /// that passes clear of what moved keeps its answer like a point light's.
  std::uint32_t keptArea(std::size_t g, int slot) const {
    return reuse_->rays->areaSamples[static_cast<std::size_t>(slot) * reuse_->rays->lightMask.size() + g];
  }
  /// Chooses, for each light, the moved bounds that a shadow ray from a hit in [lo, hi] (render space)
  /// towards the light can meet: its path lies in the box spanned by [lo, hi] and the light's position (an
  /// area light's bounds), or
  /// [lo, hi] swept towards a directional light. A tile of kept hits on the floor far from what moved
  /// then tests no bounds at all per ray.
  /// `offsetScale`: the largest component of the hits' posMagnitude, the scale of their rays' origin
  /// offsets (offsetRayOrigin), which can exceed their coordinates (a large triangle, a far instance origin).
  void selectForTile(glm::dvec3 lo, glm::dvec3 hi, double offsetScale, ReuseTile& tile) const;
  /// Whether the shadow ray towards `light` from a hit of the tile (render space; tFar may be infinite)
  /// passes clear of every moved instance's bounds, before and after its move, with a margin far beyond
  /// the rounding of Embree's tests.
  bool clearOfMoved(const ReuseTile& tile, std::size_t light, glm::vec3 originW, glm::vec3 dirW, float tFar) const;

  /// The render-space bounds of an instance of a mesh with object bounds `mesh` under `worldFromObject`,
  /// grown by the margin (empty mesh: nothing, returns false).
  static bool instanceBox(const ReuseBox& mesh, const glm::mat4& worldFromObject, glm::dvec3 anchor, ReuseBox& out);
  /// Whether the ray's span [0, tFar] meets the box (tests call it directly).
  static bool rayMeetsBox(glm::dvec3 origin, glm::dvec3 dir, double tFar, const ReuseBox& box);

 private:
  const RayReuse* reuse_ = nullptr;
  bool active_ = false;
  std::uint32_t keepable_ = 0;
  std::vector<std::uint8_t> moved_;  // per instance
  std::vector<ReuseBox> boxes_;      // old and new place of each moved instance
  struct LightReach {
    bool directional = false;
    glm::dvec3 at{0.0};       // point and spot lights: the position
    glm::dvec3 extent{0.0};   // area lights: the half-size of their bounds around `at`
    glm::dvec3 towards{0.0};  // directional lights: the direction to the light
  };
  std::vector<LightReach> lights_;
};

/// Object-space bounds of every mesh (what ReuseGate takes; computed once per scene).
std::vector<ReuseBox> reuseMeshBounds(const Scene& scene);

}  // namespace tandem::rt
