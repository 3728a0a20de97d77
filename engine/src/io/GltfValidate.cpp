// Our own validation of a parsed tinygltf::Model: tinygltf checks almost nothing (bad-inputs.md), so
// every reference, range and count is checked here, in release builds too, before any data is read.
// All range arithmetic is 64-bit and overflow-checked (`a > limit - b` form or __builtin_*_overflow).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "io/GltfInternal.h"

namespace tandem::gltf {

namespace {

using u64 = std::uint64_t;

std::string at(const char* array, std::size_t i) { return std::string(array) + "[" + std::to_string(i) + "]"; }

bool mulOk(u64 a, u64 b, u64* r) { return !__builtin_mul_overflow(a, b, r); }
bool addOk(u64 a, u64 b, u64* r) { return !__builtin_add_overflow(a, b, r); }

bool finiteAll(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double d) { return std::isfinite(d); });
}

bool uses(const tinygltf::Model& m, const char* ext) {
  return std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), ext) != m.extensionsUsed.end();
}

// "2.0" → (2, 0); anything not digits.digits → false.
bool parseVersion(const std::string& s, int* major, int* minor) {
  std::size_t dot = s.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 >= s.size() || dot > 4 || s.size() - dot > 5) return false;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (i != dot && !std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  *major = std::stoi(s.substr(0, dot));
  *minor = std::stoi(s.substr(dot + 1));
  return true;
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown";
  }
}

// Byte offset and stride of an accessor inside its view (only after validation).
struct Layout {
  const std::uint8_t* base = nullptr;  // first element, or null for an all-zero accessor
  u64 stride = 0;
};

Layout layoutOf(const tinygltf::Model& m, const tinygltf::Accessor& a) {
  Layout l;
  if (a.bufferView < 0) return l;
  const tinygltf::BufferView& v = m.bufferViews[std::size_t(a.bufferView)];
  const tinygltf::Buffer& b = m.buffers[std::size_t(v.buffer)];
  l.base = b.data.data() + v.byteOffset + a.byteOffset;
  l.stride = v.byteStride ? v.byteStride : elementSize(a.componentType, a.type);
  return l;
}

// Checks that [offset, offset + bytes) lies inside bufferViews[view]. Returns the reason otherwise.
Result<void> rangeInView(const tinygltf::Model& m, int view, u64 offset, u64 bytes, const std::string& what) {
  const tinygltf::BufferView& v = m.bufferViews[std::size_t(view)];
  u64 end = 0;
  if (!addOk(offset, bytes, &end) || end > v.byteLength)
    return Error{what + " runs past " + at("bufferViews", std::size_t(view)) + " (length " +
                 std::to_string(v.byteLength) + ")"};
  return {};
}

double readComponent(const std::uint8_t* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { std::uint8_t v = *p; return normalized ? v / 255.0 : v; }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      std::int8_t v; std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v; std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v; std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    default: return 0.0;
  }
}

u64 readUnsigned(const std::uint8_t* p, int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    default: return 0;
  }
}

// An accessor's bytes in its bufferView: aligned, strided and inside the view.
Result<void> checkAccessorView(const tinygltf::Model& m, const tinygltf::Accessor& a, const std::string& id) {
  const int cs = componentSize(a.componentType);
  const u64 es = elementSize(a.componentType, a.type);
  const tinygltf::BufferView& v = m.bufferViews[std::size_t(a.bufferView)];
  if (a.byteOffset % u64(cs) != 0 || (v.byteOffset + a.byteOffset) % u64(cs) != 0)
    return Error{id + ": byteOffset " + std::to_string(a.byteOffset) + " is not aligned to its component size " +
                 std::to_string(cs)};
  const u64 stride = v.byteStride ? v.byteStride : es;
  if (v.byteStride && v.byteStride < es)
    return Error{id + ": " + at("bufferViews", std::size_t(a.bufferView)) + " byteStride " +
                 std::to_string(v.byteStride) + " is smaller than the element size " + std::to_string(es)};
  // The last element needs no padding after its last matrix column (glTF 3.6.2.4).
  const u64 tail = (a.type >= TINYGLTF_TYPE_MAT2 && a.type <= TINYGLTF_TYPE_MAT4)
                       ? es - es / u64(a.type - 32) + u64(a.type - 32) * u64(cs)
                       : es;
  u64 span = 0, bytes = 0;
  if (!mulOk(a.count - 1, stride, &span) || !addOk(span, tail, &bytes))
    return Error{id + ": count " + std::to_string(a.count) + " × stride overflows"};
  if (auto r = rangeInView(m, a.bufferView, a.byteOffset, bytes,
                           "byteOffset " + std::to_string(a.byteOffset) + " + " + std::to_string(a.count) + "×" +
                               std::to_string(stride) + " bytes");
      !r)
    return Error{id + ": " + r.error().message};
  return {};
}

