// makeSolidProxy (tandem/Primitives.h; docs/csg.md "In the raster frame"): the raster's proxy of an exact solid
// must enclose it — every ray that meets the solid meets the proxy no later — for each shape and for CSG trees
// with transforms at every node, and should be tight (about the solid's own area for a single shape).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "core/Solids.h"
#include "tandem/Primitives.h"

namespace tandem {
namespace {

using solid::Op;
using solid::Shape;

solid::Solid leaf(Shape shape, glm::dvec3 size) {
  solid::Solid s;
  s.nodes.push_back({});
  s.nodes[0].primitive = {shape, size};
  return s;
}

// The first hit of a ray on the proxy's triangles (Möller–Trumbore in double), or infinity.
double proxyHit(const Mesh& m, glm::dvec3 o, glm::dvec3 d) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::dvec3 p0(m.positions[m.indices[t]]), p1(m.positions[m.indices[t + 1]]), p2(m.positions[m.indices[t + 2]]);
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
    const double det = glm::dot(e1, pv);
    if (std::abs(det) < 1e-300) continue;
    const glm::dvec3 tv = o - p0;
    const double u = glm::dot(tv, pv) / det;
    if (u < 0 || u > 1) continue;
    const glm::dvec3 qv = glm::cross(tv, e1);
    const double v = glm::dot(d, qv) / det;
    if (v < 0 || u + v > 1) continue;
    const double h = glm::dot(e2, qv) / det;
    if (h > 0 && h < best) best = h;
  }
  return best;
}

// Rays from points around the solid towards points inside its bounds: each one that crosses the solid crosses
// the proxy no later. Returns how many crossed the solid (the check is not vacuous).
int expectEncloses(const solid::Solid& s, const Mesh& proxy, int rays, const char* what) {
  const solid::Bounds b = solid::bounds(s);
  const glm::dvec3 centre = 0.5 * (b.lo + b.hi), half = 0.5 * (b.hi - b.lo);
  const double reach = 3.0 * glm::length(half);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int crossing = 0;
  for (int i = 0; i < rays; ++i) {
    const glm::dvec3 from = centre + reach * glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::dvec3 to = centre + half * glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 d = glm::normalize(to - from);
    solid::Crossing c;
    if (!solid::firstHit(solid::intersect(s, {from, d}), 0.0, std::numeric_limits<double>::infinity(), c)) continue;
    ++crossing;
    const double t = proxyHit(proxy, from, d);
    EXPECT_LE(t, c.t * (1.0 + 1e-9)) << what << ": ray " << i << " meets the solid before (or without) its proxy";
  }
  return crossing;
}

// Each triangle faces the way its vertices' normals say (outward).
void expectOutwardWinding(const Mesh& m, const char* what) {
  int wrong = 0;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const glm::vec3 p0 = m.positions[m.indices[t]], p1 = m.positions[m.indices[t + 1]], p2 = m.positions[m.indices[t + 2]];
    const glm::vec3 ng = glm::cross(p1 - p0, p2 - p0);
    const glm::vec3 n = m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] + m.normals[m.indices[t + 2]];
    wrong += glm::dot(ng, n) < 0.0f ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0) << what;
}

TEST(SolidProxy, EachShapeIsEnclosedTightlyAndWoundOutward) {
  struct Case {
    const char* name;
    solid::Solid s;
    double area;  // the solid's own surface area
  };
  const double pi = 3.141592653589793;
  const Case cases[] = {
      {"sphere", leaf(Shape::Sphere, {0.7, 0, 0}), 4 * pi * 0.49},
      {"box", leaf(Shape::Box, {0.5, 0.25, 1.0}), 8 * (0.5 * 0.25 + 0.25 * 1.0 + 0.5 * 1.0)},
      {"cylinder", leaf(Shape::Cylinder, {0.4, 0.8, 0}), 2 * pi * 0.4 * 1.6 + 2 * pi * 0.16},
      {"cone", leaf(Shape::Cone, {0.6, 0.0, 0.5}), pi * 0.6 * std::sqrt(0.36 + 1.0) + pi * 0.36},
      {"frustum", leaf(Shape::Cone, {0.3, 0.6, 0.5}), pi * 0.9 * std::sqrt(0.09 + 1.0) + pi * (0.09 + 0.36)},
      {"torus", leaf(Shape::Torus, {1.0, 0.3, 0}), 4 * pi * pi * 0.3},
      {"thin torus", leaf(Shape::Torus, {1.0, 0.9, 0}), 4 * pi * pi * 0.9},
  };
  for (const Case& c : cases) {
    const Mesh proxy = makeSolidProxy(c.s);
    ASSERT_TRUE(proxy.exact.has_value()) << c.name;
    ASSERT_FALSE(proxy.indices.empty()) << c.name;
    EXPECT_GT(expectEncloses(c.s, proxy, 3000, c.name), 500) << c.name;
    expectOutwardWinding(proxy, c.name);
    double area = 0.0;
    for (std::size_t t = 0; t + 2 < proxy.indices.size(); t += 3)
      area += 0.5 * glm::length(glm::cross(glm::dvec3(proxy.positions[proxy.indices[t + 1]] - proxy.positions[proxy.indices[t]]),
                                           glm::dvec3(proxy.positions[proxy.indices[t + 2]] - proxy.positions[proxy.indices[t]])));
    EXPECT_GE(area, c.area * 0.999) << c.name;
    EXPECT_LE(area, c.area * 1.03) << c.name << ": a tight proxy";
  }
}

