// loadGltf: the hardened pipeline (GltfInternal.h) and the conversion of a validated model into a Scene.
// docs/gltf.md documents the material mapping, light units, defaults, limits and refusals.
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <array>
#include <map>
#include <memory>
#include <new>
#include <optional>
#include <numbers>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "core/StbGuard.h"
#include "scene/GltfInternal.h"
#include "tandem/Image.h"
#include "tandem/Log.h"

namespace tandem {

using namespace gltf;
namespace fs = std::filesystem;

void gltf::Warn::operator()(const std::string& message) {
  ++count;
  const std::string full = file + ": " + message;
  // A hostile file can ask for a warning per object; the log shows the first ones (the callback sees all).
  constexpr int kLogged = 100;
  if (count <= kLogged) logWarning(full);
  else if (count == kLogged + 1) logWarning(file + ": further warnings are not logged");
  if (options && options->onWarning) options->onWarning(full);
}

namespace {

using u64 = std::uint64_t;

bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finiteMat(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    if (!finite3(glm::vec3(m[c])) || !std::isfinite(m[c][3])) return false;
  return true;
}

// A tinygltf extension value read defensively: numbers only when they are numbers.
double num(const tinygltf::Value& v, const char* key, double fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& x = v.Get(key);
  if (!x.IsNumber()) return fallback;
  const double d = x.GetNumberAsDouble();
  return std::isfinite(d) ? d : fallback;
}
int intOf(const tinygltf::Value& v, const char* key, int fallback) {
  if (!v.IsObject() || !v.Has(key)) return fallback;
  const tinygltf::Value& x = v.Get(key);
  return x.IsInt() ? x.GetNumberAsInt() : fallback;  // checkJsonTypes bounded index-like integers to int
}
glm::vec3 vec3Of(const tinygltf::Value& v, const char* key, glm::vec3 fallback) {
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
const tinygltf::Value* ext(const tinygltf::ExtensionMap& m, const char* name) {
  auto it = m.find(name);
  return it == m.end() ? nullptr : &it->second;
}

bool isPng(const std::uint8_t* p, std::size_t n) {
  static const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return n >= 8 && std::memcmp(p, sig, 8) == 0;
}
bool isJpeg(const std::uint8_t* p, std::size_t n) { return n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF; }

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
  int texture(int gltfTexture, bool srgb, const std::string& usage);
  int fallbackTexture();
  Result<int> meshFor(int mesh, int prim, bool flip);
  Result<Mesh> convertPrimitive(int mesh, int prim);
  Result<void> traverse(const std::vector<int>& roots);
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
  std::map<int, glm::dvec2> textureMeans_;            // scene texture → mean green, blue in [0, 1]
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

// ---- textures ----

int Importer::fallbackTexture() {
  // SKIP policy for images (bad-inputs.md I2–I4, U13): the material keeps a neutral white texture so the
  // rest renders and nothing indexes a missing texture.
  if (fallbackTexture_ < 0) {
    Texture t;
    t.name = "fallback";
    t.width = t.height = 2;
    t.rgba8.assign(16, 255);
    fallbackTexture_ = int(out_.scene.textures.size());
    out_.scene.textures.push_back(std::move(t));
  }
  return fallbackTexture_;
}

int Importer::texture(int gltfTexture, bool srgb, const std::string& usage) {
  if (gltfTexture < 0) return -1;
  const tinygltf::Texture& t = m_.textures[std::size_t(gltfTexture)];
  const std::string id = "textures[" + std::to_string(gltfTexture) + "] (" + usage + ")";
  if (t.source < 0) {
    warn_(id + ": no image source (or only an unsupported extension source); fallback texture used");
    return srgb ? fallbackTexture() : -1;
  }
  const tinygltf::Image& img = m_.images[std::size_t(t.source)];
  // Decoded once per distinct source (a bufferView, or distinct bytes read by URI), however many images and
  // textures name it.
  std::tuple<int, int, bool> key{2, t.source, srgb};
  if (img.bufferView >= 0) key = {0, img.bufferView, srgb};
  else if (auto it = images_.sourceOf.find(t.source); it != images_.sourceOf.end()) key = {1, it->second, srgb};
  if (auto it = textureCache_.find(key); it != textureCache_.end()) return it->second;
  auto fail = [&](const std::string& why) {
    warn_("images[" + std::to_string(t.source) + "]: " + why + "; " + (srgb ? "fallback texture used" : "map dropped"));
    const int r = srgb ? fallbackTexture() : -1;
    textureCache_[key] = r;
    return r;
  };
  if (std::get<0>(key) == 2) return fail("'" + img.uri.substr(0, 200) + "' could not be read (missing file?)");
  const std::uint8_t* bytes = nullptr;
  std::size_t size = 0;
  if (img.bufferView >= 0) {
    const tinygltf::BufferView& v = m_.bufferViews[std::size_t(img.bufferView)];  // range validated
    bytes = m_.buffers[std::size_t(v.buffer)].data.data() + v.byteOffset;
    size = v.byteLength;
  } else {
    const std::vector<std::uint8_t>& u = images_.unique[std::size_t(std::get<1>(key))];
    bytes = u.data();
    size = u.size();
  }
  if (!isPng(bytes, size) && !isJpeg(bytes, size)) return fail("not PNG or JPEG data (only those are decoded)");
  if (size > std::size_t(INT32_MAX)) return fail("encoded image too large");
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &comp) || w <= 0 || h <= 0)
    return fail(std::string("unreadable header (") + (stbi_failure_reason() ? stbi_failure_reason() : "?") + ")");
  const u64 pixels = u64(w) * u64(h);
  if (pixels > opt_.limits.maxImagePixels)
    return fail(std::to_string(w) + "×" + std::to_string(h) + " exceeds the cap maxImagePixels = " +
                std::to_string(opt_.limits.maxImagePixels));
  if (totalPixels_ + pixels > opt_.limits.maxTotalPixels)
    return fail("decoding it would exceed the cap maxTotalPixels = " + std::to_string(opt_.limits.maxTotalPixels));
  // The texels are charged before decoding; a file refused here fails the load (it is a resource refusal,
  // not a broken image).
  if (!budget_.charge(pixels * 4)) {
    budgetRefusal_ = err(budget_.refusal("decoding images[" + std::to_string(t.source) + "]", pixels * 4));
    return -1;
  }
  stbi_uc* px = nullptr;
  {
    // The decoder's own memory: a stream that inflates past the declared rows is cut off.
    StbMemoryCap cap(imageDecodeBytes(pixels, size));
    px = stbi_load_from_memory(bytes, int(size), &w, &h, &comp, 4);
    if (!px && cap.refused()) return fail("decoding needs more memory than its declared size allows");
  }
  if (!px) return fail(std::string("decoding failed (") + (stbi_failure_reason() ? stbi_failure_reason() : "?") + ")");
  Texture tex;
  tex.name = !img.name.empty() ? img.name : img.uri.substr(0, 200);
  tex.width = w;
  tex.height = h;
  tex.srgb = srgb;
  tex.rgba8.assign(px, px + pixels * 4);
  stbi_image_free(px);
  totalPixels_ += pixels;
  const int index = int(out_.scene.textures.size());
  out_.scene.textures.push_back(std::move(tex));
  textureCache_[key] = index;
  return index;
}

// ---- materials ----

glm::mat3 textureTransform(const tinygltf::ExtensionMap& e) {
  const tinygltf::Value* tt = ext(e, "KHR_texture_transform");
  if (!tt) return glm::mat3(1.0f);
  glm::vec2 offset(0.0f), scale(1.0f);
  if (tt->Has("offset") && tt->Get("offset").ArrayLen() == 2 && tt->Get("offset").Get(0).IsNumber() &&
      tt->Get("offset").Get(1).IsNumber())
    offset = {float(tt->Get("offset").Get(0).GetNumberAsDouble()), float(tt->Get("offset").Get(1).GetNumberAsDouble())};
  if (tt->Has("scale") && tt->Get("scale").ArrayLen() == 2 && tt->Get("scale").Get(0).IsNumber() &&
      tt->Get("scale").Get(1).IsNumber())
    scale = {float(tt->Get("scale").Get(0).GetNumberAsDouble()), float(tt->Get("scale").Get(1).GetNumberAsDouble())};
  const float rot = float(num(*tt, "rotation", 0.0));
  if (!std::isfinite(offset.x) || !std::isfinite(offset.y) || !std::isfinite(scale.x) || !std::isfinite(scale.y))
    return glm::mat3(1.0f);
  // KHR_texture_transform README: uv' = T · R · S · (u, v, 1), matrices column-major as in GLSL.
  const glm::mat3 T(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::mat3 R(std::cos(rot), std::sin(rot), 0, -std::sin(rot), std::cos(rot), 0, 0, 0, 1);
  const glm::mat3 S(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return T * R * S;
}

Result<void> Importer::buildMaterials() {
  for (std::size_t i = 0; i < m_.materials.size(); ++i) {
    const tinygltf::Material& g = m_.materials[i];
    const auto& pbr = g.pbrMetallicRoughness;
    const std::string id = "materials[" + std::to_string(i) + "]";
    Material mat;
    mat.name = g.name;
    const glm::vec3 base(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
    float metallic = float(pbr.metallicFactor), rough = float(pbr.roughnessFactor);
    // The metallic-roughness texture is not sampled per pixel (one Phong lobe per material): its mean
    // blue (metal) and green (roughness) channels scale the factors, so a mostly dielectric surface
    // with a few metal parts is not shaded as solid metal (glTF's default metallicFactor is 1).
    if (pbr.metallicRoughnessTexture.index >= 0) {
      const int mr = texture(pbr.metallicRoughnessTexture.index, false, id + " metallic-roughness");
      if (budgetRefusal_) return *budgetRefusal_;
      if (mr >= 0) {
        // Once per texture, not per material: many materials may share one large map.
        auto [it, fresh] = textureMeans_.try_emplace(mr, glm::dvec2(1.0));
        const Texture& t = out_.scene.textures[std::size_t(mr)];
        const std::size_t texels = t.rgba8.size() / 4;
        if (fresh && texels > 0) {
          double green = 0.0, blue = 0.0;
          for (std::size_t k = 0; k < texels; ++k) {
            green += t.rgba8[4 * k + 1];
            blue += t.rgba8[4 * k + 2];
          }
          it->second = glm::dvec2(green, blue) / (255.0 * double(texels));
        }
        rough *= float(it->second.x);
        metallic *= float(it->second.y);
      }
    }
    float ior = 1.5f;
    if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_ior")) {
      const double v = num(*e, "ior", 1.5);
      // The extension allows 0 (meaning "no refraction"); anything else must be >= 1. Clamp the rest.
      ior = v == 0.0 ? 1.0f : float(std::clamp(v, 1.0, 5.0));
      if (v != 0.0 && (v < 1.0 || v > 5.0)) warn_(id + ": ior " + std::to_string(v) + " clamped to [1, 5]");
    }
    float specular = 1.0f;
    glm::vec3 specularColor(1.0f);
    if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_specular")) {
      specular = float(std::clamp(num(*e, "specularFactor", 1.0), 0.0, 1.0));
      specularColor = glm::clamp(vec3Of(*e, "specularColorFactor", glm::vec3(1.0f)), 0.0f, 1e3f);
    }
    float transmission = 0.0f;
    if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_transmission"))
      transmission = float(std::clamp(num(*e, "transmissionFactor", 0.0), 0.0, 1.0));
    bool thick = false;
    if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_volume")) thick = num(*e, "thicknessFactor", 0.0) > 0.0;
    float emissiveStrength = 1.0f;
    if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_emissive_strength"))
      emissiveStrength = float(std::clamp(num(*e, "emissiveStrength", 1.0), 0.0, 1e6));

    // Fresnel reflectance at normal incidence: dielectric F0 from the IOR, scaled by KHR_materials_specular;
    // metals reflect their base colour.
    const float f0d = std::pow((ior - 1.0f) / (ior + 1.0f), 2.0f);
    const glm::vec3 f0Dielectric = glm::min(glm::vec3(f0d) * specularColor * specular, glm::vec3(1.0f));
    mat.ks = glm::mix(f0Dielectric, base, metallic);
    // Energy that is not reflected specularly by metals or transmitted goes to the diffuse lobe.
    mat.kd = base * (1.0f - metallic) * (1.0f - transmission);
    mat.ka = mat.kd;
    // Phong exponent from GGX roughness: α = roughness², ns = 2/α² − 2 (Walter et al. 2007, Beckmann↔Phong).
    const float alpha = std::max(rough * rough, 1e-3f);
    mat.ns = std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 10000.0f);
    // Mirror rays only for smooth surfaces: rough ones would need blurred reflections we do not trace.
    const float smooth = (1.0f - rough) * (1.0f - rough);
    const float f0Max = std::max({f0Dielectric.x, f0Dielectric.y, f0Dielectric.z});
    mat.kr = std::clamp(smooth * (metallic + (1.0f - metallic) * f0Max), 0.0f, 1.0f);
    mat.kt = transmission * (1.0f - metallic);
    // Without KHR_materials_volume a transmissive surface is thin-walled: light passes without bending.
    mat.ior = (mat.kt > 0.0f && !thick) ? 1.0f : ior;
    // glTF tints transmitted light by the base colour (KHR_materials_transmission); texture not included.
    mat.transmissionTint = base;
    if (g.emissiveFactor.size() == 3)
      mat.emission = glm::vec3(float(g.emissiveFactor[0]), float(g.emissiveFactor[1]), float(g.emissiveFactor[2])) *
                     emissiveStrength;
    mat.opacity = float(pbr.baseColorFactor[3]);
    mat.alphaMode = g.alphaMode == "MASK" ? AlphaMode::Mask : g.alphaMode == "BLEND" ? AlphaMode::Blend : AlphaMode::Opaque;
    mat.alphaCutoff = float(g.alphaCutoff);
    // BLEND is thin transmission: the uncovered fraction passes straight through (IOR 1). A refracting
    // BLEND material would need two transmitted rays (bent and straight); it keeps one, unbent.
    if (mat.alphaMode == AlphaMode::Blend && mat.ior != 1.0f) mat.ior = 1.0f;
    mat.doubleSided = g.doubleSided;
    if (ext(g.extensions, "KHR_materials_unlit")) {
      mat.unlit = true;
      mat.kd = base;
      mat.ka = glm::vec3(0.0f);
      mat.ks = glm::vec3(0.0f);
      mat.kr = mat.kt = 0.0f;
    }
    auto texCoordOf = [&](const tinygltf::ExtensionMap& e, int texCoord) {
      const tinygltf::Value* tt = ext(e, "KHR_texture_transform");
      return tt ? intOf(*tt, "texCoord", texCoord) : texCoord;
    };
    if (pbr.baseColorTexture.index >= 0) {
      mat.kdTexture = texture(pbr.baseColorTexture.index, true, id + " base colour");
      if (budgetRefusal_) return *budgetRefusal_;
      mat.uvTransform = textureTransform(pbr.baseColorTexture.extensions);
      if (texCoordOf(pbr.baseColorTexture.extensions, pbr.baseColorTexture.texCoord) != 0)
        warn_(id + ": base colour texture uses a TEXCOORD other than 0; TEXCOORD_0 is used");
    }
    if (g.normalTexture.index >= 0) {
      mat.normalTexture = texture(g.normalTexture.index, false, id + " normal map");
      if (budgetRefusal_) return *budgetRefusal_;
      mat.normalScale = float(g.normalTexture.scale);
      if (pbr.baseColorTexture.index < 0) mat.uvTransform = textureTransform(g.normalTexture.extensions);
      if (texCoordOf(g.normalTexture.extensions, g.normalTexture.texCoord) != 0)
        warn_(id + ": normal map uses a TEXCOORD other than 0; TEXCOORD_0 is used");
    }
    if (g.emissiveTexture.index >= 0) {
      mat.emissiveTexture = texture(g.emissiveTexture.index, true, id + " emissive");
      if (budgetRefusal_) return *budgetRefusal_;
      if (texCoordOf(g.emissiveTexture.extensions, g.emissiveTexture.texCoord) != 0)
        warn_(id + ": emissive texture uses a TEXCOORD other than 0; TEXCOORD_0 is used");
    }
    if (g.occlusionTexture.index >= 0)
      warnOnce("unusedTextures", "occlusion textures are not used; metallic-roughness textures only through their mean");
    wantsTangents_.push_back(mat.normalTexture >= 0);
    materialOf_.push_back(int(out_.scene.materials.size()));
    out_.scene.materials.push_back(std::move(mat));
  }
  return {};
}

// ---- meshes ----

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

Result<Mesh> Importer::convertPrimitive(int meshIndex, int primIndex) {
  const tinygltf::Primitive& p = m_.meshes[std::size_t(meshIndex)].primitives[std::size_t(primIndex)];
  const std::string id = "meshes[" + std::to_string(meshIndex) + "].primitives[" + std::to_string(primIndex) + "]";
  Mesh mesh;
  mesh.name = m_.meshes[std::size_t(meshIndex)].name;
  if (m_.meshes[std::size_t(meshIndex)].primitives.size() > 1) mesh.name += "#" + std::to_string(primIndex);
  auto attr = [&](const char* name) {
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
  };
  const int posAcc = attr("POSITION");
  auto pos = attribute(posAcc);
  if (!pos) return pos.error();
  const std::size_t vertexCount = (*pos)->size() / 3;
  if (vertexCount > std::size_t(UINT32_MAX)) return err(id + ": too many vertices");
  // Indices: read, range-check, then expand the topology into a triangle list.
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
    mesh.indices = std::move(idx);
  } else if (idx.size() >= 3) {
    if (auto c = charge(id + " triangle list", u64(idx.size() - 2) * 3 * sizeof(std::uint32_t)); !c) return c.error();
    mesh.indices.reserve((idx.size() - 2) * 3);
    for (std::size_t i = 0; i + 2 < idx.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // glTF 3.7.2.1: odd triangles swap their last two vertices to keep a consistent winding.
        const std::size_t b = i + 1 + i % 2, c = i + 2 - i % 2;
        mesh.indices.insert(mesh.indices.end(), {idx[i], idx[b], idx[c]});
      } else {  // fan
        mesh.indices.insert(mesh.indices.end(), {idx[i + 1], idx[i + 2], idx[0]});
      }
    }
  }
  if (mesh.indices.empty()) return mesh;  // caller skips it with a warning

  // The vertices this primitive uses. Primitives often index a vertex array shared with others; keeping
  // only the used vertices makes a mesh cost what it draws, and the work below independent of the shared
  // array's size. When every vertex is used (the usual case) the order is kept as it is.
  std::vector<std::uint32_t> used;
  {
    if (auto c = charge(id + " vertex list", u64(mesh.indices.size()) * sizeof(std::uint32_t)); !c) return c.error();
    used = mesh.indices;
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    if (used.size() < vertexCount) {
      for (std::uint32_t& i : mesh.indices)
        i = std::uint32_t(std::lower_bound(used.begin(), used.end(), i) - used.begin());
    } else {
      used.clear();
      used.shrink_to_fit();
    }
  }
  const std::size_t n = used.empty() ? vertexCount : used.size();
  auto source = [&](std::size_t i) -> std::size_t { return used.empty() ? i : used[i]; };
  if (auto c = charge(id + " vertices", u64(n) * sizeof(glm::vec3)); !c) return c.error();
  mesh.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* v = (*pos)->data() + 3 * source(i);
    mesh.positions[i] = glm::vec3(v[0], v[1], v[2]);
    if (!finite3(mesh.positions[i]))
      return err(id + ": POSITION " + std::to_string(source(i)) + " is NaN or infinite (accessors[" + std::to_string(posAcc) + "])");
  }

  if (int a = attr("NORMAL"); a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    if (auto c = charge(id + " normals", u64(n) * sizeof(glm::vec3)); !c) return c.error();
    mesh.normals.resize(n);
    bool zero = false;
    for (std::size_t i = 0; i < n; ++i) {
      const float* v = (*r)->data() + 3 * source(i);
      glm::vec3 nv(v[0], v[1], v[2]);
      if (!finite3(nv)) return err(id + ": NORMAL " + std::to_string(source(i)) + " is NaN or infinite");
      const float len = glm::length(nv);
      if (!(len > 1e-20f)) {
        zero = true;
        nv = glm::vec3(0, 0, 1);
      } else {
        nv /= len;
      }
      mesh.normals[i] = nv;
    }
    if (zero) warn_(id + ": zero-length normals replaced");
  } else {
    if (auto c = charge(id + " normals", u64(n) * sizeof(glm::vec3)); !c) return c.error();
    generateNormals(mesh);
  }
  if (int a = attr("TEXCOORD_0"); a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    if (auto c = charge(id + " uvs", u64(n) * sizeof(glm::vec2)); !c) return c.error();
    mesh.uvs.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float* v = (*r)->data() + 2 * source(i);
      mesh.uvs[i] = glm::vec2(v[0], v[1]);
      if (!std::isfinite(mesh.uvs[i].x) || !std::isfinite(mesh.uvs[i].y))
        return err(id + ": TEXCOORD_0 " + std::to_string(source(i)) + " is NaN or infinite");
    }
  }
  if (int a = attr("COLOR_0"); a >= 0) {
    auto r = attribute(a);
    if (!r) return r.error();
    const std::size_t nc = std::size_t(componentCount(m_.accessors[std::size_t(a)].type));
    if (auto c = charge(id + " colours", u64(n) * sizeof(glm::vec4)); !c) return c.error();
    mesh.colors.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      glm::vec4 c(1.0f);
      for (std::size_t k = 0; k < nc; ++k) c[int(k)] = (**r)[nc * source(i) + k];
      if (!finite3(glm::vec3(c)) || !std::isfinite(c.w))
        return err(id + ": COLOR_0 " + std::to_string(source(i)) + " is NaN or infinite");
      mesh.colors[i] = glm::clamp(c, 0.0f, 1.0f);
    }
  }
  const bool normalMap = p.material >= 0 && wantsTangents_[std::size_t(p.material)];
  if (normalMap)
    if (auto c = charge(id + " tangents", u64(n) * (sizeof(glm::vec4) + sizeof(glm::vec2))); !c) return c.error();
  if (int a = attr("TANGENT"); a >= 0 && normalMap) {
    auto r = attribute(a);
    if (!r) return r.error();
    mesh.tangents.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float* v = (*r)->data() + 4 * source(i);
      glm::vec4 t(v[0], v[1], v[2], v[3]);
      if (!finite3(glm::vec3(t)) || !std::isfinite(t.w))
        return err(id + ": TANGENT " + std::to_string(source(i)) + " is NaN or infinite");
      const float len = glm::length(glm::vec3(t));
      mesh.tangents[i] = len > 1e-20f ? glm::vec4(glm::vec3(t) / len, t.w < 0 ? -1.0f : 1.0f) : glm::vec4(1, 0, 0, 1);
    }
  } else if (normalMap) {
    if (mesh.uvs.empty()) warn_(id + ": normal map without TEXCOORD_0; tangents are arbitrary");
    else generateTangents(mesh);
    if (mesh.uvs.empty()) {
      mesh.uvs.assign(n, glm::vec2(0.0f));
      generateTangents(mesh);
    }
  }
  return mesh;
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

