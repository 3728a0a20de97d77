#pragma once
// Tile shafts: the shadow rays of a tile's points towards one light, answered "lit" together without
// tracing any of them, where nothing but the points' own flat surface can lie on any of them
// (docs/shadows.md, "Tile shafts"). A proof, as the hybrid shadows' maps are: a ray it answers gets the
// answer Embree would give, by the maps' standard:
//
// - the point's own triangle never blocks its ray (the offset origin puts the ray on the far side of it
//   from where it goes: what every traced shadow ray relies on, spawnOrigin);
// - any other triangle farther than a margin far beyond the rounding of Embree's tests from the ray's
//   segment cannot block it.
//
// Every segment from a box of origins to a box of end points lies in the shaft between the two boxes
// (Haines and Wallace, "Shaft culling for efficient ray-cast radiosity", 1991), so an instance whose
// bounds, grown by the margin, miss the shaft cannot block any of them.
//
// The points' own instance lies in the shaft by construction. It is answered for only when its mesh lies
// in one axis plane of object space, exactly (every vertex shares one coordinate c: a floor, a wall, a
// quad): Embree's triangle tests (Moller-Trumbore and the robust Pluecker form alike) take a hit's
// distance t as T / den with T = (v0 - O).Ng and den = D.Ng, and for such a triangle the edge vectors have
// that coordinate exactly 0, so Ng is exactly 0 off the axis and the sign of t is sign(c - O)·sign(D) on
// that axis for every triangle of the plane. The ray's own triangle is rejected by exactly that sign (its
// origin lies off the plane on the side the ray goes to), so every triangle of the plane is. The ray must
// not graze the plane: its direction's component along the axis then keeps its sign through Embree's
// transform to object space, which the instance's condition number bounds.
// Area lights' rays are sampled one by one and left to Embree.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "rt/RayReuse.h"
#include "tandem/Scene.h"

namespace tandem::rt {

class EmbreeScene;

/// An axis-aligned box in double (render space); empty while lo > hi.
struct ShaftBox {
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  void add(glm::dvec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
};

/// Whether `obstacle` lies wholly outside the shaft between boxes `from` and `to`: the union box of the two
/// cut by the planes through their corresponding edges (Haines and Wallace). Every segment from a point of
/// `from` to a point of `to` lies in the shaft, so such an obstacle meets none. Conservative: an obstacle
/// that misses every segment may still be said to meet the shaft.
bool shaftMisses(const ShaftBox& from, const ShaftBox& to, const ShaftBox& obstacle);

/// The axis (0, 1, 2) on which every vertex of the mesh's triangles has the same coordinate, exactly, or
/// -1 (none, an exact solid, no triangles): the planes whose triangles never block each other's rays.
int axisPlane(const Mesh& mesh);

/// One pass's shafts: every instance's render-space bounds at the pass's time, grown by the margin, and
/// which instances lie in an axis plane.
class TileShafts {
 public:
  /// `planes`: axisPlane of each mesh of `scene`; `meshBounds`: each mesh's object bounds (RayTracer's).
  void build(const Scene& scene, const EmbreeScene& embree, const std::vector<ReuseBox>& meshBounds,
             const std::vector<int>& planes, float timeU);
  bool active() const { return active_; }
  /// The shutter time the bounds are for: the pass's (every ray of a hybrid pass runs at it).
  float time() const { return time_; }

  /// Whether the rays of `instance`'s points can join a shaft: it lies in an axis plane and its transform
  /// is well conditioned.
  bool joins(std::uint32_t instance) const { return active_ && instance < planar_.size() && planar_[instance] != 0; }
  /// The least sine between a ray and its point's plane for the plane's other triangles to be passed over
  /// as the point's own is (grazing rays are left to Embree).
  static constexpr double kMinRise = 1e-2;
  /// The largest condition number (Frobenius norms) of a joining instance's transform.
  static constexpr double kMaxCondition = 30.0;
  /// A joining instance's plane in render space: unit normal n and offset d (n·x = d on it).
  glm::dvec3 planeNormal(std::uint32_t instance) const { return planes_[instance].normal; }
  double planeOffset(std::uint32_t instance) const { return planes_[instance].offset; }
  /// Whether every instance but `own` misses the shaft from the box of origins `from` to the box of end
  /// points `to`, each instance's bounds grown by the margin for rays of magnitude up to `rayMagnitude`
  /// (their origins' coordinates and their lengths).
  bool clearOfOthers(std::uint32_t own, const ShaftBox& from, const ShaftBox& to, double rayMagnitude) const;
  /// A directional light's rays run on past the scene: a distance beyond which a ray from anywhere in
  /// `from` has left every instance's bounds, grown as clearOfOthers grows them for `rayMagnitude`.
  double beyondScene(const ShaftBox& from, double rayMagnitude) const;

  /// The margin, relative to the magnitudes involved (the maps' exact tests use a tenth of it).
  static constexpr double kRelativeMargin = 1e-4;

 private:
  bool active_ = false;
  float time_ = 0.5f;
  std::vector<std::uint8_t> planar_;  // per instance: joins()
  struct Plane {
    glm::dvec3 normal{0.0};
    double offset = 0.0;
  };
  std::vector<Plane> planes_;  // per instance: its plane where it joins
  std::vector<ShaftBox> boxes_;       // per instance, grown (empty: no geometry)
  glm::dvec3 sceneCentre_{0.0};
  double sceneRadius_ = 0.0;
};

}  // namespace tandem::rt
