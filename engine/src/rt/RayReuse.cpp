#include "rt/RayReuse.h"

#include <algorithm>
#include <cmath>

#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"

namespace tandem::rt {

namespace {

// The margin around a moved instance's bounds, relative to the coordinates involved: Embree tests a ray
// against an instance in object space after transforming the ray in float, so where it finds a crossing
// differs from the exact one by a few float roundings of those coordinates (~1e-7 relative). A thousand
// times that costs a few rays traced that could have been kept, never a bit kept that could differ.
constexpr double kMargin = 1e-4;

}  // namespace

std::vector<ReuseBox> reuseMeshBounds(const Scene& scene) {
  std::vector<ReuseBox> out(scene.meshes.size());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    ReuseBox& b = out[m];
    b.lo = glm::dvec3(std::numeric_limits<double>::infinity());
    b.hi = -b.lo;
    for (const glm::vec3& p : scene.meshes[m].positions) {
      b.lo = glm::min(b.lo, glm::dvec3(p));
      b.hi = glm::max(b.hi, glm::dvec3(p));
    }
  }
  return out;
}

bool ReuseGate::instanceBox(const ReuseBox& mesh, const glm::mat4& worldFromObject, glm::dvec3 anchor, ReuseBox& out) {
  if (!(mesh.lo.x <= mesh.hi.x)) return false;
  const glm::dmat4 m(worldFromObject);
  out.lo = glm::dvec3(std::numeric_limits<double>::infinity());
  out.hi = -out.lo;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? mesh.hi.x : mesh.lo.x, (k & 2) ? mesh.hi.y : mesh.lo.y,
                            (k & 4) ? mesh.hi.z : mesh.lo.z);
    const glm::dvec3 p = glm::dvec3(m * glm::dvec4(corner, 1.0)) - anchor;
    out.lo = glm::min(out.lo, p);
    out.hi = glm::max(out.hi, p);
  }
  // The transform's own translation counts too: Embree's rounding follows the object-space coordinates
  // scaled by the transform, which can be far larger than the box (a small part far from its origin).
  const double scale = std::max({maxAbs(out.lo), maxAbs(out.hi), maxAbs(glm::dvec3(m[3]) - anchor),
                                 maxAbs(mesh.lo) * maxAbs(glm::dvec3(m[0]) + glm::dvec3(m[1]) + glm::dvec3(m[2])),
                                 maxAbs(mesh.hi) * maxAbs(glm::dvec3(m[0]) + glm::dvec3(m[1]) + glm::dvec3(m[2]))});
  const double grow = kMargin * scale + 1e-30;
  out.lo -= glm::dvec3(grow);
  out.hi += glm::dvec3(grow);
  return std::isfinite(out.lo.x + out.lo.y + out.lo.z + out.hi.x + out.hi.y + out.hi.z);
}

bool ReuseGate::rayMeetsBox(glm::dvec3 origin, glm::dvec3 dir, double tFar, const ReuseBox& box) {
  double t0 = 0.0, t1 = tFar;
  for (int a = 0; a < 3; ++a) {
    if (dir[a] == 0.0) {
      if (origin[a] < box.lo[a] || origin[a] > box.hi[a]) return false;
      continue;
    }
    double tn = (box.lo[a] - origin[a]) / dir[a];
    double tf = (box.hi[a] - origin[a]) / dir[a];
    if (tn > tf) std::swap(tn, tf);
    t0 = std::max(t0, tn);
    t1 = std::min(t1, tf);
    if (t0 > t1) return false;
  }
  return true;
}