// ---- nodes ----

Result<std::vector<glm::mat4>> Importer::gpuInstances(const tinygltf::Node& n, std::size_t nodeIndex) {
  const tinygltf::Value* e = ext(n.extensions, "EXT_mesh_gpu_instancing");
  if (!e) return std::vector<glm::mat4>{glm::mat4(1.0f)};
  const std::string id = "nodes[" + std::to_string(nodeIndex) + "].EXT_mesh_gpu_instancing";
  if (!e->Has("attributes") || !e->Get("attributes").IsObject()) return err(id + ": no attributes");
  const tinygltf::Value& attrs = e->Get("attributes");
  std::size_t count = 0;
  std::vector<float> data[3];
  const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
  const int types[3] = {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4, TINYGLTF_TYPE_VEC3};
  for (int k = 0; k < 3; ++k) {
    if (!attrs.Has(names[k])) continue;
    const int a = intOf(attrs, names[k], -1);
    if (a < 0 || a >= int(m_.accessors.size()))
      return err(id + ": " + names[k] + " names accessor " + std::to_string(a) + ", which does not exist");
    const tinygltf::Accessor& acc = m_.accessors[std::size_t(a)];
    if (acc.type != types[k]) return err(id + ": " + names[k] + " accessor has the wrong type");
    if (count != 0 && acc.count != count) return err(id + ": attribute counts differ");
    count = acc.count;
    auto r = readFloats(m_, a, file_, &budget_);
    if (!r) return r.error();
    for (float v : *r)
      if (!std::isfinite(v)) return err(id + ": " + names[k] + " contains NaN or infinity");
    data[k] = std::move(*r);
  }
  if (count == 0) return err(id + ": no TRANSLATION, ROTATION or SCALE attribute");
  if (auto c = charge(id + " transforms", u64(count) * sizeof(glm::mat4)); !c) return c.error();
  std::vector<glm::mat4> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    glm::mat4 t(1.0f);
    if (!data[0].empty()) t = glm::translate(t, glm::vec3(data[0][3 * i], data[0][3 * i + 1], data[0][3 * i + 2]));
    if (!data[1].empty()) {
      glm::quat q(data[1][4 * i + 3], data[1][4 * i], data[1][4 * i + 1], data[1][4 * i + 2]);
      const float len = glm::length(q);
      t *= glm::mat4_cast(len > 1e-20f ? q / len : glm::quat(1, 0, 0, 0));
    }
    if (!data[2].empty()) t = glm::scale(t, glm::vec3(data[2][3 * i], data[2][3 * i + 1], data[2][3 * i + 2]));
    out[i] = t;
  }
  return out;
}