// A sparse accessor's index and value arrays: inside their views, and indices strictly increasing and
// below count, since they are write positions.
Result<void> checkSparse(const tinygltf::Model& m, const tinygltf::Accessor& a, const std::string& id) {
  const int cs = componentSize(a.componentType);
  const u64 es = elementSize(a.componentType, a.type);
  const auto& s = a.sparse;
  const std::string sid = id + ": sparse";
  if (s.count < 1 || u64(s.count) > a.count)
    return Error{sid + ": count " + std::to_string(s.count) + " must be in [1, " + std::to_string(a.count) + "]"};
  if (s.indices.bufferView < 0 || s.indices.bufferView >= int(m.bufferViews.size()))
    return Error{sid + ".indices: bufferView " + std::to_string(s.indices.bufferView) + " does not exist"};
  if (s.values.bufferView < 0 || s.values.bufferView >= int(m.bufferViews.size()))
    return Error{sid + ".values: bufferView " + std::to_string(s.values.bufferView) + " does not exist"};
  const int ict = s.indices.componentType;
  if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return Error{sid + ".indices: componentType " + std::to_string(ict) + " is not an unsigned integer type"};
  if (s.indices.byteOffset < 0 || s.values.byteOffset < 0) return Error{sid + ": negative byteOffset"};
  const u64 ics = u64(componentSize(ict));
  if ((m.bufferViews[std::size_t(s.indices.bufferView)].byteOffset + u64(s.indices.byteOffset)) % ics != 0 ||
      (m.bufferViews[std::size_t(s.values.bufferView)].byteOffset + u64(s.values.byteOffset)) % u64(cs) != 0)
    return Error{sid + ": misaligned indices or values"};
  if (auto r = rangeInView(m, s.indices.bufferView, u64(s.indices.byteOffset), u64(s.count) * ics,
                           "indices (" + std::to_string(s.count) + " × " + std::to_string(ics) + " bytes)");
      !r)
    return Error{sid + ": " + r.error().message};
  if (auto r = rangeInView(m, s.values.bufferView, u64(s.values.byteOffset), u64(s.count) * es,
                           "values (" + std::to_string(s.count) + " × " + std::to_string(es) + " bytes)");
      !r)
    return Error{sid + ": " + r.error().message};
  const tinygltf::BufferView& iv = m.bufferViews[std::size_t(s.indices.bufferView)];
  const std::uint8_t* p = m.buffers[std::size_t(iv.buffer)].data.data() + iv.byteOffset + u64(s.indices.byteOffset);
  u64 prev = 0;
  for (int k = 0; k < s.count; ++k) {
    const u64 idx = readUnsigned(p + u64(k) * ics, ict);
    if (idx >= a.count)
      return Error{sid + ".indices[" + std::to_string(k) + "] = " + std::to_string(idx) + " is not below count " +
                   std::to_string(a.count)};
    if (k > 0 && idx <= prev)
      return Error{sid + ".indices[" + std::to_string(k) + "] = " + std::to_string(idx) + " is not increasing"};
    prev = idx;
  }
  return {};
}