ReuseGate::ReuseGate(const RayReuse& reuse, const Scene& scene, const EmbreeScene& embree,
                     const std::vector<ReuseBox>& meshBounds, const std::vector<shading::GpuLight>& lights,
                     std::size_t pixels, std::size_t gridPixels)
    : reuse_(&reuse) {
  const std::uint32_t all = lights.size() >= 32 ? ~0u : (1u << lights.size()) - 1u;
  for (const shading::GpuLight& l : lights) {
    LightReach r;
    r.directional = static_cast<int>(l.posType.w + 0.5f) == TD_LIGHT_DIRECTIONAL;
    r.at = glm::dvec3(glm::vec3(l.posType));
    r.towards = -glm::dvec3(glm::vec3(l.dirRange));
    const int type = static_cast<int>(l.posType.w + 0.5f);
    if (type == TD_LIGHT_SPHERE) r.extent = glm::dvec3(static_cast<double>(l.shapeV.w));
    else if (shading::tdIsAreaLight(type)) r.extent = glm::abs(glm::dvec3(glm::vec3(l.shapeU))) + glm::abs(glm::dvec3(glm::vec3(l.shapeV)));
    lights_.push_back(r);
  }
  keepable_ = all & ~reuse.changedLights;
  // Area lights keep per-sample answers: only from a kept frame that has them, with the same lights area
  // lights (a light's plane is its rank among them, which a light changing type would shift).
  int areaLights = 0;
  std::uint32_t areaBits = 0;
  for (std::size_t j = 0; j < lights.size() && j < 32; ++j)
    if (shading::tdIsAreaLight(static_cast<int>(lights[j].posType.w + 0.5f))) {
      ++areaLights;
      areaBits |= 1u << j;
    }
  const bool areaKept = reuse.rays && reuse.rays->areaLightBits == areaBits && reuse.rays->areaLights == areaLights &&
                        reuse.rays->areaSamples.size() == static_cast<std::size_t>(areaLights) * gridPixels;
  for (std::size_t j = 0; j < lights.size() && j < 32; ++j)
    if (shading::tdIsAreaLight(static_cast<int>(lights[j].posType.w + 0.5f)) && !areaKept) keepable_ &= ~(1u << j);
  // Only a kept mask of this frame's sizes can be read; an empty one (no shadow ray last frame) says
  // "all visible" for the whole frame, not per pixel, so it keeps nothing.
  active_ = keepable_ != 0 && reuse.ids && reuse.rays && reuse.ids->ids.size() == pixels &&
            reuse.rays->lightMask.size() == gridPixels && gridPixels > 0 && meshBounds.size() == scene.meshes.size();
  if (!active_) return;
  moved_.assign(scene.instances.size(), 0);
  const glm::dvec3 anchor(embree.anchor());
  for (const auto& [instance, before] : reuse.moved) {
    if (instance >= scene.instances.size()) continue;
    moved_[instance] = 1;
    const ReuseBox& mesh = meshBounds[scene.instances[instance].mesh];
    for (const glm::mat4* t : {&before, &scene.instances[instance].worldFromObject}) {
      ReuseBox box;
      if (instanceBox(mesh, *t, anchor, box)) {
        boxes_.push_back(box);
      } else if (mesh.lo.x <= mesh.hi.x) {
        active_ = false;  // a transform too large for a finite box: keep nothing rather than guess
        return;
      }
    }
  }
}

void ReuseGate::selectForTile(glm::dvec3 lo, glm::dvec3 hi, double offsetScale, ReuseTile& tile) const {
  for (std::size_t j = 0; j < lights_.size() && j < static_cast<std::size_t>(kMaxLights); ++j) {
    std::vector<std::uint32_t>& mine = tile.boxes[j];
    mine.clear();
    if (!(lo.x <= hi.x)) continue;  // no kept hit in the tile
    ReuseBox path{lo, hi};
    const LightReach& l = lights_[j];
    for (int a = 0; a < 3; ++a) {
      if (l.directional) {
        if (l.towards[a] > 0.0) path.hi[a] = std::numeric_limits<double>::infinity();
        if (l.towards[a] < 0.0) path.lo[a] = -std::numeric_limits<double>::infinity();
      } else {
        path.lo[a] = std::min(path.lo[a], l.at[a] - l.extent[a]);
        path.hi[a] = std::max(path.hi[a], l.at[a] + l.extent[a]);
      }
    }
    // The rays leave from origins offset off the hits (offsetRayOrigin: under 2e-5 of the magnitudes behind
    // them, posMagnitude, which can exceed the hits' own coordinates) and end within rounding of the light;
    // clearOfMoved grows each box by kMargin of the origin's coordinates. Grown by twice kMargin of every
    // magnitude involved, which exceeds the offset and that growth together, no box a ray's test would
    // meet is left out.
    const double scale = std::max({maxAbs(lo), maxAbs(hi), offsetScale, l.directional ? 0.0 : maxAbs(glm::abs(l.at) + l.extent)});
    const double grow = 2.0 * kMargin * scale + 1e-30;
    path.lo -= glm::dvec3(grow);
    path.hi += glm::dvec3(grow);
    for (std::uint32_t b = 0; b < boxes_.size(); ++b) {
      const ReuseBox& box = boxes_[b];
      const bool overlaps = box.lo.x <= path.hi.x && box.hi.x >= path.lo.x && box.lo.y <= path.hi.y &&
                            box.hi.y >= path.lo.y && box.lo.z <= path.hi.z && box.hi.z >= path.lo.z;
      if (overlaps) mine.push_back(b);
    }
  }
}

bool ReuseGate::clearOfMoved(const ReuseTile& tile, std::size_t light, glm::vec3 originW, glm::vec3 dirW,
                             float tFar) const {
  const std::vector<std::uint32_t>& candidates = tile.boxes[light];
  if (candidates.empty()) return true;
  const glm::dvec3 o(originW), d(dirW);
  // The ray's own coordinates add to the rounding (Embree moves its origin into object space).
  const double grow = kMargin * maxAbs(o);
  for (std::uint32_t b : candidates) {
    const ReuseBox grown{boxes_[b].lo - glm::dvec3(grow), boxes_[b].hi + glm::dvec3(grow)};
    if (rayMeetsBox(o, d, static_cast<double>(tFar), grown)) return false;
  }
  return true;
}

}  // namespace tandem::rt