void Importer::addCamera(const tinygltf::Node& n, const glm::mat4& world) {
  const tinygltf::Camera& c = m_.cameras[std::size_t(n.camera)];
  const std::string id = "cameras[" + std::to_string(n.camera) + "]";
  Camera cam;
  if (c.type == "perspective") {
    const auto& p = c.perspective;
    if (!(p.yfov > 0.0 && p.yfov < 3.14159) || !(p.znear > 0.0) || !std::isfinite(p.znear) ||
        !(p.zfar == 0.0 || (std::isfinite(p.zfar) && p.zfar > p.znear)) || !(p.aspectRatio >= 0.0)) {
      warn_(id + ": invalid perspective parameters (need 0 < yfov < π, znear > 0, zfar > znear); camera skipped");
      return;
    }
    cam.yFovDeg = float(glm::degrees(p.yfov));
    cam.nearZ = float(p.znear);
    cam.farZ = p.zfar == 0.0 ? std::numeric_limits<float>::infinity() : float(p.zfar);
  } else {
    const auto& o = c.orthographic;
    if (!(std::abs(o.ymag) > 0.0) || !std::isfinite(o.ymag) || !(std::abs(o.xmag) > 0.0) || !(o.znear >= 0.0) ||
        !std::isfinite(o.zfar) || !(o.zfar > o.znear)) {
      warn_(id + ": invalid orthographic parameters (need xmag, ymag ≠ 0, zfar > znear >= 0); camera skipped");
      return;
    }
    cam.orthographic = true;
    cam.orthoHeight = float(2.0 * std::abs(o.ymag));
    cam.nearZ = std::max(float(o.znear), 1e-4f);  // the engine's projections need near > 0
    cam.farZ = float(o.zfar);
  }
  // glTF cameras look down their local −Z with +Y up.
  const glm::vec3 pos(world[3]);
  const glm::vec3 fwd = glm::mat3(world) * glm::vec3(0, 0, -1);
  const glm::vec3 up = glm::mat3(world) * glm::vec3(0, 1, 0);
  if (!finite3(pos) || !(glm::length(fwd) > 1e-12f) || !(glm::length(up) > 1e-12f) ||
      !(glm::length(glm::cross(fwd, up)) > 1e-12f)) {
    warn_(id + ": its node's transform is degenerate; camera skipped");
    return;
  }
  cam.posW = pos;
  cam.targetW = pos + glm::normalize(fwd);
  cam.upW = glm::normalize(up);
  out_.scene.camera = cam;
  haveCamera_ = true;
}