TEST(SolidProxy, TreesWithTransformsAreEnclosed) {
  // A die (a rounded cube less pips), a lens (two spheres intersected), a union of a rotated torus and a scaled
  // cone, a difference cut by a half-space, and a mirrored node (its winding turned back out).
  std::vector<std::pair<const char*, solid::Solid>> trees;
  {
    solid::Solid s;
    s.nodes.resize(5);
    s.nodes[0] = {Op::Difference, {}, {1, 4}, glm::rotate(glm::dmat4(1.0), 0.4, glm::dvec3(0.3, 1, 0.2))};
    s.nodes[1] = {Op::Intersection, {}, {2, 3}, glm::dmat4(1.0)};
    s.nodes[2].primitive = {Shape::Box, glm::dvec3(0.5)};
    s.nodes[3].primitive = {Shape::Sphere, glm::dvec3(0.68)};
    s.nodes[4].primitive = {Shape::Sphere, glm::dvec3(0.09)};
    s.nodes[4].parentFromNode = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0.53, 0));
    trees.emplace_back("die", s);
  }
  {
    solid::Solid s;
    s.nodes.resize(3);
    s.nodes[0] = {Op::Intersection, {}, {1, 2}, glm::scale(glm::dmat4(1.0), glm::dvec3(0.75))};
    s.nodes[1].primitive = {Shape::Sphere, glm::dvec3(1.0)};
    s.nodes[1].parentFromNode = glm::translate(glm::dmat4(1.0), glm::dvec3(0, -0.82, 0));
    s.nodes[2].primitive = {Shape::Sphere, glm::dvec3(1.0)};
    s.nodes[2].parentFromNode = glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0.82, 0));
    trees.emplace_back("lens", s);
  }
  {
    solid::Solid s;
    s.nodes.resize(3);
    s.nodes[0] = {Op::Merge, {}, {1, 2}, glm::dmat4(1.0)};
    s.nodes[1].primitive = {Shape::Torus, {0.8, 0.2, 0}};
    s.nodes[1].parentFromNode = glm::rotate(glm::dmat4(1.0), 1.1, glm::dvec3(1, 0, 0));
    s.nodes[2].primitive = {Shape::Cone, {0.5, 0.1, 0.6}};
    s.nodes[2].parentFromNode = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0.2, -0.1)), glm::dvec3(1, 2, 0.5));
    trees.emplace_back("merge", s);
  }
  {
    solid::Solid s;
    s.nodes.resize(3);
    s.nodes[0] = {Op::Intersection, {}, {1, 2}, glm::dmat4(1.0)};
    s.nodes[1].primitive = {Shape::Cylinder, {0.5, 1.0, 0}};
    s.nodes[2].primitive = {Shape::Plane, glm::dvec3(0.0)};
    s.nodes[2].parentFromNode = glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0, 0, 1));
    trees.emplace_back("half-space cut", s);
  }
  {
    solid::Solid s = leaf(Shape::Torus, {1.0, 0.25, 0});
    s.nodes[0].parentFromNode = glm::scale(glm::dmat4(1.0), glm::dvec3(-1, 1, 1));
    trees.emplace_back("mirrored", s);
  }
  for (const auto& [name, s] : trees) {
    ASSERT_EQ(solid::validate(s), "") << name;
    const Mesh proxy = makeSolidProxy(s);
    ASSERT_FALSE(proxy.indices.empty()) << name;
    EXPECT_GT(expectEncloses(s, proxy, 2000, name), 300) << name;
    expectOutwardWinding(proxy, name);
  }
}

TEST(SolidProxy, UnboundedOrInvalidSolidsHaveNone) {
  EXPECT_TRUE(makeSolidProxy(leaf(Shape::Plane, glm::dvec3(0.0))).indices.empty());
  EXPECT_FALSE(makeSolidProxy(leaf(Shape::Plane, glm::dvec3(0.0))).exact.has_value());
  EXPECT_TRUE(makeSolidProxy(leaf(Shape::Sphere, glm::dvec3(-1.0))).indices.empty());
}

}  // namespace
}  // namespace tandem
