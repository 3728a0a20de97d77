// coplanarOverlaps (tandem/Scene.h): faces of two instances that lie in one plane and overlap fight for
// the same depth, so the shared area flickers between them from frame to frame and pixel to pixel (a box
// standing exactly on a floor: its bottom face and the floor). Checked where it is cheap: meshes made of
// a few planes (boxes, planes, quads), compared through a hash of their world planes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <unordered_map>

#include "tandem/Scene.h"

namespace tandem {

namespace {

// One plane of a mesh: its unit normal, offset, and its triangles' vertices (object space).
struct PlaneGroup {
  glm::dvec3 n{0.0};
  double d = 0.0;
  std::vector<glm::dvec3> corners;  // three per triangle
};

// The planes of a mesh, or none when it has more than maxPlanes (curved: not checked).
std::vector<PlaneGroup> planesOf(const Mesh& mesh, std::size_t maxPlanes) {
  std::vector<PlaneGroup> groups;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    if (!(len > 0.0)) continue;  // degenerate: covers no area
    n /= len;
    const double d = glm::dot(n, a);
    const double scale = std::max({1.0, std::abs(d), glm::length(b - a), glm::length(c - a)});
    auto same = [&](const PlaneGroup& g) { return glm::dot(g.n, n) > 1.0 - 1e-9 && std::abs(g.d - d) <= 1e-7 * scale; };
    auto it = std::find_if(groups.begin(), groups.end(), same);
    if (it == groups.end()) {
      if (groups.size() == maxPlanes) return {};
      groups.push_back({n, d, {}});
      it = groups.end() - 1;
    }
    it->corners.insert(it->corners.end(), {a, b, c});
  }
  return groups;
}

// A plane in world space with its triangles projected into 2D coordinates of the plane.
struct WorldPlane {
  std::size_t instance = 0;
  glm::dvec3 n{0.0};  // canonical sign: faces of either side of one plane compare equal
  bool flipped = false;  // the face's own normal is −n
  double d = 0.0;
  double extent = 0.0;
  std::vector<glm::dvec3> corners;  // world space, three per triangle
};

glm::dvec3 canonical(glm::dvec3 n, double& d) {
  // The first clearly non-zero component positive: a box's bottom (−y) and a floor's top (+y) are one plane.
  for (int i = 0; i < 3; ++i) {
    if (std::abs(n[i]) > 1e-9) {
      if (n[i] < 0.0) {
        n = -n;
        d = -d;
      }
      break;
    }
  }
  return n;
}

// Strict 2D overlap of two triangles (shared edges and touching corners do not count): no separating axis
// among their edge normals.
bool trianglesOverlap(const std::array<glm::dvec2, 3>& p, const std::array<glm::dvec2, 3>& q, double eps) {
  auto separated = [&](const std::array<glm::dvec2, 3>& a, const std::array<glm::dvec2, 3>& b) {
    for (int i = 0; i < 3; ++i) {
      const glm::dvec2 e = a[(i + 1) % 3] - a[i];
      const glm::dvec2 axis(-e.y, e.x);
      double aMin = 1e300, aMax = -1e300, bMin = 1e300, bMax = -1e300;
      for (int k = 0; k < 3; ++k) {
        aMin = std::min(aMin, glm::dot(axis, a[k]));
        aMax = std::max(aMax, glm::dot(axis, a[k]));
        bMin = std::min(bMin, glm::dot(axis, b[k]));
        bMax = std::max(bMax, glm::dot(axis, b[k]));
      }
      const double tol = eps * glm::length(axis);
      if (aMax <= bMin + tol || bMax <= aMin + tol) return true;
    }
    return false;
  };
  return !separated(p, q) && !separated(q, p);
}

bool planesOverlap(const WorldPlane& a, const WorldPlane& b) {
  // 2D coordinates in the plane: two axes orthogonal to the normal.
  const glm::dvec3 helper = std::abs(a.n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(a.n, helper));
  const glm::dvec3 v = glm::cross(a.n, u);
  auto project = [&](const std::vector<glm::dvec3>& c, std::size_t t) {
    return std::array<glm::dvec2, 3>{glm::dvec2(glm::dot(c[t], u), glm::dot(c[t], v)),
                                     glm::dvec2(glm::dot(c[t + 1], u), glm::dot(c[t + 1], v)),
                                     glm::dvec2(glm::dot(c[t + 2], u), glm::dot(c[t + 2], v))};
  };
  // Triangles that meet along an edge may overlap by float rounding of their vertices (1e-7 relative): a
  // sliver thinner than 1e-5 of the faces' size is not an area two surfaces can be seen fighting over.
  const double eps = 1e-5 * std::max({1.0, a.extent, b.extent});
  for (std::size_t i = 0; i + 2 < a.corners.size(); i += 3) {
    const auto p = project(a.corners, i);
    for (std::size_t j = 0; j + 2 < b.corners.size(); j += 3)
      if (trianglesOverlap(p, project(b.corners, j), eps)) return true;
  }
  return false;
}

// Every plane of every instance whose mesh has at most maxPlanes planes, in world space.
std::vector<WorldPlane> worldPlanes(const Scene& scene, std::size_t maxPlanes) {
  std::vector<std::vector<PlaneGroup>> meshPlanes(scene.meshes.size());
  std::vector<bool> done(scene.meshes.size(), false);
  std::vector<WorldPlane> planes;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.mesh >= scene.meshes.size()) continue;
    if (!done[inst.mesh]) {
      meshPlanes[inst.mesh] = planesOf(scene.meshes[inst.mesh], maxPlanes);
      done[inst.mesh] = true;
    }
    const glm::dmat4 m(inst.worldFromObject);
    const glm::dmat3 normalM = glm::transpose(glm::inverse(glm::dmat3(m)));
    for (const PlaneGroup& g : meshPlanes[inst.mesh]) {
      WorldPlane w;
      w.instance = i;
      glm::dvec3 n = normalM * g.n;
      const double len = glm::length(n);
      if (!(len > 0.0) || !std::isfinite(len)) continue;
      n /= len;
      w.corners.reserve(g.corners.size());
      glm::dvec3 lo(1e300), hi(-1e300);
      for (const glm::dvec3& c : g.corners) {
        const glm::dvec3 p = glm::dvec3(m * glm::dvec4(c, 1.0));
        w.corners.push_back(p);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
      double d = glm::dot(n, w.corners[0]);
      w.n = canonical(n, d);
      w.flipped = glm::dot(w.n, n) < 0.0;
      w.d = d;
      w.extent = glm::length(hi - lo);
      planes.push_back(std::move(w));
    }
  }
  return planes;
}

