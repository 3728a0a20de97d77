// makeSolidProxy (tandem/Primitives.h): a mesh that encloses an exact solid, the raster's proxy of it
// (docs/csg.md, "In the raster frame"). Each shape is tessellated to circumscribe it, so the proxy is tight
// (fewer pixels resolved by ray, raster shadows and probes close to the solid) and conservative.
#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/gtc/constants.hpp>

#include "core/Solids.h"
#include "tandem/Primitives.h"

namespace tandem {

namespace {

// A hair outward, so rounding of the proxy's float vertices never puts a facet inside the solid.
constexpr double kOutward = 1.0 + 1e-6;

void append(Mesh& to, const Mesh& from) {
  const auto base = static_cast<std::uint32_t>(to.positions.size());
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  for (std::uint32_t i : from.indices) to.indices.push_back(base + i);
}

// The volume a proxy encloses (the divergence theorem over its triangles; a union's parts summed): the
// tighter of two proxies encloses less. Area would mislead: a die's bounding sphere has less area than its cube,
// and stands far out of its faces.
double volume(const Mesh& m) {
  double v = 0.0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::dvec3 p0(m.positions[m.indices[t]]), p1(m.positions[m.indices[t + 1]]), p2(m.positions[m.indices[t + 2]]);
    v += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
  }
  return std::abs(v);
}

Mesh boxAround(const solid::Bounds& b) {
  const glm::dvec3 size = b.hi - b.lo;
  const glm::dvec3 margin = 1e-5 * size + 1e-30;
  Mesh m = makeBox(glm::vec3(size + 2.0 * margin));
  m.uvs.clear();
  const glm::vec3 centre(0.5 * (b.lo + b.hi));
  for (glm::vec3& p : m.positions) p += centre;
  return m;
}

// A surface of revolution about y from rings of (radius, y, normal's radial and y parts): each ring an n-gon
// whose edges touch the circle of its radius (vertices at radius / cos(π/n)), quads between rings, smooth
// normals. A ring of radius 0 is a single point (an apex).
struct Ring {
  double radius, y, nr, ny;
};
void revolve(Mesh& m, const std::vector<Ring>& rings, int n) {
  const double out = kOutward / std::cos(glm::pi<double>() / n);
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  for (const Ring& r : rings)
    for (int i = 0; i <= n; ++i) {
      const double phi = (i == n ? 0 : i) * glm::two_pi<double>() / n;
      const double c = std::cos(phi), s = -std::sin(phi);
      m.positions.emplace_back(r.radius * out * c, r.y, r.radius * out * s);
      m.normals.push_back(glm::normalize(glm::vec3(r.nr * c, r.ny, r.nr * s)));
    }
  for (std::size_t k = 0; k + 1 < rings.size(); ++k)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = base + static_cast<std::uint32_t>(k * (n + 1) + i), b = a + 1;
      const std::uint32_t c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
      // Counter-clockwise seen from outside (rings go up in y, φ runs clockwise seen from above).
      if (rings[k].radius > 0) m.indices.insert(m.indices.end(), {a, b, c});
      if (rings[k + 1].radius > 0) m.indices.insert(m.indices.end(), {b, d, c});
    }
}

// A flat n-gon cap at height y facing up (+1) or down (-1), circumscribing the circle of `radius`.
void cap(Mesh& m, double radius, double y, float facing, int n) {
  if (!(radius > 0)) return;
  const double out = kOutward / std::cos(glm::pi<double>() / n);
  const auto centre = static_cast<std::uint32_t>(m.positions.size());
  m.positions.emplace_back(0.0f, static_cast<float>(y), 0.0f);
  m.normals.emplace_back(0.0f, facing, 0.0f);
  for (int i = 0; i < n; ++i) {
    const double phi = i * glm::two_pi<double>() / n;
    m.positions.emplace_back(radius * out * std::cos(phi), y, -radius * out * std::sin(phi));
    m.normals.emplace_back(0.0f, facing, 0.0f);
  }
  for (int i = 0; i < n; ++i) {
    const std::uint32_t a = centre + 1 + static_cast<std::uint32_t>(i), b = centre + 1 + static_cast<std::uint32_t>((i + 1) % n);
    if (facing > 0) m.indices.insert(m.indices.end(), {centre, a, b});
    else m.indices.insert(m.indices.end(), {centre, b, a});
  }
}

