#pragma once
// The glTF importer's conversion of a validated tinygltf::Model into a Scene (GltfInternal.h has the
// pipeline): the Importer class, whose work is split by what it converts — GltfMaterials.cpp (materials,
// textures), GltfMeshes.cpp (primitives to meshes), GltfImport.cpp (nodes, instances, cameras, lights, the
// load itself). Internal to the loader.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <glm/glm.hpp>

#include "io/GltfInternal.h"
#include "io/LoadBudget.h"

namespace tandem::gltf {

using u64 = std::uint64_t;

inline bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finiteMat(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    if (!finite3(glm::vec3(m[c])) || !std::isfinite(m[c][3])) return false;
  return true;
}

// A tinygltf extension value read defensively: numbers only when they are numbers.
inline double num(const tinygltf::Value& v, const char* key, double fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& x = v.Get(key);
  if (!x.IsNumber()) return fallback;
  const double d = x.GetNumberAsDouble();
  return std::isfinite(d) ? d : fallback;
}
inline int intOf(const tinygltf::Value& v, const char* key, int fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& x = v.Get(key);
  return x.IsInt() ? x.GetNumberAsInt() : fallback;  // checkJsonTypes bounded index-like integers to int
}
inline glm::vec3 vec3Of(const tinygltf::Value& v, const char* key, glm::vec3 fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& a = v.Get(key);
  if (!a.IsArray() || a.ArrayLen() != 3) return fallback;
  glm::vec3 r;
  for (int i = 0; i < 3; ++i) {
    if (!a.Get(i).IsNumber()) return fallback;
    r[i] = static_cast<float>(a.Get(i).GetNumberAsDouble());
  }
  return finite3(r) ? r : fallback;
}
inline const tinygltf::Value* ext(const tinygltf::ExtensionMap& m, const char* name) {
  auto it = m.find(name);
  return it == m.end() ? nullptr : &it->second;
}

inline bool isPng(const std::uint8_t* p, std::size_t n) {
  static const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return n >= 8 && std::memcmp(p, sig, 8) == 0;
}
inline bool isJpeg(const std::uint8_t* p, std::size_t n) { return n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF; }

class Importer {
 public:
  Importer(const tinygltf::Model& m, const GltfOptions& o, std::string file, Warn& w, DeferredImages& img,
           LoadBudget& budget)
      : m_(m), opt_(o), file_(std::move(file)), warn_(w), images_(img), budget_(budget) {}

  Result<GltfAsset> run();

 private:
  Error err(const std::string& msg) const { return Error{file_ + ": " + msg}; }
  Result<void> charge(const std::string& what, u64 bytes) {
    if (budget_.charge(bytes)) return {};
    return err(budget_.refusal(what, bytes));
  }
  Result<std::shared_ptr<const std::vector<float>>> attribute(int accessor);
  Result<void> buildMaterials();
  Result<void> readFactorMaps(const tinygltf::Material& g, const std::string& id, std::size_t material);
  glm::dvec4 wholeMean(int texture);
  void applyFactorMaps();
  /// A double-sided copy of a single-sided material, for the instances of a skinned (unposed) mesh.
  std::uint32_t unposedMaterial(std::uint32_t material);
  Result<void> attachMaterialTextures(Material& mat, const tinygltf::Material& g, const std::string& id);
  int texture(int gltfTexture, bool srgb, const std::string& usage);
  int fallbackTexture();
  Result<int> meshFor(int mesh, int prim, bool flip);
  Result<Mesh> convertPrimitive(int mesh, int prim);
  Result<void> readNormals(const tinygltf::Primitive& p, const std::string& id, const std::vector<std::uint32_t>& used,
                           std::size_t n, Mesh& mesh);
  Result<void> readUvsAndColours(const tinygltf::Primitive& p, const std::string& id,
                                 const std::vector<std::uint32_t>& used, std::size_t n, Mesh& mesh);
  Result<void> readTangents(const tinygltf::Primitive& p, const std::string& id, const std::vector<std::uint32_t>& used,
                            std::size_t n, Mesh& mesh);
  Result<std::vector<std::uint32_t>> triangleList(const tinygltf::Primitive& p, std::size_t vertexCount,
                                                  const std::string& id);
  Result<void> traverse(const std::vector<int>& roots);
  Result<void> reserveInstances(const std::vector<int>& roots, bool animating);
  Result<void> addMeshInstances(const tinygltf::Node& n, std::size_t nodeIndex, const glm::mat4& world, bool dynamic,
                                int animIndex);
  Result<std::vector<glm::mat4>> gpuInstances(const tinygltf::Node& n, std::size_t nodeIndex);
  void addCamera(const tinygltf::Node& n, const glm::mat4& world);
  void addLight(const tinygltf::Node& n, std::size_t nodeIndex, const glm::mat4& world);
  void addDefaults();
  void warnOnce(const std::string& key, const std::string& msg) {
    if (warned_.insert({key, true}).second) warn_(msg);
  }

  const tinygltf::Model& m_;
  const GltfOptions& opt_;
  std::string file_;
  Warn& warn_;
  DeferredImages& images_;
  LoadBudget& budget_;
  std::optional<Error> budgetRefusal_;  // set by texture(), which answers an index, and checked by its callers
  GltfAsset out_;
  std::vector<int> materialOf_;   // glTF material → scene material
  std::vector<bool> wantsTangents_;  // per glTF material: has a normal map
  int defaultMaterial_ = -1;
  int fallbackTexture_ = -1;
  // (source kind, id, srgb) → scene texture or -1. Kinds: 0 a bufferView, 1 distinct bytes read by URI
  // (images_.unique), 2 an image whose file could not be read.
  std::map<std::tuple<int, int, bool>, int> textureCache_;
  std::map<int, glm::dvec4> textureMeans_;  // scene texture → its texels' mean, channels in [0, 1]
  // The textures that scale a material's factors (not sampled per pixel: one Phong lobe per material), read
  // through their means over the texels the material's triangles cover (applyFactorMaps, after the meshes).
  struct FactorMaps {
    int metallicRoughness = -1, transmission = -1;        // scene textures, -1 for none
    glm::mat3 metallicRoughnessUv{1.0f}, transmissionUv{1.0f};  // each map's KHR_texture_transform
    bool metallicRoughnessOnUv0 = true, transmissionOnUv0 = true;  // read on TEXCOORD_0 (else: the whole mean)
  };
  std::vector<FactorMaps> factorMaps_;  // per glTF material
  std::map<std::uint32_t, std::uint32_t> unposedCopy_;  // scene material → its double-sided copy
  std::map<std::tuple<int, int, bool>, int> meshCache_;  // (mesh, primitive, flipped) → scene mesh or -1
  // Primitives that read the same accessors the same way share one scene mesh, whichever glTF mesh holds
  // them: (POSITION, NORMAL, TEXCOORD_0, COLOR_0, TANGENT, indices, mode, tangents wanted, flipped).
  std::map<std::array<int, 9>, int> contentCache_;
  // Attribute arrays read recently: primitives of one mesh often share a vertex array, which is then read
  // (and charged to the budget) once rather than once per primitive.
  std::vector<std::pair<int, std::shared_ptr<const std::vector<float>>>> readCache_;
  std::map<std::string, bool> warned_;
  u64 totalPixels_ = 0;
  u64 triangles_ = 0;
  bool haveCamera_ = false;
  std::vector<int> animIndexOfNode_;
  std::vector<bool> animated_;  // glTF node targeted by a TRS channel
};

}  // namespace tandem::gltf