void Importer::addLight(const tinygltf::Node& n, std::size_t nodeIndex, const glm::mat4& world) {
  const tinygltf::Value* e = ext(n.extensions, "KHR_lights_punctual");
  if (!e) return;
  const std::string id = "nodes[" + std::to_string(nodeIndex) + "].KHR_lights_punctual";
  const int li = intOf(*e, "light", -1);
  if (li < 0 || li >= int(m_.lights.size())) {
    warn_(id + ": light " + std::to_string(li) + " does not exist; light skipped");
    return;
  }
  const tinygltf::Light& g = m_.lights[std::size_t(li)];
  const std::string lid = "KHR_lights_punctual.lights[" + std::to_string(li) + "]";
  Light l;
  l.name = g.name;
  if (g.type == "point") l.type = LightType::Point;
  else if (g.type == "spot") l.type = LightType::Spot;
  else if (g.type == "directional") l.type = LightType::Directional;
  else {
    warn_(lid + ": unknown type '" + g.type + "'; light skipped");
    return;
  }
  if (!g.color.empty()) {
    if (g.color.size() != 3) {
      warn_(lid + ": color needs 3 numbers; light skipped");
      return;
    }
    l.color = glm::vec3(float(g.color[0]), float(g.color[1]), float(g.color[2]));
  }
  if (!finite3(l.color) || l.color.x < 0 || l.color.y < 0 || l.color.z < 0 || !std::isfinite(g.intensity) ||
      g.intensity < 0 || !std::isfinite(g.range) || g.range < 0) {
    warn_(lid + ": negative or non-finite colour, intensity or range; light skipped");
    return;
  }
  // Units (docs/gltf.md): point/spot intensity in candela with inverse-square falloff, directional in lux.
  // glTF's diffuse BRDF is albedo/π, the engine's Phong term kd·E·(N·L) has no 1/π: dividing the
  // intensity by π makes a Lambertian surface as bright as in glTF viewers at exposure 1.
  l.intensity = float(g.intensity / std::numbers::pi);
  l.range = float(g.range);
  l.attenuation = l.type == LightType::Directional ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  if (l.type == LightType::Spot) {
    const double inner = g.spot.innerConeAngle, outer = g.spot.outerConeAngle;
    if (!(inner >= 0.0) || !(outer > inner) || !(outer <= 1.5707964)) {
      warn_(lid + ": spot cone needs 0 <= inner < outer <= π/2; light skipped");
      return;
    }
    l.innerConeDeg = float(glm::degrees(inner));
    l.outerConeDeg = float(glm::degrees(outer));
  }
  l.posW = glm::vec3(world[3]);
  const glm::vec3 dir = glm::mat3(world) * glm::vec3(0, 0, -1);  // lights shine down their local −Z
  if (!finite3(l.posW) || !(glm::length(dir) > 1e-12f)) {
    warn_(lid + ": its node's transform is degenerate; light skipped");
    return;
  }
  l.dirW = glm::normalize(dir);
  if (out_.scene.directLights().size() >= std::size_t(kMaxLights)) {
    warn_(lid + ": more than " + std::to_string(kMaxLights) + " lights; light skipped");
    return;
  }
  out_.scene.lights.push_back(std::move(l));
}