Result<void> validateAccessor(const tinygltf::Model& m, std::size_t i, const GltfLimits& limits,
                              const std::string& file) {
  const tinygltf::Accessor& a = m.accessors[i];
  const std::string id = file + ": " + at("accessors", i);
  const int cs = componentSize(a.componentType);
  if (cs == 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_INT)
    return Error{id + ": componentType " + std::to_string(a.componentType) + " is not a glTF component type"};
  if (componentCount(a.type) == 0) return Error{id + ": unknown type"};
  if (a.count < 1) return Error{id + ": count " + std::to_string(a.count) + " must be at least 1"};
  if (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                       a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    return Error{id + ": normalized is only allowed for byte and short components"};
  const u64 es = elementSize(a.componentType, a.type);
  u64 total = 0;
  if (!mulOk(a.count, es, &total)) return Error{id + ": count " + std::to_string(a.count) + " overflows"};
  if (a.bufferView < -1 || a.bufferView >= static_cast<int>(m.bufferViews.size()))
    return Error{id + ": bufferView " + std::to_string(a.bufferView) + " does not exist"};
  if (a.bufferView >= 0) {
    if (auto r = checkAccessorView(m, a, id); !r) return r;
  } else {
    if (a.byteOffset != 0) return Error{id + ": byteOffset without a bufferView"};
    // Nothing backs the count of a view-less accessor (it is zeros, maybe with sparse values), so cap it
    // before anything allocates count × size.
    if (total > limits.maxFileBytes)
      return Error{id + ": count " + std::to_string(a.count) + " without a bufferView exceeds the cap maxFileBytes = " +
                   std::to_string(limits.maxFileBytes)};
  }
  if (a.sparse.isSparse)
    if (auto r = checkSparse(m, a, id); !r) return r;
  return {};
}

Result<void> checkTextureRef(const tinygltf::Model& m, int index, const std::string& id) {
  if (index < -1 || index >= int(m.textures.size()))
    return Error{id + ": texture " + std::to_string(index) + " does not exist"};
  return {};
}

// Accessor usage of one vertex attribute (glTF 3.7.2.1; KHR_mesh_quantization widens it).
Result<void> checkAttribute(const tinygltf::Model& m, const std::string& name, const tinygltf::Accessor& a,
                            const std::string& id) {
  const bool q = uses(m, "KHR_mesh_quantization");
  const int ct = a.componentType;
  const bool fl = ct == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool normU8U16 = a.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  const bool normI8I16 =
      a.normalized && (ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT);
  const bool anyInt = ct != TINYGLTF_COMPONENT_TYPE_FLOAT && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  auto bad = [&]() {
    return Error{id + ": attribute " + name + " cannot be " + typeName(a.type) + " of componentType " +
                 std::to_string(ct) + (a.normalized ? " (normalized)" : "")};
  };
  if (name == "POSITION") {
    if (a.type != TINYGLTF_TYPE_VEC3 || !(fl || (q && anyInt))) return bad();
  } else if (name == "NORMAL") {
    if (a.type != TINYGLTF_TYPE_VEC3 || !(fl || (q && normI8I16))) return bad();
  } else if (name == "TANGENT") {
    if (a.type != TINYGLTF_TYPE_VEC4 || !(fl || (q && normI8I16))) return bad();
  } else if (name.rfind("TEXCOORD_", 0) == 0) {
    if (a.type != TINYGLTF_TYPE_VEC2 || !(fl || normU8U16 || (q && anyInt))) return bad();
  } else if (name.rfind("COLOR_", 0) == 0) {
    if ((a.type != TINYGLTF_TYPE_VEC3 && a.type != TINYGLTF_TYPE_VEC4) || !(fl || normU8U16)) return bad();
  }
  return {};
}

}  // namespace

int componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // DOUBLE is a tinygltf extension, not glTF
  }
}

int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

std::uint64_t elementSize(int componentType, int type) {
  const u64 cs = u64(componentSize(componentType));
  const auto column = [&](u64 rows) { return (rows * cs + 3) / 4 * 4; };  // columns start 4-aligned
  switch (type) {
    case TINYGLTF_TYPE_MAT2: return 2 * column(2);
    case TINYGLTF_TYPE_MAT3: return 3 * column(3);
    case TINYGLTF_TYPE_MAT4: return 4 * column(4);
    default: return cs * u64(componentCount(type));
  }
}

bool supportedExtension(const std::string& name) {
  static const char* const names[] = {
      "KHR_materials_specular",   "KHR_materials_ior",   "KHR_materials_transmission",
      "KHR_materials_volume",     "KHR_materials_emissive_strength", "KHR_materials_unlit",
      "KHR_texture_transform",    "KHR_lights_punctual", "EXT_mesh_gpu_instancing",
      "KHR_mesh_quantization"};
  for (const char* n : names)
    if (name == n) return true;
  return false;
}

