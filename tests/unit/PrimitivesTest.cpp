// Built-in meshes: the ray pass assumes closed, consistently wound meshes (rays that enter a glass
// sphere must leave it), and the rasterizer culls by counter-clockwise winding.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "tandem/Primitives.h"

namespace tandem {
namespace {

using Key = std::tuple<float, float, float>;

/// Maps every vertex to the first vertex with exactly the same position (the sphere's seam and poles
/// duplicate positions for their uvs).
std::vector<std::uint32_t> weld(const Mesh& m) {
  std::map<Key, std::uint32_t> first;
  std::vector<std::uint32_t> id(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::vec3& p = m.positions[i];
    id[i] = first.emplace(Key{p.x, p.y, p.z}, std::uint32_t(i)).first->second;
  }
  return id;
}

/// Closed and consistently oriented: each welded directed edge appears once and its reverse once.
void expectWatertight(const Mesh& m) {
  std::vector<std::uint32_t> id = weld(m);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < m.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = id[m.indices[3 * t + std::size_t(k)]], b = id[m.indices[3 * t + std::size_t((k + 1) % 3)]];
      ASSERT_NE(a, b) << "degenerate triangle " << t;
      ++directed[{a, b}];
    }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "->" << edge.second << " used " << count << " times";
    auto rev = directed.find({edge.second, edge.first});
    EXPECT_TRUE(rev != directed.end() && rev->second == 1)
        << "edge " << edge.first << "-" << edge.second << " is not shared by exactly two triangles";
  }
}

glm::vec3 faceNormal(const Mesh& m, std::size_t t) {
  const glm::vec3& a = m.positions[m.indices[3 * t]];
  const glm::vec3& b = m.positions[m.indices[3 * t + 1]];
  const glm::vec3& c = m.positions[m.indices[3 * t + 2]];
  return glm::cross(b - a, c - a);
}

void expectUnitNormalsAndCcw(const Mesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  for (const glm::vec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  for (std::size_t t = 0; t < m.triangleCount(); ++t) {
    glm::vec3 g = faceNormal(m, t);
    ASSERT_GT(glm::length(g), 0.0f) << "zero-area triangle " << t;
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(glm::dot(g, m.normals[m.indices[3 * t + std::size_t(k)]]), 0.0f)
          << "triangle " << t << " is wound clockwise seen from outside";
  }
}

TEST(Primitives, SphereIsClosedUnitNormalsCounterClockwise) {
  for (auto [segments, rings] : {std::pair{3, 2}, std::pair{7, 5}, std::pair{64, 32}}) {
    SCOPED_TRACE(std::to_string(segments) + "x" + std::to_string(rings));
    Mesh s = makeSphere(2.5f, segments, rings);
    EXPECT_EQ(s.triangleCount(), std::size_t(segments) * std::size_t(2 * rings - 2));
    for (std::uint32_t i : s.indices) ASSERT_LT(i, s.positions.size());
    expectWatertight(s);
    expectUnitNormalsAndCcw(s);
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(s.positions[i]), 2.5f, 1e-5f);
      // Smooth normals of a sphere point along the position.
      EXPECT_NEAR(glm::dot(s.normals[i], glm::normalize(s.positions[i])), 1.0f, 1e-5f);
    }
  }
}

TEST(Primitives, SphereClampsTessellationToAClosedMinimum) {
  Mesh s = makeSphere(1.0f, 0, 0);
  EXPECT_EQ(s.triangleCount(), 3u * 2u);  // 3 segments, 2 rings
  expectWatertight(s);
}

TEST(Primitives, BoxHasTwelveOutwardTrianglesAndIsClosed) {
  const glm::vec3 size(2.0f, 1.0f, 0.5f);
  Mesh b = makeBox(size);
  EXPECT_EQ(b.triangleCount(), 12u);
  EXPECT_EQ(b.positions.size(), 24u);
  expectWatertight(b);
  expectUnitNormalsAndCcw(b);
  for (std::size_t t = 0; t < b.triangleCount(); ++t) {
    glm::vec3 centroid = (b.positions[b.indices[3 * t]] + b.positions[b.indices[3 * t + 1]] + b.positions[b.indices[3 * t + 2]]) / 3.0f;
    EXPECT_GT(glm::dot(faceNormal(b, t), centroid), 0.0f) << "triangle " << t << " faces inwards";
  }
  for (const glm::vec3& p : b.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x), size.x / 2);
    EXPECT_FLOAT_EQ(std::abs(p.y), size.y / 2);
    EXPECT_FLOAT_EQ(std::abs(p.z), size.z / 2);
  }
}

TEST(Primitives, PlaneFacesUpWithUvsInSceneUnits) {
  Mesh p = makePlane({4.0f, 6.0f}, 3);
  EXPECT_EQ(p.triangleCount(), 2u * 3u * 3u);
  expectUnitNormalsAndCcw(p);
  for (std::size_t t = 0; t < p.triangleCount(); ++t) {
    glm::vec3 g = glm::normalize(faceNormal(p, t));
    EXPECT_NEAR(g.y, 1.0f, 1e-6f) << "triangle " << t;
  }
  glm::vec2 uvMax(0.0f);
  for (std::size_t i = 0; i < p.positions.size(); ++i) {
    EXPECT_EQ(p.positions[i].y, 0.0f);
    EXPECT_EQ(p.normals[i], glm::vec3(0, 1, 0));
    EXPECT_LE(std::abs(p.positions[i].x), 2.0f);
    EXPECT_LE(std::abs(p.positions[i].z), 3.0f);
    uvMax = glm::max(uvMax, p.uvs[i]);
  }
  // A checker frequency of 1 then gives unit squares.
  EXPECT_FLOAT_EQ(uvMax.x, 4.0f);
  EXPECT_FLOAT_EQ(uvMax.y, 6.0f);
}

}  // namespace
}  // namespace tandem