Result<void> Importer::traverse(const std::vector<int>& roots) {
  struct Item {
    int node;
    int parentAnim;
    bool dynamic;
    glm::mat4 parentWorld;
  };
  const bool animating = !m_.animations.empty();
  animIndexOfNode_.assign(m_.nodes.size(), -1);
  // Instances are a product (nodes × primitives × GPU instances). Counted first, charged and reserved at
  // once, so the vector never doubles past what the budget allowed.
  {
    u64 planned = 0;
    std::vector<int> walk(roots.begin(), roots.end());
    while (!walk.empty()) {
      const tinygltf::Node& n = m_.nodes[std::size_t(walk.back())];
      walk.pop_back();
      if (n.mesh >= 0) {
        u64 copies = 1;
        if (const tinygltf::Value* e = ext(n.extensions, "EXT_mesh_gpu_instancing"); e && e->Has("attributes"))
          for (const char* a : {"TRANSLATION", "ROTATION", "SCALE"}) {
            const int ai = intOf(e->Get("attributes"), a, -1);
            if (ai >= 0 && ai < int(m_.accessors.size())) copies = std::max<u64>(copies, m_.accessors[std::size_t(ai)].count);
          }
        planned += copies * m_.meshes[std::size_t(n.mesh)].primitives.size();
      }
      walk.insert(walk.end(), n.children.begin(), n.children.end());
    }
    const u64 each = sizeof(Instance) + (animating ? sizeof(AnimBinding) : 0);
    if (planned > (~u64(0)) / each) return err("the scene's instances overflow a 64-bit count");
    if (auto c = charge(std::to_string(planned) + " instances (nodes × primitives × GPU instances)", planned * each); !c)
      return c.error();
    out_.scene.instances.reserve(std::size_t(planned));
    if (animating) out_.animation.bindings.reserve(std::size_t(planned));
  }
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, false, glm::mat4(1.0f)});
  // Iterative depth-first walk (validateModel proved the graph a forest), so a 100 000-deep chain needs
  // no call stack.
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const std::size_t ni = std::size_t(item.node);
    const tinygltf::Node& n = m_.nodes[ni];
    const glm::mat4 local = nodeLocalMatrix(n);
    const glm::mat4 world = item.parentWorld * local;
    const bool dynamic = item.dynamic || animated_[ni];
    int animIndex = -1;
    if (animating) {
      AnimNode an;
      an.parent = item.parentAnim;
      if (n.matrix.size() == 16) {
        an.hasMatrix = true;
        an.matrix = local;
      } else {
        if (n.translation.size() == 3) an.translation = glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
        if (n.rotation.size() == 4)
          an.rotation = glm::normalize(glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])));
        if (n.scale.size() == 3) an.scale = glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
      }
      animIndex = int(out_.animation.nodes.size());
      animIndexOfNode_[ni] = animIndex;
      out_.animation.nodes.push_back(an);
    }
    if (n.skin >= 0) warnOnce("skin", "skins are ignored; skinned meshes are drawn unposed with their node transform");
    if (n.camera >= 0 && !haveCamera_) addCamera(n, world);
    addLight(n, ni, world);
    if (n.mesh >= 0) {
      auto xf = gpuInstances(n, ni);
      if (!xf) return xf.error();
      const tinygltf::Mesh& mesh = m_.meshes[std::size_t(n.mesh)];
      for (const glm::mat4& x : *xf) {
        const glm::mat4 w = world * x;
        const float det = glm::determinant(glm::mat3(w));
        if (!finiteMat(w) || (!dynamic && !(std::abs(det) > 1e-30f))) {
          // A singular static transform (zero scale) draws nothing and would give NaN normals.
          warnOnce("singular" + std::to_string(ni), "nodes[" + std::to_string(ni) + "]: singular or non-finite transform; its mesh is skipped");
          continue;
        }
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
          auto mi = meshFor(n.mesh, int(p), det < 0.0f);
          if (!mi) return mi.error();
          if (*mi < 0) continue;
          triangles_ += out_.scene.meshes[std::size_t(*mi)].triangleCount();
          if (triangles_ > opt_.limits.maxTriangles)
            return err("more than the cap maxTriangles = " + std::to_string(opt_.limits.maxTriangles) + " triangles");
          const int gm = mesh.primitives[p].material;
          if (gm < 0 && defaultMaterial_ < 0) {
            // glTF's default material: white, fully rough dielectric.
            Material d;
            d.name = "default";
            d.kd = d.ka = glm::vec3(1.0f);
            d.ks = glm::vec3(0.04f);
            d.ns = 1.0f;
            defaultMaterial_ = int(out_.scene.materials.size());
            out_.scene.materials.push_back(std::move(d));
          }
          Instance inst;
          inst.name = n.name.empty() ? "node " + std::to_string(ni) : n.name;
          // The instance itself was charged above; a name too long for the string's own storage is extra.
          if (inst.name.size() > 15)
            if (auto c = charge("nodes[" + std::to_string(ni) + "] instance names", inst.name.size()); !c) return c.error();
          inst.mesh = std::uint32_t(*mi);
          inst.material = std::uint32_t(gm < 0 ? defaultMaterial_ : materialOf_[std::size_t(gm)]);
          inst.worldFromObject = w;
          inst.dynamic = dynamic;
          if (dynamic && animIndex >= 0)
            out_.animation.bindings.push_back({std::uint32_t(out_.scene.instances.size()), std::uint32_t(animIndex), x});
          out_.scene.instances.push_back(std::move(inst));
        }
      }
    }
    for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, animIndex, dynamic, world});
  }
  return {};
}