namespace {

// Asset and extensions.
Result<void> checkAsset(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  int major = 0, minor = 0;
  if (!parseVersion(m.asset.version, &major, &minor) || major != 2)
    return Error{f + "asset.version '" + m.asset.version + "' is not glTF 2.x"};
  if (!m.asset.minVersion.empty()) {
    if (!parseVersion(m.asset.minVersion, &major, &minor))
      return Error{f + "asset.minVersion '" + m.asset.minVersion + "' is not a version"};
    if (major != 2 || minor > 0)
      return Error{f + "asset.minVersion " + m.asset.minVersion + " is newer than the supported glTF 2.0"};
  }
  std::string unknown;
  for (const std::string& e : m.extensionsRequired)
    if (!supportedExtension(e)) unknown += (unknown.empty() ? "" : ", ") + e;
  if (!unknown.empty()) return Error{f + "extensionsRequired names unsupported extensions: " + unknown};
  return {};
}

// Caps on object counts.
Result<void> checkCounts(const tinygltf::Model& m, const GltfLimits& limits, const std::string& f) {
  if (m.nodes.size() > limits.maxNodes)
    return Error{f + std::to_string(m.nodes.size()) + " nodes exceed the cap maxNodes = " + std::to_string(limits.maxNodes)};
  const std::pair<const char*, std::size_t> counts[] = {
      {"accessors", m.accessors.size()}, {"bufferViews", m.bufferViews.size()}, {"buffers", m.buffers.size()},
      {"meshes", m.meshes.size()},       {"materials", m.materials.size()},     {"images", m.images.size()},
      {"textures", m.textures.size()},   {"animations", m.animations.size()},   {"scenes", m.scenes.size()}};
  for (const auto& [name, n] : counts)
    if (n > limits.maxObjects)
      return Error{f + std::to_string(n) + " " + name + " exceed the cap maxObjects = " + std::to_string(limits.maxObjects)};
  return {};
}

// Buffers, views, accessors.
Result<void> checkBuffers(const tinygltf::Model& m, const GltfLimits& limits, const std::string& file,
                          const std::string& f) {
  for (std::size_t i = 0; i < m.buffers.size(); ++i)
    if (m.buffers[i].data.empty()) return Error{f + at("buffers", i) + ": no data (byteLength 0 or not loaded)"};
  for (std::size_t i = 0; i < m.bufferViews.size(); ++i) {
    const tinygltf::BufferView& v = m.bufferViews[i];
    const std::string id = f + at("bufferViews", i);
    if (v.buffer < 0 || v.buffer >= int(m.buffers.size()))
      return Error{id + ": buffer " + std::to_string(v.buffer) + " does not exist"};
    if (v.byteLength < 1) return Error{id + ": byteLength must be at least 1"};
    const u64 size = m.buffers[std::size_t(v.buffer)].data.size();
    u64 end = 0;
    if (!addOk(v.byteOffset, v.byteLength, &end) || end > size)
      return Error{id + ": byteOffset " + std::to_string(v.byteOffset) + " + byteLength " + std::to_string(v.byteLength) +
                   " runs past " + at("buffers", std::size_t(v.buffer)) + " (length " + std::to_string(size) + ")"};
    if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4 != 0))
      return Error{id + ": byteStride " + std::to_string(v.byteStride) + " is not a multiple of 4 in [4, 252]"};
  }
  for (std::size_t i = 0; i < m.accessors.size(); ++i)
    if (auto r = validateAccessor(m, i, limits, file); !r) return r;
  return {};
}

