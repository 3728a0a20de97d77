// The glTF importer's meshes (docs/gltf.md, "Geometry"): primitives converted to triangle lists with the
// vertices they use, normals and tangents generated where missing, shared between primitives that read the
// same accessors, every array charged to the load budget first.
#include <algorithm>

#include "io/GltfImporter.h"

namespace tandem::gltf {

// ---- meshes ----

namespace {

// The vertices a primitive uses, in ascending order, with `indices` renumbered onto them; empty (and
// `indices` untouched) when it uses them all, the usual case, so their order is kept. Primitives often
// index a vertex array shared with others: keeping only the used vertices makes a mesh cost what it draws,
// and the work on it independent of the shared array's size.
std::vector<std::uint32_t> keepUsedVertices(std::vector<std::uint32_t>& indices, std::size_t vertexCount) {
  std::vector<std::uint32_t> used = indices;
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  if (used.size() == vertexCount) return {};
  for (std::uint32_t& i : indices) i = std::uint32_t(std::lower_bound(used.begin(), used.end(), i) - used.begin());
  return used;
}

// Copies the n used vertices' values (nc floats each in `data`; `used` empty: vertices 0..n−1) into `out`
// through `convert`, which answers false for a value the mesh cannot take: then *bad is its vertex.
template <class T, class Convert>
bool gatherVertices(const std::vector<float>& data, std::size_t nc, const std::vector<std::uint32_t>& used,
                    std::size_t n, std::vector<T>& out, std::size_t* bad, Convert convert) {
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t v = used.empty() ? i : used[i];
    if (!convert(data.data() + nc * v, out[i])) {
      *bad = v;
      return false;
    }
  }
  return true;
}

void generateNormals(Mesh& mesh) {
  // Area-weighted face normals (the cross product's length), accumulated per vertex.
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    if (!finite3(n)) continue;
    mesh.normals[a] += n;
    mesh.normals[b] += n;
    mesh.normals[c] += n;
  }
  for (glm::vec3& n : mesh.normals) {
    const float len = glm::length(n);
    // Degenerate-only vertices get an arbitrary unit normal rather than NaN (bad-inputs.md M6).
    n = (len > 1e-30f && std::isfinite(len)) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
  }
}

void generateTangents(Mesh& mesh) {
  // Per-triangle tangent from the uv gradient (Lengyel), accumulated, then Gram-Schmidt against the
  // normal; w is the handedness of (T, B, N).
  const std::size_t n = mesh.positions.size();
  std::vector<glm::vec3> tan(n, glm::vec3(0.0f)), bit(n, glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
    const glm::vec3 e1 = mesh.positions[i1] - mesh.positions[i0], e2 = mesh.positions[i2] - mesh.positions[i0];
    const glm::vec2 d1 = mesh.uvs[i1] - mesh.uvs[i0], d2 = mesh.uvs[i2] - mesh.uvs[i0];
    const float det = d1.x * d2.y - d2.x * d1.y;
    if (std::abs(det) < 1e-20f || !std::isfinite(det)) continue;
    const float r = 1.0f / det;
    const glm::vec3 sdir = (e1 * d2.y - e2 * d1.y) * r, tdir = (e2 * d1.x - e1 * d2.x) * r;
    if (!finite3(sdir) || !finite3(tdir)) continue;
    for (std::uint32_t i : {i0, i1, i2}) {
      tan[i] += sdir;
      bit[i] += tdir;
    }
  }
  mesh.tangents.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 nn = mesh.normals[i];
    glm::vec3 t = tan[i] - nn * glm::dot(nn, tan[i]);
    float len = glm::length(t);
    if (!(len > 1e-20f) || !std::isfinite(len)) {
      // No usable uv gradient: any unit vector perpendicular to the normal.
      t = std::abs(nn.x) < 0.9f ? glm::cross(nn, glm::vec3(1, 0, 0)) : glm::cross(nn, glm::vec3(0, 1, 0));
      len = glm::length(t);
    }
    t /= len;
    const float w = glm::dot(glm::cross(nn, t), bit[i]) < 0.0f ? -1.0f : 1.0f;
    mesh.tangents[i] = glm::vec4(t, w);
  }
}

}  // namespace

