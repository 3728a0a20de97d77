#include "rt/TileShafts.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"

namespace tandem::rt {

namespace {

// One plane of a shaft: points x with n·x <= d are inside.
struct ShaftPlane {
  glm::dvec3 n{0.0};
  double d = 0.0;
};

// The union box and the planes through corresponding edges of `from` and `to`: the shaft contains both
// boxes, so it contains every segment between them. For axes i, j and a corner direction (si, sj) of the
// plane they span, read in u = (si·x_i, sj·x_j) where both boxes' corners are maxima: when one box reaches
// further along i and the other along j, the line through their two corners bounds the hull there. Its
// normal ν has both components of one sign; taken >= 0, ν·u <= ν·corner holds for every point of either box
// (each lies below its own corner in both coordinates, and both corners are on the line).
int shaftPlanes(const ShaftBox& from, const ShaftBox& to, ShaftPlane (&planes)[12]) {
  int count = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      for (int corner = 0; corner < 4; ++corner) {
        const double si = (corner & 1) ? 1.0 : -1.0, sj = (corner & 2) ? 1.0 : -1.0;
        const double ai = si > 0 ? from.hi[i] : -from.lo[i], aj = sj > 0 ? from.hi[j] : -from.lo[j];
        const double bi = si > 0 ? to.hi[i] : -to.lo[i], bj = sj > 0 ? to.hi[j] : -to.lo[j];
        const bool mixed = (ai > bi && bj > aj) || (bi > ai && aj > bj);
        if (!mixed) continue;  // one box's corner dominates: the union box's faces bound the hull there
        double ni = bj - aj, nj = ai - bi;
        if (ni < 0.0) ni = -ni, nj = -nj;
        ShaftPlane& p = planes[count++];
        p.n[i] = si * ni;
        p.n[j] = sj * nj;
        p.d = ni * ai + nj * aj;
      }
  return count;
}

}  // namespace

bool shaftMisses(const ShaftBox& from, const ShaftBox& to, const ShaftBox& obstacle) {
  if (obstacle.empty()) return true;
  const glm::dvec3 lo = glm::min(from.lo, to.lo), hi = glm::max(from.hi, to.hi);
  for (int a = 0; a < 3; ++a)
    if (obstacle.hi[a] < lo[a] || obstacle.lo[a] > hi[a]) return true;
  ShaftPlane planes[12];
  const int count = shaftPlanes(from, to, planes);
  // Rounding of the planes' arithmetic (double): far below the obstacles' margins, but a box that only
  // touches a plane is not called outside it.
  const double slack = 1e-12 * std::max({maxAbs(lo), maxAbs(hi), maxAbs(obstacle.lo), maxAbs(obstacle.hi), 1e-300});
  for (int k = 0; k < count; ++k) {
    const ShaftPlane& p = planes[k];
    // The obstacle's corner least far along n.
    double least = 0.0;
    for (int a = 0; a < 3; ++a) least += p.n[a] * (p.n[a] > 0.0 ? obstacle.lo[a] : obstacle.hi[a]);
    if (least > p.d + slack * (std::abs(p.n.x) + std::abs(p.n.y) + std::abs(p.n.z))) return true;
  }
  return false;
}

int axisPlane(const Mesh& mesh) {
  if (mesh.exact || mesh.indices.empty()) return -1;
  for (std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size()) return -1;
  for (int a = 0; a < 3; ++a) {
    const float c = mesh.positions[mesh.indices[0]][a];
    bool same = std::isfinite(c);
    for (std::size_t k = 1; k < mesh.indices.size() && same; ++k) same = mesh.positions[mesh.indices[k]][a] == c;
    if (same) return a;
  }
  return -1;
}

void TileShafts::build(const Scene& scene, const EmbreeScene& embree, const std::vector<ReuseBox>& meshBounds,
                       const std::vector<int>& planes, float timeU) {
  const std::size_t n = scene.instances.size();
  active_ = false;
  time_ = timeU;
  planar_.assign(n, 0);
  planes_.assign(n, Plane{});
  boxes_.assign(n, ShaftBox{});
  if (meshBounds.size() != scene.meshes.size() || planes.size() != scene.meshes.size() || n != embree.instanceCount())
    return;
  ShaftBox all;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t mesh = scene.instances[i].mesh;
    const glm::mat4& m = embree.transformAt(i, timeU).worldFromObject;
    ReuseBox box;
    if (!ReuseGate::instanceBox(meshBounds[mesh], m, glm::dvec3(0.0), box)) {
      // No geometry (nothing to block), or a transform too large for a finite box (anything may block).
      if (meshBounds[mesh].lo.x <= meshBounds[mesh].hi.x) return;
      continue;
    }
    boxes_[i].lo = box.lo;
    boxes_[i].hi = box.hi;
    all.add(box.lo);
    all.add(box.hi);
    if (planes[mesh] >= 0) {
      // Its condition number (Frobenius norms bound the 2-norm one): a ray kMinRise off the plane keeps the
      // sign of its component along the axis through Embree's transform, whose rounding it scales, and a
      // shear stays far from moving an offset origin across the plane (rigid or uniformly scaled: 3).
      const glm::dmat3 linear{glm::dmat4(m)};
      const double det = glm::determinant(linear);
      if (!(std::abs(det) > 0.0)) continue;
      const glm::dmat3 inverse = glm::inverse(linear);
      double f = 0.0, g = 0.0;
      for (int c = 0; c < 3; ++c) f += glm::dot(linear[c], linear[c]), g += glm::dot(inverse[c], inverse[c]);
      if (!(std::sqrt(f * g) <= kMaxCondition)) continue;
      // The plane x[axis] = c of object space in render space: normal along the inverse transpose's column.
      const int axis = planes[mesh];
      const Mesh& m3 = scene.meshes[mesh];
      const glm::dvec3 normal = glm::transpose(inverse)[axis];
      const double length = glm::length(normal);
      if (!(length > 0.0)) continue;
      const glm::dvec3 onPlane(glm::dmat4(m) * glm::dvec4(glm::dvec3(m3.positions[m3.indices[0]]), 1.0));
      planes_[i].normal = normal / length;
      planes_[i].offset = glm::dot(planes_[i].normal, onPlane);
      planar_[i] = 1;
    }
  }
  if (!all.empty()) {
    sceneCentre_ = 0.5 * (all.lo + all.hi);
    sceneRadius_ = 0.5 * glm::length(all.hi - all.lo);
  }
  active_ = true;
}

bool TileShafts::clearOfOthers(std::uint32_t own, const ShaftBox& from, const ShaftBox& to, double rayMagnitude) const {
  const double grow = kRelativeMargin * rayMagnitude;
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    if (i == own || boxes_[i].empty()) continue;
    ShaftBox b = boxes_[i];
    b.lo -= glm::dvec3(grow);
    b.hi += glm::dvec3(grow);
    if (!shaftMisses(from, to, b)) return false;
  }
  return true;
}

double TileShafts::beyondScene(const ShaftBox& from, double rayMagnitude) const {
  // The farthest point of `from` from the scene's centre, plus the scene's radius and the bounds' growth:
  // past that, outside every grown box.
  const glm::dvec3 far = glm::max(glm::abs(from.lo - sceneCentre_), glm::abs(from.hi - sceneCentre_));
  return glm::length(far) + sceneRadius_ * (1.0 + 1e-3) + 2.0 * kRelativeMargin * rayMagnitude + 1.0;
}

}  // namespace tandem::rt