// Images, samplers, textures, materials.
Result<void> checkMaterials(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  for (std::size_t i = 0; i < m.images.size(); ++i)
    if (m.images[i].bufferView < -1 || m.images[i].bufferView >= int(m.bufferViews.size()))
      return Error{f + at("images", i) + ": bufferView " + std::to_string(m.images[i].bufferView) + " does not exist"};
  for (std::size_t i = 0; i < m.textures.size(); ++i) {
    const tinygltf::Texture& t = m.textures[i];
    if (t.source < -1 || t.source >= int(m.images.size()))
      return Error{f + at("textures", i) + ": source " + std::to_string(t.source) + " does not exist"};
    if (t.sampler < -1 || t.sampler >= int(m.samplers.size()))
      return Error{f + at("textures", i) + ": sampler " + std::to_string(t.sampler) + " does not exist"};
  }
  for (std::size_t i = 0; i < m.materials.size(); ++i) {
    const tinygltf::Material& mat = m.materials[i];
    const std::string id = f + at("materials", i);
    const auto& pbr = mat.pbrMetallicRoughness;
    for (int tex : {pbr.baseColorTexture.index, pbr.metallicRoughnessTexture.index, mat.normalTexture.index,
                    mat.occlusionTexture.index, mat.emissiveTexture.index})
      if (auto r = checkTextureRef(m, tex, id); !r) return r;
    if (pbr.baseColorFactor.size() != 4 || !finiteAll(pbr.baseColorFactor) ||
        std::any_of(pbr.baseColorFactor.begin(), pbr.baseColorFactor.end(), [](double d) { return d < 0 || d > 1; }))
      return Error{id + ": baseColorFactor must be 4 numbers in [0, 1]"};
    if (!(pbr.metallicFactor >= 0 && pbr.metallicFactor <= 1) || !(pbr.roughnessFactor >= 0 && pbr.roughnessFactor <= 1))
      return Error{id + ": metallicFactor and roughnessFactor must be in [0, 1]"};
    if (!mat.emissiveFactor.empty() &&
        (mat.emissiveFactor.size() != 3 || !finiteAll(mat.emissiveFactor) ||
         std::any_of(mat.emissiveFactor.begin(), mat.emissiveFactor.end(), [](double d) { return d < 0 || d > 1; })))
      return Error{id + ": emissiveFactor must be 3 numbers in [0, 1]"};
    if (mat.alphaMode != "OPAQUE" && mat.alphaMode != "MASK" && mat.alphaMode != "BLEND")
      return Error{id + ": alphaMode '" + mat.alphaMode + "' is not OPAQUE, MASK or BLEND"};
    if (!(mat.alphaCutoff >= 0) || !std::isfinite(mat.alphaCutoff)) return Error{id + ": alphaCutoff must be >= 0"};
    if (!std::isfinite(mat.normalTexture.scale)) return Error{id + ": normalTexture.scale is not finite"};
  }
  return {};
}

// Meshes.
Result<void> checkMeshes(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  for (std::size_t i = 0; i < m.meshes.size(); ++i) {
    const tinygltf::Mesh& mesh = m.meshes[i];
    if (mesh.primitives.empty()) return Error{f + at("meshes", i) + ": no primitives"};
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& prim = mesh.primitives[p];
      const std::string id = f + at("meshes", i) + "." + at("primitives", p);
      if (prim.mode < -1 || prim.mode > TINYGLTF_MODE_TRIANGLE_FAN)
        return Error{id + ": mode " + std::to_string(prim.mode) + " is not a glTF primitive mode"};
      if (prim.material < -1 || prim.material >= int(m.materials.size()))
        return Error{id + ": material " + std::to_string(prim.material) + " does not exist"};
      u64 vertexCount = 0;
      for (const auto& [name, acc] : prim.attributes) {
        if (acc < 0 || acc >= int(m.accessors.size()))
          return Error{id + ": attribute " + name + " names accessor " + std::to_string(acc) + ", which does not exist"};
        const tinygltf::Accessor& a = m.accessors[std::size_t(acc)];
        if (auto r = checkAttribute(m, name, a, id); !r) return r;
        if (vertexCount != 0 && a.count != vertexCount)
          return Error{id + ": attribute " + name + " has " + std::to_string(a.count) + " elements, others have " +
                       std::to_string(vertexCount)};
        vertexCount = a.count;
      }
      for (std::size_t t = 0; t < prim.targets.size(); ++t)
        for (const auto& [name, acc] : prim.targets[t])
          if (acc < 0 || acc >= int(m.accessors.size()))
            return Error{id + ": targets[" + std::to_string(t) + "]." + name + " names accessor " + std::to_string(acc) +
                         ", which does not exist"};
      if (prim.indices != -1) {
        if (prim.indices < 0 || prim.indices >= int(m.accessors.size()))
          return Error{id + ": indices accessor " + std::to_string(prim.indices) + " does not exist"};
        const tinygltf::Accessor& a = m.accessors[std::size_t(prim.indices)];
        const int ct = a.componentType;
        if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized ||
            (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
          return Error{id + ": indices " + at("accessors", std::size_t(prim.indices)) +
                       " must be SCALAR unsigned byte/short/int, not normalized"};
        if (a.bufferView >= 0 && m.bufferViews[std::size_t(a.bufferView)].byteStride != 0)
          return Error{id + ": indices " + at("accessors", std::size_t(prim.indices)) + " lie in a strided bufferView"};
      }
    }
  }
  return {};
}

