// Exact analytic solids and CSG along rays (core/Solids.h): closed-form hits of each shape; random rays
// against random shapes at scales 1e-4..1e4 and 1e5 from the origin, every crossing on the surface within
// the stated bound and the inside spans agreeing with a point-membership walk (no false hit or miss beyond
// it); the CSG operations' classification tables (union keeps inner surfaces, merge does not, intersection,
// difference, coincident faces); rays that start inside; validation.
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/Solids.h"

namespace tandem::solid {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Solid single(Shape shape, glm::dvec3 size, glm::dmat4 place = glm::dmat4(1.0)) {
  Solid s;
  Node n;
  n.primitive = {shape, size};
  n.parentFromNode = place;
  s.nodes.push_back(n);
  return s;
}

// A tree: node 0 the operation on the leaves that follow.
Solid operation(Op op, std::vector<std::pair<Primitive, glm::dmat4>> leaves) {
  Solid s;
  Node root;
  root.op = op;
  s.nodes.push_back(root);
  for (const auto& [p, m] : leaves) {
    Node leaf;
    leaf.primitive = p;
    leaf.parentFromNode = m;
    s.nodes[0].children.push_back(static_cast<std::uint32_t>(s.nodes.size()));
    s.nodes.push_back(leaf);
  }
  return s;
}

glm::dmat4 at(glm::dvec3 t) { return glm::translate(glm::dmat4(1.0), t); }

std::vector<double> ts(const Hits& h) {
  std::vector<double> out;
  for (const Crossing& c : h.crossings) out.push_back(c.t);
  return out;
}

void expectTs(const Hits& h, std::vector<double> expected, double tolerance, const char* what) {
  const std::vector<double> got = ts(h);
  ASSERT_EQ(got.size(), expected.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], tolerance) << what << " crossing " << i;
}

