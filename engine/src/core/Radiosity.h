#pragma once
// A radiosity solution as the frame shows it (docs/radiosity.md): per triangle of each instance, a grid of
// n × n patches whose vertices carry the indirect irradiance H of each side, interpolated over the patch
// (tdGridCorners, shaders/shading.glsl) by the GL shade pass and the ray pass alike. Plain data: the solver
// (rt/Radiosity.h) makes it, the GL copy uploads it, the ray pass reads it.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/Shading.h"

namespace tandem {

struct RadiosityField {
  /// Marks an instance or a triangle the solution does not cover (its H is 0).
  static constexpr std::uint32_t kNone = 0xffffffffu;
  /// Entries [0, instances): (the instance's first triangle entry, its triangle count), or (kNone, 0).
  /// Then one entry per covered triangle: (its first value, its grid's n). The GL copy uploads this
  /// table as it is (an RG32UI buffer texture).
  std::vector<glm::uvec2> table;
  /// Per grid vertex, two values: H on the side the triangle's counter-clockwise front faces, then on its back.
  std::vector<glm::vec3> values;
  /// Unshot light not yet distributed, as an ambient estimate (progressive refinement's ambient term,
  /// Cohen et al. 1988): added to every point's H so a frame shown mid-solve is not too dark. 0 once converged.
  glm::vec3 ambient{0.0f};
  /// Set by whoever publishes the field (the Renderer), changed whenever the values are: what the frame's
  /// caches compare.
  std::uint64_t version = 0;

  /// Instances the table starts with (the scene's instance count when solved).
  std::size_t instanceCount = 0;

  bool empty() const { return table.empty(); }

  /// H at barycentrics `bary` of `triangle` of `instance`, seen from its back (backFace) or front:
  /// tdGridCorners over the triangle's grid, plus `ambient`. False where the solution does not cover the
  /// triangle (a dynamic instance): the ambient term lights it as before.
  bool at(std::uint32_t instance, std::uint32_t triangle, glm::vec3 bary, bool backFace, glm::vec3& h) const {
    if (instance >= instanceCount) return false;
    const glm::uvec2 first = table[instance];
    if (first.x == kNone || triangle >= first.y) return false;
    const glm::uvec2 tri = table[first.x + triangle];
    glm::ivec3 corner;
    glm::vec3 weight;
    shading::tdGridCorners(bary, static_cast<int>(tri.y), corner, weight);
    const std::uint32_t side = backFace ? 1u : 0u;
    h = ambient;
    for (int k = 0; k < 3; ++k)
      h += weight[k] * values[tri.x + 2u * static_cast<std::uint32_t>(corner[k]) + side];
    return true;
  }

  /// The field of a solve that left some instances out (Renderer: the dynamic ones), for the scene with
  /// all `count` instances: `solved[k]` is the scene's index of the solve's instance k; the others get none.
  RadiosityField forInstances(const std::vector<std::uint32_t>& solved, std::size_t count) const {
    RadiosityField out;
    out.values = values;
    out.ambient = ambient;
    out.version = version;
    out.instanceCount = count;
    out.table.assign(count, glm::uvec2(kNone, 0u));
    const auto shift = static_cast<std::uint32_t>(count) - static_cast<std::uint32_t>(instanceCount);
    for (std::size_t k = 0; k < solved.size() && k < instanceCount; ++k)
      if (table[k].x != kNone) out.table[solved[k]] = glm::uvec2(table[k].x + shift, table[k].y);
    out.table.insert(out.table.end(), table.begin() + static_cast<std::ptrdiff_t>(instanceCount), table.end());
    return out;
  }
};

}  // namespace tandem