// Nodes: references, finite transforms, single parent, no cycle; the parent of each node (−1 for roots).
Result<std::vector<int>> checkNodes(const tinygltf::Model& m, const std::string& f) {
  std::vector<int> parent(m.nodes.size(), -1);
  for (std::size_t i = 0; i < m.nodes.size(); ++i) {
    const tinygltf::Node& n = m.nodes[i];
    const std::string id = f + at("nodes", i);
    if (n.mesh < -1 || n.mesh >= int(m.meshes.size())) return Error{id + ": mesh " + std::to_string(n.mesh) + " does not exist"};
    if (n.camera < -1 || n.camera >= int(m.cameras.size()))
      return Error{id + ": camera " + std::to_string(n.camera) + " does not exist"};
    if (n.skin < -1 || n.skin >= int(m.skins.size())) return Error{id + ": skin " + std::to_string(n.skin) + " does not exist"};
    if (!n.matrix.empty() && n.matrix.size() != 16) return Error{id + ": matrix must have 16 numbers"};
    if (!n.translation.empty() && n.translation.size() != 3) return Error{id + ": translation must have 3 numbers"};
    if (!n.rotation.empty() && n.rotation.size() != 4) return Error{id + ": rotation must have 4 numbers"};
    if (!n.scale.empty() && n.scale.size() != 3) return Error{id + ": scale must have 3 numbers"};
    if (!finiteAll(n.matrix) || !finiteAll(n.translation) || !finiteAll(n.rotation) || !finiteAll(n.scale))
      return Error{id + ": transform contains NaN or infinity"};
    if (!n.matrix.empty() && (!n.translation.empty() || !n.rotation.empty() || !n.scale.empty()))
      return Error{id + ": has both matrix and translation/rotation/scale"};
    if (!n.rotation.empty()) {
      const double len2 = n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                          n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3];
      if (!(len2 > 1e-12)) return Error{id + ": rotation is a zero quaternion"};
    }
    for (int c : n.children) {
      if (c < 0 || c >= int(m.nodes.size())) return Error{id + ": child " + std::to_string(c) + " does not exist"};
      if (std::size_t(c) == i) return Error{id + ": is its own child"};
      if (parent[std::size_t(c)] != -1)
        return Error{id + ": child " + std::to_string(c) + " already has parent " + std::to_string(parent[std::size_t(c)])};
      parent[std::size_t(c)] = int(i);
    }
  }
  {
    // With one parent each, a cycle is a parent chain that returns to itself. Colour the chains
    // iteratively (0 = unvisited, 1 = on the current chain, 2 = known to reach a root): O(nodes).
    std::vector<std::uint8_t> state(m.nodes.size(), 0);
    std::vector<std::size_t> chain;
    for (std::size_t s = 0; s < m.nodes.size(); ++s) {
      chain.clear();
      std::size_t n = s;
      while (true) {
        if (state[n] == 2) break;
        if (state[n] == 1) return Error{f + at("nodes", n) + ": is part of a cycle in the node hierarchy"};
        state[n] = 1;
        chain.push_back(n);
        if (parent[n] < 0) break;
        n = std::size_t(parent[n]);
      }
      for (std::size_t c : chain) state[c] = 2;
    }
  }
  return parent;
}

// Scenes: references, roots that are roots, no node twice.
Result<void> checkScenes(const tinygltf::Model& m, const std::string& f, const std::vector<int>& parent) {
  if (m.defaultScene < -1 || m.defaultScene >= int(m.scenes.size()))
    return Error{f + "scene " + std::to_string(m.defaultScene) + " does not exist"};
  for (std::size_t i = 0; i < m.scenes.size(); ++i) {
    std::set<int> seen;
    for (int n : m.scenes[i].nodes) {
      if (n < 0 || n >= int(m.nodes.size()))
        return Error{f + at("scenes", i) + ": node " + std::to_string(n) + " does not exist"};
      if (parent[std::size_t(n)] != -1)
        return Error{f + at("scenes", i) + ": node " + std::to_string(n) + " is not a root (its parent is " +
                     std::to_string(parent[std::size_t(n)]) + ")"};
      if (!seen.insert(n).second) return Error{f + at("scenes", i) + ": node " + std::to_string(n) + " listed twice"};
    }
  }
  return {};
}