std::string overlapMessage(const Scene& scene, std::pair<std::size_t, std::size_t> pair, const WorldPlane& a) {
  std::ostringstream s;
  const Instance& ia = scene.instances[pair.first];
  const Instance& ib = scene.instances[pair.second];
  s << "instances " << pair.first << " '" << ia.name << "' and " << pair.second << " '" << ib.name
    << "' have overlapping faces in one plane (normal (" << a.n.x << ", " << a.n.y << ", " << a.n.z
    << "), offset " << a.d << "): the shared area flickers between them (depth fighting); move one apart "
    << "or into the other";
  return s.str();
}

}  // namespace

std::vector<std::string> coplanarOverlaps(const Scene& scene, std::size_t maxPlanes) {
  const std::vector<WorldPlane> planes = worldPlanes(scene, maxPlanes);
  // Planes that may coincide share a cell: the normal rounded to 1e-6 and the offset to a cell of the
  // tolerance; the neighbouring offset cells are looked at too.
  auto tolerance = [](const WorldPlane& p) { return 1e-6 * std::max({1.0, std::abs(p.d), p.extent}); };
  std::map<std::array<std::int64_t, 4>, std::vector<std::size_t>> cells;
  auto key = [](const WorldPlane& p, std::int64_t dCell) {
    return std::array<std::int64_t, 4>{std::llround(p.n.x * 1e6), std::llround(p.n.y * 1e6), std::llround(p.n.z * 1e6),
                                       dCell};
  };
  const double cell = 1e-4;
  for (std::size_t i = 0; i < planes.size(); ++i)
    cells[key(planes[i], std::llround(planes[i].d / cell))].push_back(i);
  auto seeThrough = [&](std::size_t instance) {
    const std::uint32_t mat = scene.instances[instance].material;
    if (mat >= scene.materials.size()) return false;
    const Material& m = scene.materials[mat];
    return m.kt > 0.0f || m.alphaMode != AlphaMode::Opaque || m.opacity < 1.0f;
  };
  std::vector<std::string> out;
  std::map<std::pair<std::size_t, std::size_t>, bool> reported;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const WorldPlane& a = planes[i];
    const std::int64_t dc = std::llround(a.d / cell);
    for (std::int64_t k = dc - 1; k <= dc + 1; ++k) {
      auto it = cells.find(key(a, k));
      if (it == cells.end()) continue;
      for (std::size_t j : it->second) {
        if (j <= i) continue;
        const WorldPlane& b = planes[j];
        if (a.instance == b.instance) continue;
        const auto pair = std::minmax(a.instance, b.instance);
        if (reported.count(pair)) continue;
        if (glm::dot(a.n, b.n) < 1.0 - 1e-9 || std::abs(a.d - b.d) > std::max(tolerance(a), tolerance(b))) continue;
        // Faces back to back (a box standing on a floor) can only be seen fighting through a surface that
        // lets light through; faces that look the same way fight in plain view.
        if (a.flipped != b.flipped && !seeThrough(a.instance) && !seeThrough(b.instance)) continue;
        if (!planesOverlap(a, b)) continue;
        reported[pair] = true;
        out.push_back(overlapMessage(scene, pair, a));
      }
    }
  }
  return out;
}

}  // namespace tandem