Result<std::shared_ptr<const std::vector<float>>> Importer::attribute(int accessor) {
  for (auto it = readCache_.begin(); it != readCache_.end(); ++it)
    if (it->first == accessor) {
      auto hit = *it;  // move to the back: most recently used
      readCache_.erase(it);
      readCache_.push_back(hit);
      return hit.second;
    }
  auto r = readFloats(m_, accessor, file_, &budget_);
  if (!r) return r.error();
  auto data = std::make_shared<const std::vector<float>>(std::move(*r));
  constexpr std::size_t kEntries = 8;
  if (readCache_.size() == kEntries) readCache_.erase(readCache_.begin());
  readCache_.emplace_back(accessor, data);
  return data;
}

// The primitive's indices (or 0..n−1), range-checked, as a triangle list (strips and fans expanded with
// glTF's winding); empty for fewer than three vertices.
Result<std::vector<std::uint32_t>> Importer::triangleList(const tinygltf::Primitive& p, std::size_t vertexCount,
                                                         const std::string& id) {
  std::vector<std::uint32_t> idx;
  if (p.indices >= 0) {
    auto r = readIndices(m_, p.indices, file_, &budget_);
    if (!r) return r.error();
    idx = std::move(*r);
    const int ct = m_.accessors[std::size_t(p.indices)].componentType;
    const u64 restart = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 0xFFu
                        : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 0xFFFFu
                                                                       : 0xFFFFFFFFu;
    for (std::size_t i = 0; i < idx.size(); ++i) {
      if (idx[i] == restart)
        return err(id + ": index " + std::to_string(i) + " is the primitive-restart value " + std::to_string(restart) +
                   ", which glTF forbids (accessors[" + std::to_string(p.indices) + "])");
      if (idx[i] >= vertexCount)
        return err(id + ": index " + std::to_string(i) + " = " + std::to_string(idx[i]) + " is not below the vertex count " +
                   std::to_string(vertexCount) + " (accessors[" + std::to_string(p.indices) + "])");
    }
  } else {
    if (auto c = charge(id + " indices", u64(vertexCount) * sizeof(std::uint32_t)); !c) return c.error();
    idx.resize(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) idx[i] = std::uint32_t(i);
  }
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (idx.size() % 3 != 0)
      return err(id + ": " + std::to_string(idx.size()) + " indices for a triangle list, not a multiple of 3");
    return idx;
  } else if (idx.size() >= 3) {
    if (auto c = charge(id + " triangle list", u64(idx.size() - 2) * 3 * sizeof(std::uint32_t)); !c) return c.error();
    std::vector<std::uint32_t> list;
    list.reserve((idx.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // glTF 3.7.2.1: odd triangles swap their last two vertices to keep a consistent winding.
        const std::size_t b = i + 1 + i % 2, c = i + 2 - i % 2;
        list.insert(list.end(), {idx[i], idx[b], idx[c]});
      } else {  // fan
        list.insert(list.end(), {idx[i + 1], idx[i + 2], idx[0]});
      }
    }
    return list;
  }
  return std::vector<std::uint32_t>{};  // fewer than 3 vertices: nothing to draw
}

namespace {
int attributeAccessor(const tinygltf::Primitive& p, const char* name) {
  auto it = p.attributes.find(name);
  return it == p.attributes.end() ? -1 : it->second;
}
}  // namespace