// Cameras (types only; bad parameters skip the camera at import).
Result<void> checkCameras(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  for (std::size_t i = 0; i < m.cameras.size(); ++i)
    if (m.cameras[i].type != "perspective" && m.cameras[i].type != "orthographic")
      return Error{f + at("cameras", i) + ": type '" + m.cameras[i].type + "' is not perspective or orthographic"};
  return {};
}

// Animations (references; content problems skip the channel at import).
Result<void> checkAnimations(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  for (std::size_t i = 0; i < m.animations.size(); ++i) {
    const tinygltf::Animation& an = m.animations[i];
    const std::string id = f + at("animations", i);
    for (std::size_t s = 0; s < an.samplers.size(); ++s) {
      const auto& smp = an.samplers[s];
      if (smp.input < 0 || smp.input >= int(m.accessors.size()) || smp.output < 0 || smp.output >= int(m.accessors.size()))
        return Error{id + "." + at("samplers", s) + ": input or output accessor does not exist"};
      if (smp.interpolation != "LINEAR" && smp.interpolation != "STEP" && smp.interpolation != "CUBICSPLINE")
        return Error{id + "." + at("samplers", s) + ": interpolation '" + smp.interpolation + "' is unknown"};
    }
    for (std::size_t c = 0; c < an.channels.size(); ++c) {
      const auto& ch = an.channels[c];
      if (ch.sampler < 0 || ch.sampler >= int(an.samplers.size()))
        return Error{id + "." + at("channels", c) + ": sampler " + std::to_string(ch.sampler) + " does not exist"};
      if (ch.target_node < -1 || ch.target_node >= int(m.nodes.size()))
        return Error{id + "." + at("channels", c) + ": target node " + std::to_string(ch.target_node) + " does not exist"};
    }
  }
  return {};
}

// Skins (ignored at import, but their references must still be sound).
Result<void> checkSkins(const tinygltf::Model& m, const GltfLimits&, const std::string& f) {
  for (std::size_t i = 0; i < m.skins.size(); ++i) {
    const tinygltf::Skin& s = m.skins[i];
    if (s.inverseBindMatrices < -1 || s.inverseBindMatrices >= int(m.accessors.size()))
      return Error{f + at("skins", i) + ": inverseBindMatrices accessor does not exist"};
    if (s.skeleton < -1 || s.skeleton >= int(m.nodes.size())) return Error{f + at("skins", i) + ": skeleton node does not exist"};
    for (int j : s.joints)
      if (j < 0 || j >= int(m.nodes.size()))
        return Error{f + at("skins", i) + ": joint " + std::to_string(j) + " does not exist"};
  }
  return {};
}

}  // namespace

Result<void> validateModel(const tinygltf::Model& m, const GltfLimits& limits, const std::string& file) {
  const std::string f = file + ": ";
  if (auto r = checkAsset(m, limits, f); !r) return r;
  if (auto r = checkCounts(m, limits, f); !r) return r;
  if (auto r = checkBuffers(m, limits, file, f); !r) return r;
  if (auto r = checkMaterials(m, limits, f); !r) return r;
  if (auto r = checkMeshes(m, limits, f); !r) return r;
  auto parent = checkNodes(m, f);
  if (!parent) return parent.error();
  if (auto r = checkScenes(m, f, *parent); !r) return r;
  if (auto r = checkCameras(m, limits, f); !r) return r;
  if (auto r = checkAnimations(m, limits, f); !r) return r;
  if (auto r = checkSkins(m, limits, f); !r) return r;
  return {};
}