TEST(Solids, EachShapeMeetsItsClosedForm) {
  const Ray down{{0.25, 10.0, 0.0}, {0.0, -1.0, 0.0}};
  // Sphere r = 2 along x = 0.25: y = ±√(4 − 1/16).
  const double y = std::sqrt(4.0 - 0.0625);
  expectTs(intersect(single(Shape::Sphere, glm::dvec3(2.0)), down), {10.0 - y, 10.0 + y}, 1e-12, "sphere");
  // Box 1 × 2 × 3 half sizes: y faces at ±2.
  expectTs(intersect(single(Shape::Box, {1.0, 2.0, 3.0}), down), {8.0, 12.0}, 1e-12, "box");
  // Cylinder r = 1, h = 1.5 along its axis: the caps; across it (along x at y = 0.5): x = ±1.
  expectTs(intersect(single(Shape::Cylinder, {1.0, 1.5, 0.0}), down), {8.5, 11.5}, 1e-12, "cylinder caps");
  const Ray across{{-5.0, 0.5, 0.0}, {2.0, 0.0, 0.0}};  // a direction of length 2: t in half units
  expectTs(intersect(single(Shape::Cylinder, {1.0, 1.5, 0.0}), across), {2.0, 3.0}, 1e-12, "cylinder side");
  // Cone r0 = 1 at y = −1, apex at y = +1: across at y = 0.5 the radius is 0.25.
  expectTs(intersect(single(Shape::Cone, {1.0, 0.0, 1.0}), across), {2.375, 2.625}, 1e-12, "cone side");
  // Down its axis: the apex (y = 1) and the base (y = −1).
  const Ray axis{{0.0, 10.0, 0.0}, {0.0, -1.0, 0.0}};
  expectTs(intersect(single(Shape::Cone, {1.0, 0.0, 1.0}), axis), {9.0, 11.0}, 1e-12, "cone axis");
  // Torus R = 2, r = 0.5 along the x axis: x = ±2.5 and ±1.5 — two spans.
  const Ray diameter{{-10.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
  const Hits torus = intersect(single(Shape::Torus, {2.0, 0.5, 0.0}), diameter);
  expectTs(torus, {7.5, 8.5, 11.5, 12.5}, 1e-9, "torus");
  EXPECT_EQ(torus.spans.size(), 2u);
  // Down through the tube at x = 2: y = ±0.5.
  expectTs(intersect(single(Shape::Torus, {2.0, 0.5, 0.0}), Ray{{2.0, 10.0, 0.0}, {0.0, -1.0, 0.0}}), {9.5, 10.5}, 1e-9,
           "torus tube");
  // Half-space y <= 0: one crossing, entering from above; a ray along it inside has no crossing, all inside.
  const Hits plane = intersect(single(Shape::Plane, {}), down);
  expectTs(plane, {10.0}, 0.0, "plane");
  ASSERT_EQ(plane.spans.size(), 1u);
  EXPECT_EQ(plane.spans[0].t1, kInf);
  const Hits along = intersect(single(Shape::Plane, {}), Ray{{0.0, -1.0, 0.0}, {1.0, 0.0, 0.0}});
  EXPECT_TRUE(along.crossings.empty());
  ASSERT_EQ(along.spans.size(), 1u);
  EXPECT_EQ(along.spans[0].t0, -kInf);
}

// The implicit distance of a point to a primitive's surface, in its units (0 on the surface).
double surfaceGap(const Primitive& p, const glm::dvec3& q) {
  switch (p.shape) {
    case Shape::Sphere: return std::abs(glm::length(q) - p.size.x);
    case Shape::Box: {
      double gap = kInf;
      for (int a = 0; a < 3; ++a) {
        glm::dvec3 inside = glm::abs(q);
        bool onFace = true;
        for (int b = 0; b < 3; ++b)
          if (b != a && inside[b] > p.size[b] * (1.0 + 1e-9)) onFace = false;
        if (onFace) gap = std::min(gap, std::abs(inside[a] - p.size[a]));
      }
      return gap;
    }
    case Shape::Cylinder:
    case Shape::Cone: {
      const bool cone = p.shape == Shape::Cone;
      const double h = cone ? p.size.z : p.size.y;
      const double r0 = p.size.x, r1 = cone ? p.size.y : p.size.x;
      const double rho = r0 + (r1 - r0) * (q.y + h) / (2.0 * h);
      const double radial = std::sqrt(q.x * q.x + q.z * q.z);
      const double side = std::abs(radial - rho) / std::sqrt(1.0 + std::pow((r1 - r0) / (2.0 * h), 2.0));
      const double cap = radial <= std::max(r0, r1) * (1.0 + 1e-9) ? std::abs(std::abs(q.y) - h) : kInf;
      return std::min(std::abs(q.y) <= h * (1.0 + 1e-9) ? side : kInf, cap);
    }
    case Shape::Torus: {
      const double ring = std::sqrt(q.x * q.x + q.z * q.z) - p.size.x;
      return std::abs(std::sqrt(ring * ring + q.y * q.y) - p.size.y);
    }
    case Shape::Plane: return std::abs(q.y);
  }
  return kInf;
}

Primitive randomPrimitive(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.3, 1.5);
  switch (rng() % 5) {
    case 0: return {Shape::Sphere, glm::dvec3(u(rng))};
    case 1: return {Shape::Box, {u(rng), u(rng), u(rng)}};
    case 2: return {Shape::Cylinder, {u(rng), u(rng), 0.0}};
    case 3: return {Shape::Cone, {u(rng), rng() % 2 ? 0.0 : u(rng) * 0.5, u(rng)}};
    default: {
      const double R = u(rng) + 0.5;
      return {Shape::Torus, {R, R * std::uniform_real_distribution<double>(0.1, 0.6)(rng), 0.0}};
    }
  }
}

TEST(Solids, RandomRaysFindEverySurfaceExactlyAtAnyScaleAndFarFromTheOrigin) {
  // Every crossing lies on the surface within 1e-9 of the solid's size (relative to the ray's coordinates
  // far from the origin), and the spans agree with membership sampled along the ray: a sample further
  // than 1e-6 of the chord from a span's end is inside exactly when the spans say so.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int crossings = 0, samples = 0;
  double worstGap = 0.0;
  for (double scale : {1e-4, 1.0, 1e4})
    for (glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e5, -2e5, 3e5)})
      for (int trial = 0; trial < 200; ++trial) {
        Primitive p = randomPrimitive(rng);
        p.size *= scale;
        const glm::dvec3 centre = offset + scale * glm::dvec3(unit(rng), unit(rng), unit(rng)) * 0.3;
        const Solid s = single(p.shape, p.size, at(centre));
        // A ray from a point around the solid towards another point near it (often through it).
        const glm::dvec3 from = centre + scale * 4.0 * glm::dvec3(unit(rng), unit(rng), unit(rng));
        const glm::dvec3 to = centre + scale * 0.8 * glm::dvec3(unit(rng), unit(rng), unit(rng));
        const Ray ray{from, (to - from) * (0.5 + 0.5 * std::abs(unit(rng)))};
        const Hits h = intersect(s, ray);
        // Surface: the crossing's point in the primitive's space.
        const double coordinateScale = (glm::length(from) + glm::length(centre)) / scale;
        for (const Crossing& c : h.crossings) {
          const glm::dvec3 q = ray.origin + c.t * ray.dir - centre;
          const double gap = surfaceGap(p, q) / scale;
          worstGap = std::max(worstGap, gap / (1.0 + coordinateScale * 1e-7));
          EXPECT_LT(gap, 1e-9 * (1.0 + coordinateScale)) << "shape " << int(p.shape) << " scale " << scale;
          ++crossings;
        }
        // Spans against membership along the chord through the solid's bounds.
        const double length = glm::length(ray.dir);
        const double tMid = glm::dot(centre - from, ray.dir) / (length * length);
        const double reach = 3.0 * scale / length;
        for (int k = 0; k <= 400; ++k) {
          const double t = tMid - reach + 2.0 * reach * k / 400.0;
          const glm::dvec3 q = ray.origin + t * ray.dir;
          double nearest = kInf;
          bool inSpan = false;
          for (const Span& sp : h.spans) {
            inSpan = inSpan || (t >= sp.t0 && t <= sp.t1);
            nearest = std::min({nearest, std::abs(t - sp.t0), std::abs(t - sp.t1)});
          }
          if (nearest * length < 1e-6 * scale * (1.0 + coordinateScale * 1e-3)) continue;  // at an end: either way
          ++samples;
          EXPECT_EQ(inSpan, contains(s, q)) << "shape " << int(p.shape) << " scale " << scale << " offset " << offset.x
                                            << " t " << t;
        }
      }
  std::printf("%d crossings on their surfaces (worst gap %.2e of the size), %d samples classified\n", crossings,
              worstGap, samples);
  EXPECT_GT(crossings, 1000);
}