// One shape, circumscribed. A torus's facets lie outside its tube when the tube they are made on is widened by
// the two chords' sagittas (about the tube and about the axis; its inner side curves away from the hole, so
// chords there fall into the hole, outside the solid).
std::optional<Mesh> shapeProxy(const solid::Primitive& p, int n) {
  const double pi = glm::pi<double>();
  Mesh m;
  switch (p.shape) {
    case solid::Shape::Sphere: {
      const int rings = std::max(n / 2, 2);
      const double out = 1.0 / (std::cos(pi / n) * std::cos(pi / (2.0 * rings)));
      m = makeSphere(static_cast<float>(p.size.x * out * kOutward), n, rings);
      m.uvs.clear();
      return m;
    }
    case solid::Shape::Box:
      m = makeBox(glm::vec3(2.0 * p.size * kOutward));
      m.uvs.clear();
      return m;
    case solid::Shape::Cylinder:
      revolve(m, {{p.size.x, -p.size.y * kOutward, 1, 0}, {p.size.x, p.size.y * kOutward, 1, 0}}, n);
      cap(m, p.size.x, -p.size.y * kOutward, -1.0f, n);
      cap(m, p.size.x, p.size.y * kOutward, 1.0f, n);
      return m;
    case solid::Shape::Cone: {
      const double r0 = p.size.x, r1 = p.size.y, h = p.size.z;
      // The side's outward normal: radial 2h, along y r0 − r1 (the slope of ρ(y)).
      revolve(m, {{r0, -h * kOutward, 2 * h, r0 - r1}, {r1, h * kOutward, 2 * h, r0 - r1}}, n);
      cap(m, r0, -h * kOutward, -1.0f, n);
      cap(m, r1, h * kOutward, 1.0f, n);
      return m;
    }
    case solid::Shape::Torus: {
      const double R = p.size.x, r = p.size.y;
      const int around = n, tube = std::max(n / 2, 3);
      const double widened = (r * (1 - std::cos(pi / tube)) + (R + r) * (1 - std::cos(pi / around))) * 1.25 + r * 1e-6;
      const double rt = r + widened;
      const auto base = static_cast<std::uint32_t>(m.positions.size());
      for (int j = 0; j <= tube; ++j) {
        const double theta = (j == tube ? 0 : j) * 2 * pi / tube;
        for (int i = 0; i <= around; ++i) {
          const double phi = (i == around ? 0 : i) * 2 * pi / around;
          const glm::dvec3 radial(std::cos(phi), 0.0, -std::sin(phi));
          const glm::dvec3 normal = std::cos(theta) * radial + glm::dvec3(0.0, std::sin(theta), 0.0);
          m.positions.emplace_back(R * radial + rt * normal);
          m.normals.emplace_back(normal);
        }
      }
      for (int j = 0; j < tube; ++j)
        for (int i = 0; i < around; ++i) {
          const std::uint32_t a = base + static_cast<std::uint32_t>(j * (around + 1) + i), b = a + 1;
          const std::uint32_t c = a + static_cast<std::uint32_t>(around + 1), d = c + 1;
          m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
      return m;
    }
    case solid::Shape::Plane:
      return std::nullopt;  // unbounded
  }
  return std::nullopt;
}

void transform(Mesh& m, const glm::dmat4& parentFromNode) {
  if (parentFromNode == glm::dmat4(1.0)) return;
  const glm::dmat3 normals = glm::transpose(glm::inverse(glm::dmat3(parentFromNode)));
  for (glm::vec3& p : m.positions) p = glm::vec3(parentFromNode * glm::dvec4(glm::dvec3(p), 1.0));
  for (glm::vec3& n : m.normals) n = glm::vec3(glm::normalize(normals * glm::dvec3(n)));
  // A mirroring transform turns the winding inside out.
  if (glm::determinant(glm::dmat3(parentFromNode)) < 0)
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) std::swap(m.indices[t + 1], m.indices[t + 2]);
}

// Node `index`'s proxy in its parent's space, or nothing when its subtree is unbounded.
std::optional<Mesh> nodeProxy(const solid::Solid& s, std::uint32_t index, int n) {
  const solid::Node& node = s.nodes[index];
  std::optional<Mesh> m;
  switch (node.op) {
    case solid::Op::Leaf:
      m = shapeProxy(node.primitive, n);
      break;
    case solid::Op::Union:
    case solid::Op::Merge: {
      m = Mesh{};
      for (std::uint32_t c : node.children) {
        const std::optional<Mesh> child = nodeProxy(s, c, n);
        if (!child) return std::nullopt;
        append(*m, *child);
      }
      break;
    }
    case solid::Op::Intersection: {
      // Any operand encloses the intersection, and so does the box of their common bounds.
      solid::Bounds b{glm::dvec3(-1e300), glm::dvec3(1e300)};
      for (std::uint32_t c : node.children) {
        const solid::Bounds k = solid::nodeBounds(s, c);
        b = {glm::max(b.lo, k.lo), glm::min(b.hi, k.hi)};
        std::optional<Mesh> child = nodeProxy(s, c, n);
        if (child && (!m || volume(*child) < volume(*m))) m = std::move(child);
      }
      const glm::dvec3 size = b.hi - b.lo;
      if (size.x > 0 && size.y > 0 && size.z > 0 && size.x < 1e15 && size.y < 1e15 && size.z < 1e15) {
        Mesh box = boxAround(b);
        if (!m || volume(box) < volume(*m)) m = std::move(box);
      }
      break;
    }
    case solid::Op::Difference:
      m = nodeProxy(s, node.children.front(), n);
      break;
  }
  if (m) transform(*m, node.parentFromNode);
  return m;
}

}  // namespace

Mesh makeSolidProxy(const solid::Solid& solid, int segments) {
  segments = std::clamp(segments, 8, 1024);
  if (!solid::validate(solid).empty()) return {};
  const solid::Bounds b = solid::bounds(solid);
  const glm::dvec3 size = b.hi - b.lo;
  if (!(size.x > 0 && size.y > 0 && size.z > 0 && size.x < 1e15 && size.y < 1e15 && size.z < 1e15)) return {};
  Mesh box = boxAround(b);
  std::optional<Mesh> tight = nodeProxy(solid, solid.root, segments);
  Mesh m = tight && volume(*tight) < volume(box) ? std::move(*tight) : std::move(box);
  m.name = "solid proxy";
  m.exact = solid;
  return m;
}

}  // namespace tandem