namespace {
/// Where a sparse accessor's index and value arrays start (ranges already validated).
struct SparseData {
  const std::uint8_t* indices;
  const std::uint8_t* values;
  std::size_t indexSize;
};
SparseData sparseOf(const tinygltf::Model& m, const tinygltf::Accessor& a) {
  const auto& s = a.sparse;  // an unnamed struct in tinygltf 2.7
  const tinygltf::BufferView& iv = m.bufferViews[std::size_t(s.indices.bufferView)];
  const tinygltf::BufferView& vv = m.bufferViews[std::size_t(s.values.bufferView)];
  return {m.buffers[std::size_t(iv.buffer)].data.data() + iv.byteOffset + std::size_t(s.indices.byteOffset),
          m.buffers[std::size_t(vv.buffer)].data.data() + vv.byteOffset + std::size_t(s.values.byteOffset),
          std::size_t(componentSize(s.indices.componentType))};
}
}  // namespace

Result<std::vector<float>> readFloats(const tinygltf::Model& m, int accessor, const std::string& file,
                                      LoadBudget* budget) {
  const tinygltf::Accessor& a = m.accessors[std::size_t(accessor)];
  if (a.type >= TINYGLTF_TYPE_MAT2 && a.type <= TINYGLTF_TYPE_MAT4)
    return Error{file + ": " + at("accessors", std::size_t(accessor)) + ": matrix accessors are not read"};
  const std::size_t nc = std::size_t(componentCount(a.type));
  const std::size_t cs = std::size_t(componentSize(a.componentType));
  // count·nc fits: validateModel bounded count·elementSize by the view (or maxFileBytes for view-less ones).
  if (budget && !budget->charge(u64(a.count) * nc * sizeof(float)))
    return Error{file + ": " + budget->refusal("reading " + at("accessors", std::size_t(accessor)),
                                               u64(a.count) * nc * sizeof(float))};
  std::vector<float> out(a.count * nc, 0.0f);
  const Layout l = layoutOf(m, a);
  if (l.base)
    for (std::size_t i = 0; i < a.count; ++i)
      for (std::size_t c = 0; c < nc; ++c)
        out[i * nc + c] = static_cast<float>(readComponent(l.base + i * l.stride + c * cs, a.componentType, a.normalized));
  if (a.sparse.isSparse) {
    const auto& s = a.sparse;
    const SparseData sd = sparseOf(m, a);
    const std::uint8_t* ip = sd.indices;
    const std::uint8_t* vp = sd.values;
    const std::size_t ics = sd.indexSize;
    for (std::size_t k = 0; k < std::size_t(s.count); ++k) {
      const std::size_t idx = std::size_t(readUnsigned(ip + k * ics, s.indices.componentType));  // < count: validated
      for (std::size_t c = 0; c < nc; ++c)
        out[idx * nc + c] = static_cast<float>(readComponent(vp + (k * nc + c) * cs, a.componentType, a.normalized));
    }
  }
  return out;
}

Result<std::vector<std::uint32_t>> readIndices(const tinygltf::Model& m, int accessor, const std::string& file,
                                               LoadBudget* budget) {
  const tinygltf::Accessor& a = m.accessors[std::size_t(accessor)];
  if (a.type != TINYGLTF_TYPE_SCALAR || componentSize(a.componentType) == 0 ||
      a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
    return Error{file + ": " + at("accessors", std::size_t(accessor)) + ": not an index accessor"};
  if (budget && !budget->charge(u64(a.count) * sizeof(std::uint32_t)))
    return Error{file + ": " + budget->refusal("reading " + at("accessors", std::size_t(accessor)),
                                               u64(a.count) * sizeof(std::uint32_t))};
  // Read as integers, not through readFloats: a float holds integers exactly only up to 2^24.
  std::vector<std::uint32_t> out(a.count, 0);
  const Layout l = layoutOf(m, a);
  if (l.base)
    for (std::size_t i = 0; i < a.count; ++i)
      out[i] = static_cast<std::uint32_t>(readUnsigned(l.base + i * l.stride, a.componentType));
  if (a.sparse.isSparse) {
    const auto& s = a.sparse;
    const SparseData sd = sparseOf(m, a);
    const std::uint8_t* ip = sd.indices;
    const std::uint8_t* vp = sd.values;
    const std::size_t ics = sd.indexSize;
    const std::size_t cs = std::size_t(componentSize(a.componentType));
    for (std::size_t k = 0; k < std::size_t(s.count); ++k)
      out[std::size_t(readUnsigned(ip + k * ics, s.indices.componentType))] =
          static_cast<std::uint32_t>(readUnsigned(vp + k * cs, a.componentType));
  }
  return out;
}

}  // namespace tandem::gltf