TEST(Solids, CsgOperationsClassifyTheirOperandsSurfaces) {
  const Primitive sphere{Shape::Sphere, glm::dvec3(1.0)};
  const Ray axis{{-10.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
  // Two unit spheres 1 apart along x: A = [−1, 1], B = [0, 2] on the axis.
  const std::vector<std::pair<Primitive, glm::dmat4>> two{{sphere, at({0, 0, 0})}, {sphere, at({1, 0, 0})}};
  // union keeps every surface (glass shows the inner ones), merge only the outer ones.
  expectTs(intersect(operation(Op::Union, two), axis), {9.0, 10.0, 11.0, 12.0}, 1e-12, "union");
  expectTs(intersect(operation(Op::Merge, two), axis), {9.0, 12.0}, 1e-12, "merge");
  // intersection: the lens [0, 1]: B's front, A's back.
  const Hits lens = intersect(operation(Op::Intersection, two), axis);
  expectTs(lens, {10.0, 11.0}, 1e-12, "intersection");
  EXPECT_EQ(lens.crossings[0].leaf, 2u);
  EXPECT_EQ(lens.crossings[1].leaf, 1u);
  EXPECT_TRUE(lens.crossings[0].entering(axis.dir));
  EXPECT_FALSE(lens.crossings[1].entering(axis.dir));
  // difference A − B: [−1, 0]; the cut at 0 is B's surface turned inside out (its normal now faces −x).
  const Hits bite = intersect(operation(Op::Difference, two), axis);
  expectTs(bite, {9.0, 10.0}, 1e-12, "difference");
  EXPECT_EQ(bite.crossings[1].leaf, 2u);
  EXPECT_NEAR(bite.crossings[1].normal.x, 1.0, 1e-12);  // B's front (−x) turned: the bite's exit faces +x
  EXPECT_FALSE(bite.crossings[1].entering(axis.dir));
  ASSERT_EQ(bite.spans.size(), 1u);
  EXPECT_NEAR(bite.spans[0].t1, 10.0, 1e-12);
  // The die: a box with a spherical dimple cut in its top face. Straight down into the dimple: its floor.
  const Solid die = operation(Op::Difference, {{{Shape::Box, glm::dvec3(0.5)}, at({0, 0, 0})},
                                               {{Shape::Sphere, glm::dvec3(0.12)}, at({0, 0.5, 0})}});
  const Ray down{{0.0, 5.0, 0.0}, {0.0, -1.0, 0.0}};
  Crossing hit;
  ASSERT_TRUE(firstHit(intersect(die, down), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 5.0 - 0.38, 1e-12);
  EXPECT_NEAR(hit.normal.y, 1.0, 1e-12);
  EXPECT_TRUE(hit.entering(down.dir));
  // Beside the dimple: the box's own top.
  ASSERT_TRUE(firstHit(intersect(die, Ray{{0.3, 5.0, 0.0}, {0.0, -1.0, 0.0}}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 4.5, 1e-12);
}

TEST(Solids, RaysStartingInsideLeaveThroughTheRightSurface) {
  // A hollow glass shell: a sphere of radius 1 minus one of 0.8. From the centre (inside the hollow, outside
  // the solid) the first crossing enters the shell at 0.8; from inside the shell's wall it leaves at 1.
  const Solid shell = operation(Op::Difference, {{{Shape::Sphere, glm::dvec3(1.0)}, at({0, 0, 0})},
                                                 {{Shape::Sphere, glm::dvec3(0.8)}, at({0, 0, 0})}});
  const glm::dvec3 x(1.0, 0.0, 0.0);
  Crossing hit;
  ASSERT_TRUE(firstHit(intersect(shell, Ray{{0.0, 0.0, 0.0}, x}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 0.8, 1e-12);
  EXPECT_TRUE(hit.entering(x));
  EXPECT_NEAR(hit.normal.x, -1.0, 1e-12);  // the inner surface faces the hollow
  ASSERT_TRUE(firstHit(intersect(shell, Ray{{0.9, 0.0, 0.0}, x}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 0.1, 1e-12);
  EXPECT_FALSE(hit.entering(x));
  // Through the wall from inside it, going in: it leaves into the hollow at 0.8.
  ASSERT_TRUE(firstHit(intersect(shell, Ray{{0.9, 0.0, 0.0}, -x}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 0.1, 1e-12);
  EXPECT_FALSE(hit.entering(-x));
  EXPECT_TRUE(contains(shell, {0.9, 0.0, 0.0}));
  EXPECT_FALSE(contains(shell, {0.5, 0.0, 0.0}));
  // A half-space cut: a sphere minus y > 0 (a dome turned over, its flat face at y = 0, inside the plane's
  // complement). From below the cut face inside the solid, upwards: it leaves through the flat face.
  const Solid bowl = operation(Op::Intersection, {{{Shape::Sphere, glm::dvec3(1.0)}, at({0, 0, 0})},
                                                  {{Shape::Plane, glm::dvec3(0.0)}, at({0, 0, 0})}});
  ASSERT_TRUE(firstHit(intersect(bowl, Ray{{0.2, -0.5, 0.0}, {0.0, 1.0, 0.0}}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 0.5, 1e-12);
  EXPECT_NEAR(hit.normal.y, 1.0, 1e-12);
  EXPECT_FALSE(hit.entering({0.0, 1.0, 0.0}));
}

TEST(Solids, CoincidentFacesFollowTheDocumentedRule) {
  const Primitive cube{Shape::Box, glm::dvec3(0.5)};
  const Ray along{{-5.0, 0.1, 0.2}, {1.0, 0.0, 0.0}};
  // Two cubes touching face to face at x = 0.5: merge has no wall between them, union keeps it.
  const std::vector<std::pair<Primitive, glm::dmat4>> touching{{cube, at({0, 0, 0})}, {cube, at({1, 0, 0})}};
  expectTs(intersect(operation(Op::Merge, touching), along), {4.5, 6.5}, 1e-12, "merge of touching cubes");
  expectTs(intersect(operation(Op::Union, touching), along), {4.5, 5.5, 5.5, 6.5}, 1e-12, "union of touching cubes");
  // A cube intersected with itself: its surfaces stay (each on the other's boundary counts as inside it).
  const Hits self = intersect(operation(Op::Intersection, {{cube, at({0, 0, 0})}, {cube, at({0, 0, 0})}}), along);
  Crossing hit;
  ASSERT_TRUE(firstHit(self, 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 4.5, 1e-12);
  // A cut flush with the top face: the subtracted operand wins, the top is open where it cuts. Down through
  // the cut: the first surface is the cut's floor (the slot's bottom at y = 0.3), not the old top at 0.5.
  const Solid slot = operation(Op::Difference, {{cube, at({0, 0, 0})},
                                                {{Shape::Box, {0.2, 0.1, 0.6}}, at({0, 0.4, 0})}});
  ASSERT_TRUE(firstHit(intersect(slot, Ray{{0.0, 5.0, 0.0}, {0.0, -1.0, 0.0}}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 4.7, 1e-12);
  EXPECT_NEAR(hit.normal.y, 1.0, 1e-12);
  // The same far from the origin and scaled down: the rule holds with the tolerance relative to the ray.
  const glm::dvec3 far(1e5, 1e5, -1e5);
  const double s = 1e-3;
  const Solid farSlot = operation(Op::Difference, {{{Shape::Box, glm::dvec3(0.5 * s)}, at(far)},
                                                   {{Shape::Box, glm::dvec3(0.2, 0.1, 0.6) * s}, at(far + glm::dvec3(0, 0.4 * s, 0))}});
  ASSERT_TRUE(firstHit(intersect(farSlot, Ray{far + glm::dvec3(0.0, 5.0 * s, 0.0), {0.0, -s, 0.0}}), 0.0, kInf, hit));
  EXPECT_NEAR(hit.t, 4.7, 1e-6);
}

TEST(Solids, RandomTreesAgreeWithPointMembership) {
  // Nested trees of random shapes and operations, transformed at every node: along random rays, the spans
  // and the crossings' inside/outside agree with contains() sampled between them.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 150; ++trial) {
    Solid s;
    const Op ops[] = {Op::Union, Op::Merge, Op::Intersection, Op::Difference};
    std::function<std::uint32_t(int)> build = [&](int depth) -> std::uint32_t {
      const auto index = static_cast<std::uint32_t>(s.nodes.size());
      s.nodes.emplace_back();
      glm::dmat4 m = at(0.4 * glm::dvec3(unit(rng), unit(rng), unit(rng)));
      m = glm::rotate(m, 3.0 * unit(rng), glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)) + 1e-3));
      m = glm::scale(m, glm::dvec3(0.8 + 0.3 * unit(rng), 0.8 + 0.3 * unit(rng), 0.8 + 0.3 * unit(rng)));
      s.nodes[index].parentFromNode = m;
      if (depth >= 2 || rng() % 3 == 0) {
        s.nodes[index].primitive = randomPrimitive(rng);
        return index;
      }
      s.nodes[index].op = ops[rng() % 4];
      const int n = 2 + static_cast<int>(rng() % 2);
      for (int k = 0; k < n; ++k) {
        const std::uint32_t child = build(depth + 1);
        s.nodes[index].children.push_back(child);
      }
      return index;
    };
    build(0);
    ASSERT_EQ(validate(s), "");
    const glm::dvec3 from = 5.0 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    const glm::dvec3 to = 0.5 * glm::dvec3(unit(rng), unit(rng), unit(rng));
    const Ray ray{from, to - from};
    const Hits h = intersect(s, ray);
    for (int k = 0; k <= 300; ++k) {
      const double t = 2.0 * k / 300.0;
      double nearest = kInf;
      bool inSpan = false;
      for (const Span& sp : h.spans) {
        inSpan = inSpan || (t >= sp.t0 && t <= sp.t1);
        nearest = std::min({nearest, std::abs(t - sp.t0), std::abs(t - sp.t1)});
      }
      if (nearest < 1e-7) continue;
      EXPECT_EQ(inSpan, contains(s, ray.origin + t * ray.dir)) << "trial " << trial << " t " << t;
      ++checked;
    }
    // Each crossing of a merge, intersection or difference root is a change of inside-ness there.
    if (s.nodes[0].op == Op::Union || s.nodes[0].op == Op::Leaf) continue;
    for (const Crossing& c : h.crossings) {
      const double d = 1e-6;
      const bool before = contains(s, ray.origin + (c.t - d) * ray.dir), after = contains(s, ray.origin + (c.t + d) * ray.dir);
      if (before == after) continue;  // two surfaces within d of each other
      EXPECT_EQ(c.entering(ray.dir), after) << "trial " << trial << " t " << c.t;
    }
  }
  EXPECT_GT(checked, 30000);
}

TEST(Solids, ValidationNamesWhatIsWrong) {
  Solid ok = operation(Op::Union, {{{Shape::Sphere, glm::dvec3(1.0)}, glm::dmat4(1.0)}});
  EXPECT_EQ(validate(ok), "");
  Solid cycle = ok;
  cycle.nodes[1].op = Op::Union;
  cycle.nodes[1].children = {0};
  EXPECT_NE(validate(cycle).find("deeper than"), std::string::npos) << validate(cycle);
  Solid badSize = single(Shape::Box, {1.0, 0.0, 1.0});
  EXPECT_NE(validate(badSize).find("node 0"), std::string::npos);
  Solid fatTorus = single(Shape::Torus, {1.0, 1.5, 0.0});
  EXPECT_NE(validate(fatTorus).find("torus"), std::string::npos);
  Solid flat = single(Shape::Sphere, glm::dvec3(1.0), glm::scale(glm::dmat4(1.0), glm::dvec3(1.0, 0.0, 1.0)));
  EXPECT_NE(validate(flat).find("invertible"), std::string::npos);
  Solid empty = ok;
  empty.nodes[0].children.clear();
  EXPECT_NE(validate(empty).find("at least one operand"), std::string::npos);
  Solid deep;
  for (int i = 0; i < kMaxCsgDepth + 2; ++i) {
    Node n;
    n.op = Op::Union;
    n.children = {static_cast<std::uint32_t>(i + 1)};
    deep.nodes.push_back(n);
  }
  deep.nodes.back() = single(Shape::Sphere, glm::dvec3(1.0)).nodes[0];
  EXPECT_NE(validate(deep).find("deeper than"), std::string::npos);
}

}  // namespace
}  // namespace tandem::solid
