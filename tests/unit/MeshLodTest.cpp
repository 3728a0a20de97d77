// clusteredTriangles (core/MeshLod.h): the coarse copies reflection probes draw small objects with. A copy
// indexes the mesh's own vertices, keeps every surviving triangle's winding, drops the collapsed and the
// repeated ones, and a grid fine enough to give each vertex its own cell gives the mesh back.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>

#include "core/MeshLod.h"
#include "tandem/Primitives.h"

namespace tandem {
namespace {

std::array<std::uint32_t, 3> turnedToSmallest(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  std::array<std::uint32_t, 3> t{a, b, c};
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

TEST(MeshLod, ASphereKeepsItsShapeInFewerTrianglesFacingOut) {
  const Mesh sphere = makeSphere(1.0f, 64, 32);
  std::size_t previous = sphere.indices.size();
  for (int cells : {16, 4}) {
    SCOPED_TRACE("cells " + std::to_string(cells));
    const std::vector<std::uint32_t> copy = clusteredTriangles(sphere, cells);
    ASSERT_EQ(copy.size() % 3, 0u);
    ASSERT_GT(copy.size(), 0u);
    EXPECT_LT(copy.size() * 2, previous) << "a coarser grid keeps under half the triangles";
    previous = copy.size();
    std::set<std::array<std::uint32_t, 3>> seen;
    for (std::size_t t = 0; t < copy.size(); t += 3) {
      const std::uint32_t a = copy[t], b = copy[t + 1], c = copy[t + 2];
      ASSERT_LT(std::max({a, b, c}), sphere.positions.size());
      EXPECT_TRUE(a != b && b != c && a != c) << "a collapsed triangle";
      EXPECT_TRUE(seen.insert(turnedToSmallest(a, b, c)).second) << "a repeated triangle";
      const glm::vec3 pa = sphere.positions[a], pb = sphere.positions[b], pc = sphere.positions[c];
      // Counter-clockwise seen from outside, as the sphere's own triangles: the unit normal never points
      // inwards (a sliver left near a pole may stand on edge, at 0).
      const glm::vec3 n = glm::cross(pb - pa, pc - pa);
      EXPECT_GT(glm::dot(n, glm::normalize(pa + pb + pc)), -1e-3f * glm::length(n) - 1e-12f) << "winding turned";
    }
    // Every vertex kept is a vertex of the sphere, so on it; the copy still covers every direction.
    for (glm::vec3 dir : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                          glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)}) {
      float best = -1.0f;
      for (std::uint32_t v : copy) best = std::max(best, glm::dot(sphere.positions[v], dir));
      EXPECT_GT(best, 0.85f) << "the copy lost the side facing " << dir.x << "," << dir.y << "," << dir.z;
    }
  }
}

TEST(MeshLod, ABoxWhoseCornersKeepTheirCellsComesBackWhole) {
  const Mesh box = makeBox(glm::vec3(2.0f));  // 24 vertices, 8 places: the seams between faces merge
  const std::vector<std::uint32_t> copy = clusteredTriangles(box, 2);
  ASSERT_EQ(copy.size(), box.indices.size()) << "each corner is its own cell: no triangle collapses";
  // The same twelve triangles over the corners' representatives: each corner position turns up as one vertex.
  std::set<std::array<float, 3>> corners;
  for (std::uint32_t v : copy) corners.insert({box.positions[v].x, box.positions[v].y, box.positions[v].z});
  EXPECT_EQ(corners.size(), 8u);
  for (std::size_t t = 0; t < copy.size(); t += 3) {
    const glm::vec3 pa = box.positions[copy[t]], pb = box.positions[copy[t + 1]], pc = box.positions[copy[t + 2]];
    EXPECT_GT(glm::dot(glm::cross(pb - pa, pc - pa), pa + pb + pc), 0.0f) << "winding turned";
  }
  // One cell holds the whole box: every triangle collapses.
  EXPECT_TRUE(clusteredTriangles(box, 1).empty());
}

TEST(MeshLod, AFinelyCutPlaneInFourCellsLeavesEachTriangleOnce) {
  const Mesh plane = makePlane(glm::vec2(2.0f), 8);  // 128 triangles over a 9x9 grid of vertices
  const std::vector<std::uint32_t> copy = clusteredTriangles(plane, 2);
  // Four cells, so four corners: the triangles that span three of them are each one of the four such
  // triangles, kept once, all facing up as the plane does.
  std::set<std::array<std::uint32_t, 3>> seen;
  for (std::size_t t = 0; t < copy.size(); t += 3) {
    EXPECT_TRUE(seen.insert(turnedToSmallest(copy[t], copy[t + 1], copy[t + 2])).second) << "a repeated triangle";
    const glm::vec3 pa = plane.positions[copy[t]], pb = plane.positions[copy[t + 1]], pc = plane.positions[copy[t + 2]];
    EXPECT_GT(glm::cross(pb - pa, pc - pa).y, 0.0f);
  }
  EXPECT_GE(copy.size() / 3, 2u);
  EXPECT_LE(copy.size() / 3, 4u);
}

TEST(MeshLod, TrianglesThatBecomeOneAreKeptOnce) {
  // Two triangles whose first corners share a cell: moved to its representative they are one triangle.
  Mesh m;
  m.positions = {{0.0f, 0.0f, 0.0f}, {0.1f, 0.05f, 0.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}};
  m.indices = {0, 2, 3, 1, 2, 3};
  const std::vector<std::uint32_t> copy = clusteredTriangles(m, 4);
  ASSERT_EQ(copy.size(), 3u);
  EXPECT_EQ(copy[1], 2u);
  EXPECT_EQ(copy[2], 3u);
}

TEST(MeshLod, AMeshWithNoExtentOrNoTrianglesComesBackAsItIs) {
  Mesh point;
  point.positions = {glm::vec3(1.0f), glm::vec3(1.0f), glm::vec3(1.0f)};
  point.indices = {0, 1, 2};
  EXPECT_EQ(clusteredTriangles(point, 4), point.indices);
  Mesh none;
  EXPECT_TRUE(clusteredTriangles(none, 4).empty());
  Mesh outOfRange = makeBox(glm::vec3(1.0f));
  outOfRange.indices.insert(outOfRange.indices.end(), {0, 1, 999});  // a bad index: that triangle is dropped
  const std::vector<std::uint32_t> copy = clusteredTriangles(outOfRange, 2);
  EXPECT_EQ(copy.size(), outOfRange.indices.size() - 3);
}

}  // namespace
}  // namespace tandem
