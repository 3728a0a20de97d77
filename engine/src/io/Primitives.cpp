#include "tandem/Primitives.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/constants.hpp>

namespace tandem {

Mesh makeSphere(float radius, int segments, int rings) {
  segments = std::max(segments, 3);
  rings = std::max(rings, 2);
  Mesh m;
  m.name = "sphere";
  for (int r = 0; r <= rings; ++r) {
    float v = float(r) / float(rings);
    float theta = v * glm::pi<float>();
    for (int s = 0; s <= segments; ++s) {
      float u = float(s) / float(segments);
      // The seam column reuses phi = 0: sin(2π) in float is not 0, which would leave a crack.
      float phi = (s == segments ? 0.0f : u) * glm::two_pi<float>();
      // The poles are exact so the mesh closes (needed by "rays from inside always hit").
      glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      if (r == 0) n = {0, 1, 0};
      if (r == rings) n = {0, -1, 0};
      m.positions.push_back(n * radius);
      m.normals.push_back(n);
      m.uvs.push_back({u, 1.0f - v});
    }
  }
  auto at = [segments](int r, int s) { return std::uint32_t(r * (segments + 1) + s); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // Counter-clockwise seen from outside. The seam column duplicates positions exactly (u = 0 and 1).
      if (r != 0) m.indices.insert(m.indices.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
      if (r != rings - 1) m.indices.insert(m.indices.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
    }
  return m;
}

Mesh makeBox(glm::vec3 size) {
  Mesh m;
  m.name = "box";
  glm::vec3 h = size * 0.5f;
  const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const glm::vec3& n : normals) {
    // Two tangent axes with u × v = n so the face winds counter-clockwise seen from outside.
    glm::vec3 u = std::abs(n.y) > 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    glm::vec3 v = glm::cross(n, u);
    u = glm::cross(v, n);
    auto base = std::uint32_t(m.positions.size());
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const glm::vec2& c : corners) {
      m.positions.push_back((n + u * c.x + v * c.y) * h);
      m.normals.push_back(n);
      m.uvs.push_back(c * 0.5f + 0.5f);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return m;
}

Mesh makePlane(glm::vec2 size, int divisions) {
  divisions = std::max(divisions, 1);
  Mesh m;
  m.name = "plane";
  for (int j = 0; j <= divisions; ++j)
    for (int i = 0; i <= divisions; ++i) {
      float fu = float(i) / float(divisions);
      float fv = float(j) / float(divisions);
      m.positions.push_back({(fu - 0.5f) * size.x, 0.0f, (fv - 0.5f) * size.y});
      m.normals.push_back({0, 1, 0});
      m.uvs.push_back({fu * size.x, fv * size.y});
    }
  auto at = [divisions](int i, int j) { return std::uint32_t(j * (divisions + 1) + i); };
  for (int j = 0; j < divisions; ++j)
    for (int i = 0; i < divisions; ++i)
      // +Y facing: (i,j) → (i,j+1) → (i+1,j) is counter-clockwise seen from above.
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
  return m;
}

}  // namespace tandem