void Importer::addDefaults() {
  Scene& s = out_.scene;
  if (!haveCamera_ && opt_.addDefaultCamera) {
    // Frame the world bounds of every instance from the glTF "front" (+Z), slightly above.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Instance& inst : s.instances)
      for (const glm::vec3& p : s.meshes[inst.mesh].positions) {
        const glm::vec3 w(inst.worldFromObject * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
    Camera cam;
    if (!s.instances.empty() && finite3(lo) && finite3(hi) && lo.x <= hi.x) {
      const glm::vec3 c = (lo + hi) * 0.5f;
      const float r = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
      const float d = r / std::sin(glm::radians(cam.yFovDeg) * 0.5f) * 1.1f;
      cam.posW = c + glm::normalize(glm::vec3(0.0f, 0.25f, 1.0f)) * d;
      cam.targetW = c;
      cam.nearZ = std::max(r * 1e-3f, 1e-5f);
    }
    s.camera = cam;
  }
  // glTF has no background: escaped rays see a dark neutral grey (ACES-mapped to about sRGB 59): light
  // models (most sample models are white or pastel) keep their contrast, as on the screenshots' dark
  // backdrops, and black silhouettes still stand out from it.
  s.background = glm::vec3(0.05f);
  if (s.lights.empty() && opt_.addDefaultLights) {
    // A headlight along the view direction (every visible surface facing the camera is lit) plus a
    // dim ambient so faces turned away are not black.
    Light head;
    head.name = "default headlight";
    head.type = LightType::Directional;
    head.intensity = 1.0f;
    head.attenuation = glm::vec3(1, 0, 0);
    const glm::vec3 dir = s.camera.targetW - s.camera.posW;
    head.dirW = glm::length(dir) > 1e-12f ? glm::normalize(dir) : glm::vec3(0, 0, -1);
    head.castShadows = false;
    Light amb;
    amb.name = "default ambient";
    amb.type = LightType::Ambient;
    amb.intensity = 0.2f;
    s.lights.push_back(std::move(head));
    s.lights.push_back(std::move(amb));
  }
}

Result<GltfAsset> Importer::run() {
  if (m_.scenes.empty() && opt_.sceneIndex >= 0) return err("scene " + std::to_string(opt_.sceneIndex) + " does not exist (the file has no scenes)");
  if (opt_.sceneIndex >= int(m_.scenes.size())) return err("scene " + std::to_string(opt_.sceneIndex) + " does not exist (the file has " + std::to_string(m_.scenes.size()) + ")");
  std::vector<int> roots;
  if (!m_.scenes.empty()) {
    const int si = opt_.sceneIndex >= 0 ? opt_.sceneIndex : std::max(m_.defaultScene, 0);
    roots = m_.scenes[std::size_t(si)].nodes;
    out_.scene.name = m_.scenes[std::size_t(si)].name;
  } else {
    // No scene: glTF leaves rendering to the application; we show every root node.
    std::vector<bool> child(m_.nodes.size(), false);
    for (const auto& n : m_.nodes)
      for (int c : n.children) child[std::size_t(c)] = true;
    for (std::size_t i = 0; i < m_.nodes.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  if (out_.scene.name.empty()) out_.scene.name = fs::path(file_).stem().string();
  animated_.assign(m_.nodes.size(), false);
  for (const auto& a : m_.animations)
    for (const auto& c : a.channels)
      if (c.target_node >= 0 && (c.target_path == "translation" || c.target_path == "rotation" || c.target_path == "scale"))
        animated_[std::size_t(c.target_node)] = true;
  if (auto r = buildMaterials(); !r) return r.error();
  if (auto r = traverse(roots); !r) return r.error();
  if (!m_.animations.empty())
    if (auto r = buildAnimationClips(m_, animIndexOfNode_, out_.animation, warn_, file_, budget_); !r) return r.error();
  if (out_.animation.clips.empty()) out_.animation = SceneAnimation{};
  if (out_.scene.instances.empty()) warn_("the scene has nothing to draw");
  addDefaults();
  if (auto r = validateScene(out_.scene); !r) return err("imported scene failed validation: " + r.error().message);
  return std::move(out_);
}

Result<GltfAsset> loadImpl(const std::string& path, const GltfOptions& opt) {
  // Messages name the file as the caller gave it, as the scene file's do.
  const std::string& file = path;
  std::error_code ec;
  const fs::path canon = fs::canonical(fs::path(path), ec);
  if (ec) return Error{file + ": cannot open: " + ec.message()};
  // The main file gets the same treatment as every file it names.
  auto bytes = readFileCapped(canon, opt.limits.maxFileBytes, &opt.onFileOpened);
  if (!bytes) return Error{file + ": " + bytes.error().message};
  if (bytes->empty()) return Error{file + ": empty file"};
  if (bytes->size() > std::size_t(UINT32_MAX)) return Error{file + ": larger than tinygltf can take (4 GiB)"};

  Confinement conf;
  conf.root = canon.parent_path();
  conf.rootPrefix = conf.root.string();
  if (conf.rootPrefix.empty() || conf.rootPrefix.back() != '/') conf.rootPrefix += '/';
  conf.maxFileBytes = opt.limits.maxFileBytes;
  conf.onFileOpened = &opt.onFileOpened;
  // tinygltf joins baseDir and uri with '/', so the root without its trailing slash (except "/").
  const std::string baseDir = conf.root.string();

  const bool glb = bytes->size() >= 4 && std::memcmp(bytes->data(), "glTF", 4) == 0;
  std::size_t jsonOffset = 0, jsonSize = bytes->size();
  if (glb)
    if (auto r = checkGlb(*bytes, &jsonOffset, &jsonSize); !r) return Error{file + ": " + r.error().message};
  if (auto r = checkJsonDepth(bytes->data() + jsonOffset, jsonSize, opt.limits.maxJsonDepth); !r)
    return Error{file + ": " + r.error().message};
  LoadBudget budget(opt.limits.budgetBaseBytes, opt.limits.budgetBytesPerInputByte);
  budget.addInput(bytes->size());
  auto scan = prescanJson(bytes->data() + jsonOffset, jsonSize, glb);
  if (!scan) return Error{file + ": " + scan.error().message};
  // The model tinygltf will build is charged before it is built: a file of many tiny objects ("{}" is a
  // 2 KB tinygltf::Material) is refused here instead of after the parser has allocated them.
  if (!budget.charge(scan->modelEstimate))
    return Error{file + ": " + budget.refusal("the parsed model (estimated before parsing)", scan->modelEstimate)};
  conf.budget = &budget;

  tinygltf::Model model;
  DeferredImages images;
  std::string err, warn;
  bool ok = false;
  try {
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(makeFsCallbacks(&conf));
    loader.SetImageLoader(&recordImage, &images);
    if (glb)
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes->data(), static_cast<unsigned>(bytes->size()), baseDir);
    else
      ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes->data()),
                                      static_cast<unsigned>(bytes->size()), baseDir);
  } catch (const std::bad_alloc&) {
    return Error{file + ": out of memory while parsing (tinygltf threw std::bad_alloc)"};
  } catch (const std::exception& e) {
    return Error{file + ": parse failed (tinygltf threw: " + e.what() + ")"};
  } catch (...) {
    return Error{file + ": parse failed (tinygltf threw an unknown exception)"};
  }
  // A refused file (escape, non-regular, oversized) rejects the load whatever tinygltf made of it.
  if (!conf.refusals.empty()) return Error{file + ": " + conf.refusals.front()};
  auto trim = [](std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& ch : s)
      if (ch == '\n') ch = ';';
    return s;
  };
  if (!ok) return Error{file + ": " + (err.empty() ? std::string("tinygltf failed without a message") : trim(err))};

  Warn w{file, &opt, 0};
  if (!warn.empty()) w(trim(warn));
  if (auto r = validateModel(model, opt.limits, file); !r) return r.error();
  Importer imp(model, opt, file, w, images, budget);
  auto asset = imp.run();
  if (!asset) return asset.error();
  asset->stats.inputBytes = budget.inputBytes();
  asset->stats.modelEstimate = scan->modelEstimate;
  asset->stats.decodedBytes = budget.used() - scan->modelEstimate;
  asset->stats.budgetBytes = budget.limit();
  return asset;
}

}  // namespace

Result<GltfAsset> loadGltfAsset(const std::string& path, const GltfOptions& options) {
  // Everything the loader allocates is sized by validated data, but a hostile file can still ask for a
  // lot within the caps: running out of memory fails this load, not the process.
  try {
    return loadImpl(path, options);
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

Result<Scene> loadGltf(const std::string& path, const GltfOptions& options) {
  auto r = loadGltfAsset(path, options);
  if (!r) return r.error();
  return std::move(r->scene);
}

}  // namespace tandem