// Each attribute: read through the cache, charged, then copied for the used vertices; a value the mesh
// cannot take (NaN, infinity) rejects the file, naming it.
Result<Mesh> Importer::convertPrimitive(int meshIndex, int primIndex) {
  const tinygltf::Primitive& p = m_.meshes[std::size_t(meshIndex)].primitives[std::size_t(primIndex)];
  const std::string id = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primIndex) + "]";
  Mesh mesh;
  mesh.name = m_.meshes[std::size_t(meshIndex)].name;
  if (m_.meshes[std::size_t(meshIndex)].primitives.size() > 1) mesh.name.append("#").append(std::to_string(primIndex));
  const int posAcc = attributeAccessor(p, "POSITION");
  auto pos = attribute(posAcc);
  if (!pos) return pos.error();
  const std::size_t vertexCount = (*pos)->size() / 3;
  if (vertexCount > std::size_t(UINT32_MAX)) return err(id + ": too many vertices");
  auto triangles = triangleList(p, vertexCount, id);
  if (!triangles) return triangles.error();
  mesh.indices = std::move(*triangles);
  if (mesh.indices.empty()) return mesh;  // caller skips it with a warning

  if (auto c = charge(id + " vertex list", u64(mesh.indices.size()) * sizeof(std::uint32_t)); !c) return c.error();
  const std::vector<std::uint32_t> used = keepUsedVertices(mesh.indices, vertexCount);
  const std::size_t n = used.empty() ? vertexCount : used.size();
  std::size_t bad = 0;
  if (auto c = charge(id + " vertices", u64(n) * sizeof(glm::vec3)); !c) return c.error();
  if (!gatherVertices(**pos, 3, used, n, mesh.positions, &bad, [](const float* v, glm::vec3& out) {
        out = glm::vec3(v[0], v[1], v[2]);
        return finite3(out);
      }))
    return err(id + ": POSITION " + std::to_string(bad) + " is NaN or infinite (accessors[" + std::to_string(posAcc) + "])");
  if (auto r = readNormals(p, id, used, n, mesh); !r) return r.error();
  if (auto r = readUvsAndColours(p, id, used, n, mesh); !r) return r.error();
  if (auto r = readTangents(p, id, used, n, mesh); !r) return r.error();
  return mesh;
}

Result<void> Importer::readNormals(const tinygltf::Primitive& p, const std::string& id,
                                   const std::vector<std::uint32_t>& used, std::size_t n, Mesh& mesh) {
  if (auto c = charge(id + " normals", u64(n) * sizeof(glm::vec3)); !c) return c.error();
  const int a = attributeAccessor(p, "NORMAL");
  if (a < 0) {
    generateNormals(mesh);
    return {};
  }
  auto r = attribute(a);
  if (!r) return r.error();
  std::size_t bad = 0;
  bool zero = false;
  if (!gatherVertices(**r, 3, used, n, mesh.normals, &bad, [&zero](const float* v, glm::vec3& out) {
        out = glm::vec3(v[0], v[1], v[2]);
        if (!finite3(out)) return false;
        const float len = glm::length(out);
        zero = zero || !(len > 1e-20f);
        out = len > 1e-20f ? out / len : glm::vec3(0, 0, 1);
        return true;
      }))
    return err(id + ": NORMAL " + std::to_string(bad) + " is NaN or infinite");
  if (zero) warn_(id + ": zero-length normals replaced");
  return {};
}

Result<void> Importer::readUvsAndColours(const tinygltf::Primitive& p, const std::string& id,
                                         const std::vector<std::uint32_t>& used, std::size_t n, Mesh& mesh) {
  std::size_t bad = 0;
  if (int a = attributeAccessor(p, "TEXCOORD_0"); a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    if (auto c = charge(id + " uvs", u64(n) * sizeof(glm::vec2)); !c) return c.error();
    if (!gatherVertices(**r, 2, used, n, mesh.uvs, &bad, [](const float* v, glm::vec2& out) {
          out = glm::vec2(v[0], v[1]);
          return std::isfinite(out.x) && std::isfinite(out.y);
        }))
      return err(id + ": TEXCOORD_0 " + std::to_string(bad) + " is NaN or infinite");
  }
  if (int a = attributeAccessor(p, "COLOR_0"); a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    const std::size_t nc = std::size_t(componentCount(m_.accessors[std::size_t(a)].type));
    if (auto c = charge(id + " colours", u64(n) * sizeof(glm::vec4)); !c) return c.error();
    if (!gatherVertices(**r, nc, used, n, mesh.colors, &bad, [nc](const float* v, glm::vec4& out) {
          out = glm::vec4(1.0f);
          for (std::size_t k = 0; k < nc; ++k) out[int(k)] = v[k];
          if (!finite3(glm::vec3(out)) || !std::isfinite(out.w)) return false;
          out = glm::clamp(out, 0.0f, 1.0f);
          return true;
        }))
      return err(id + ": COLOR_0 " + std::to_string(bad) + " is NaN or infinite");
  }
  return {};
}

