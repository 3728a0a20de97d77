#include "core/MeshLod.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace tandem {

std::vector<std::uint32_t> clusteredTriangles(const Mesh& mesh, int cellsAcross) {
  assert(cellsAcross >= 1 && "clusteredTriangles: at least one cell");
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (mesh.indices.empty() || !(extent > 0.0f) || !std::isfinite(extent)) return mesh.indices;
  const float cell = extent / static_cast<float>(cellsAcross);
  // Cell coordinates per axis, clamped: the largest corner falls on the grid's far edge, not past it.
  auto cellOf = [&](glm::vec3 p) {
    const glm::ivec3 c = glm::clamp(glm::ivec3(glm::floor((p - lo) / cell)), glm::ivec3(0), glm::ivec3(cellsAcross - 1));
    return (static_cast<std::uint64_t>(c.x) * static_cast<std::uint64_t>(cellsAcross) + static_cast<std::uint64_t>(c.y)) *
               static_cast<std::uint64_t>(cellsAcross) + static_cast<std::uint64_t>(c.z);
  };
  // Each vertex's cluster, and each cluster's mean.
  std::unordered_map<std::uint64_t, std::uint32_t> clusterOfCell;
  std::vector<std::uint32_t> clusterOf(mesh.positions.size());
  std::vector<glm::dvec3> sum;
  std::vector<std::uint32_t> members;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const auto [it, added] = clusterOfCell.try_emplace(cellOf(mesh.positions[v]), static_cast<std::uint32_t>(sum.size()));
    if (added) sum.emplace_back(0.0), members.push_back(0);
    clusterOf[v] = it->second;
    sum[it->second] += glm::dvec3(mesh.positions[v]);
    ++members[it->second];
  }
  // The representative: the member nearest the mean (the lowest vertex number among equals).
  std::vector<std::uint32_t> representative(sum.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<double> best(sum.size(), std::numeric_limits<double>::infinity());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const std::uint32_t c = clusterOf[v];
    const glm::dvec3 d = glm::dvec3(mesh.positions[v]) - sum[c] / static_cast<double>(members[c]);
    const double dist = glm::dot(d, d);
    if (dist < best[c]) best[c] = dist, representative[c] = static_cast<std::uint32_t>(v);
  }
  std::vector<std::uint32_t> out;
  std::vector<std::array<std::uint32_t, 3>> kept;  // each survivor turned to start at its smallest corner
  kept.reserve(mesh.indices.size() / 3);
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    std::array<std::uint32_t, 3> r;
    bool valid = true;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.indices[t + static_cast<std::size_t>(k)];
      valid = valid && v < clusterOf.size();
      r[static_cast<std::size_t>(k)] = valid ? representative[clusterOf[v]] : 0u;
    }
    if (!valid || r[0] == r[1] || r[1] == r[2] || r[0] == r[2]) continue;
    // A triangle the moved corners turned over (clustering folds a few near a pole or a crease) is dropped:
    // drawn, it would face the other way, and a single-sided material's would vanish or show its back.
    auto normal = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      return glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    };
    if (glm::dot(normal(r[0], r[1], r[2]), normal(mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2])) <= 0.0f)
      continue;
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());  // keeps the turning order
    kept.push_back(r);
  }
  // Repeats out, the first of each kept where it stood.
  std::vector<std::size_t> order(kept.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return kept[a] < kept[b]; });
  std::vector<bool> repeat(kept.size(), false);
  for (std::size_t i = 1; i < order.size(); ++i) repeat[order[i]] = kept[order[i]] == kept[order[i - 1]];
  out.reserve(kept.size() * 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
    if (!repeat[i]) out.insert(out.end(), kept[i].begin(), kept[i].end());
  return out;
}

}  // namespace tandem