// Tangents only for primitives drawn with a normal map, their only reader.
Result<void> Importer::readTangents(const tinygltf::Primitive& p, const std::string& id,
                                    const std::vector<std::uint32_t>& used, std::size_t n, Mesh& mesh) {
  const bool normalMap = p.material >= 0 && wantsTangents_[std::size_t(p.material)];
  if (!normalMap) return {};
  // Charged what it keeps: n tangents, and n zero uvs where there are neither tangents nor uvs to make them from.
  const int a = attributeAccessor(p, "TANGENT");
  const bool zeroUvs = a < 0 && mesh.uvs.empty();
  if (auto c = charge(id + " tangents", u64(n) * (sizeof(glm::vec4) + (zeroUvs ? sizeof(glm::vec2) : 0))); !c)
    return c.error();
  if (a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    std::size_t bad = 0;
    if (!gatherVertices(**r, 4, used, n, mesh.tangents, &bad, [](const float* v, glm::vec4& out) {
          const glm::vec4 t(v[0], v[1], v[2], v[3]);
          if (!finite3(glm::vec3(t)) || !std::isfinite(t.w)) return false;
          const float len = glm::length(glm::vec3(t));
          out = len > 1e-20f ? glm::vec4(glm::vec3(t) / len, t.w < 0 ? -1.0f : 1.0f) : glm::vec4(1, 0, 0, 1);
          return true;
        }))
      return err(id + ": TANGENT " + std::to_string(bad) + " is NaN or infinite");
  } else {
    if (mesh.uvs.empty()) warn_(id + ": normal map without TEXCOORD_0; tangents are arbitrary");
    else generateTangents(mesh);
    if (mesh.uvs.empty()) {
      mesh.uvs.assign(n, glm::vec2(0.0f));
      generateTangents(mesh);
    }
  }
  return {};
}

Result<int> Importer::meshFor(int meshIndex, int primIndex, bool flip) {
  const auto key = std::make_tuple(meshIndex, primIndex, flip);
  if (auto it = meshCache_.find(key); it != meshCache_.end()) return it->second;
  const tinygltf::Primitive& p = m_.meshes[std::size_t(meshIndex)].primitives[std::size_t(primIndex)];
  const std::string id = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primIndex) + "]";
  auto skip = [&](const std::string& why) {
    warn_(id + ": " + why + "; primitive skipped");
    meshCache_[key] = -1;
    return -1;
  };
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode <= TINYGLTF_MODE_LINE_STRIP) return skip(mode == 0 ? "points are not rendered" : "lines are not rendered");
  if (p.attributes.find("POSITION") == p.attributes.end()) return skip("no POSITION attribute");
  if (!p.targets.empty()) warnOnce("morph", "morph targets are ignored; the base shape is used");
  auto attr = [&](const char* name) {
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const bool normalMap = p.material >= 0 && wantsTangents_[std::size_t(p.material)];
  const std::array<int, 9> content{attr("POSITION"), attr("NORMAL"),   attr("TEXCOORD_0"),
                                   attr("COLOR_0"),  normalMap ? attr("TANGENT") : -1,
                                   p.indices,        mode,             int(normalMap), int(flip)};
  if (auto it = contentCache_.find(content); it != contentCache_.end()) {
    meshCache_[key] = it->second;
    return it->second;
  }
  // The twin of the other handedness may exist already: copy it and reverse it instead of converting twice.
  Mesh mesh;
  bool reverse = flip;
  if (auto twin = meshCache_.find(std::make_tuple(meshIndex, primIndex, !flip));
      twin != meshCache_.end() && twin->second >= 0) {
    const Mesh& original = out_.scene.meshes[std::size_t(twin->second)];
    if (auto c = charge(id + " (mirrored copy)", original.bytes()); !c) return c.error();
    mesh = original;
    reverse = true;
  } else {
    auto r = convertPrimitive(meshIndex, primIndex);
    if (!r) return r.error();
    mesh = std::move(*r);
    if (mesh.indices.empty()) return skip("fewer than 3 vertices");
  }
  if (reverse) {
    // Under a mirroring transform (det < 0) glTF asks for the opposite winding. Normals stay in object
    // space (the inverse transpose handles them); the bitangent sign flips with the handedness.
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    for (glm::vec4& t : mesh.tangents) t.w = -t.w;
  }
  const std::string suffix = " (mirrored)";
  if (mesh.name.ends_with(suffix)) mesh.name.resize(mesh.name.size() - suffix.size());
  if (flip) mesh.name += suffix;
  const int index = int(out_.scene.meshes.size());
  out_.scene.meshes.push_back(std::move(mesh));
  meshCache_[key] = index;
  contentCache_[content] = index;
  return index;
}

}  // namespace tandem::gltf
