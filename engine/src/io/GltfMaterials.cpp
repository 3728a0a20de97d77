// The glTF importer's materials and textures (docs/gltf.md, "Materials"): metallic-roughness mapped onto
// the engine's Phong/Whitted material, textures decoded once per distinct source under the load budget.
#include <stb_image.h>

#include <algorithm>
#include <map>
#include <set>

#include "core/StbGuard.h"
#include "io/GltfImporter.h"
#include "tandem/Image.h"

namespace tandem::gltf {

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

glm::mat3 textureTransformOf(const tinygltf::Value* tt);
glm::mat3 textureTransform(const tinygltf::ExtensionMap& e) { return textureTransformOf(ext(e, "KHR_texture_transform")); }

glm::mat3 textureTransformOf(const tinygltf::Value* tt) {
  if (!tt || !tt->IsObject()) return glm::mat3(1.0f);
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
  // KHR_texture_transform: uv' = T · R · S · (u, v, 1), matrices column-major as in GLSL. The rotation turns
  // the UVs counter-clockwise as glTF's UV space (v down) shows them: the transpose of the matrix the extension's
  // README prints, which is counter-clockwise with v up (KhronosGroup/glTF#1563; Babylon.js, Blender and
  // three.js apply this one, and the sample model TextureTransformTest's arrows point at their green markers so).
  const glm::mat3 T(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::mat3 R(std::cos(rot), -std::sin(rot), 0, std::sin(rot), std::cos(rot), 0, 0, 0, 1);
  const glm::mat3 S(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  return T * R * S;
}

namespace {

// What the supported KHR_materials_* extensions add to a metallic-roughness material, at their defaults
// when absent.
struct MaterialExtensions {
  float ior = 1.5f;
  float specular = 1.0f;
  glm::vec3 specularColor{1.0f};
  float transmission = 0.0f;
  bool thick = false;
  float emissiveStrength = 1.0f;
};

// `warnings` false: read again (applyFactorMaps), what it would warn of was said the first time.
MaterialExtensions readMaterialExtensions(const tinygltf::Material& g, const std::string& id, Warn& warn,
                                          bool warnings = true) {
  MaterialExtensions x;
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_ior")) {
    const double v = num(*e, "ior", 1.5);
    // The extension allows 0 (meaning "no refraction"); anything else must be >= 1. Clamp the rest.
    x.ior = v == 0.0 ? 1.0f : float(std::clamp(v, 1.0, 5.0));
    if (warnings && v != 0.0 && (v < 1.0 || v > 5.0)) warn(id + ": ior " + std::to_string(v) + " clamped to [1, 5]");
  }
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_specular")) {
    x.specular = float(std::clamp(num(*e, "specularFactor", 1.0), 0.0, 1.0));
    x.specularColor = glm::clamp(vec3Of(*e, "specularColorFactor", glm::vec3(1.0f)), 0.0f, 1e3f);
  }
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_transmission"))
    x.transmission = float(std::clamp(num(*e, "transmissionFactor", 0.0), 0.0, 1.0));
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_volume")) x.thick = num(*e, "thicknessFactor", 0.0) > 0.0;
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_emissive_strength"))
    x.emissiveStrength = float(std::clamp(num(*e, "emissiveStrength", 1.0), 0.0, 1e6));
  return x;
}

// Metallic-roughness mapped onto the Phong/Whitted material's coefficients.
void setPhongTerms(Material& mat, const tinygltf::Material& g, glm::vec3 base, float metallic, float rough,
                   const MaterialExtensions& x) {
  const auto& pbr = g.pbrMetallicRoughness;
  // Fresnel reflectance at normal incidence: dielectric F0 from the IOR, scaled by KHR_materials_specular;
  // metals reflect their base colour.
  const float f0d = std::pow((x.ior - 1.0f) / (x.ior + 1.0f), 2.0f);
  const glm::vec3 f0Dielectric = glm::min(glm::vec3(f0d) * x.specularColor * x.specular, glm::vec3(1.0f));
  mat.ks = glm::mix(f0Dielectric, base, metallic);
  // Energy that is not reflected specularly by metals or transmitted goes to the diffuse lobe.
  mat.kd = base * (1.0f - metallic) * (1.0f - x.transmission);
  mat.ka = mat.kd;
  // Phong exponent from GGX roughness: α = roughness², ns = 2/α² − 2 (Walter et al. 2007, Beckmann↔Phong).
  const float alpha = std::max(rough * rough, 1e-3f);
  mat.ns = std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 10000.0f);
  // Glossy rays sample the lobe of this roughness (Material::roughness, docs/glossy.md). The reflected share
  // still fades with roughness, (1 − roughness)²: a rough surface's reflection spreads into its diffuse and
  // Phong terms, which already carry it, and very rough lobes would only add noise.
  mat.roughness = std::clamp(rough, 0.0f, 1.0f);
  const float smooth = (1.0f - rough) * (1.0f - rough);
  const float f0Max = std::max({f0Dielectric.x, f0Dielectric.y, f0Dielectric.z});
  mat.kr = std::clamp(smooth * (metallic + (1.0f - metallic) * f0Max), 0.0f, 1.0f);
  mat.kt = x.transmission * (1.0f - metallic);
  // Without KHR_materials_volume a transmissive surface is thin-walled: light passes without bending.
  mat.ior = (mat.kt > 0.0f && !x.thick) ? 1.0f : x.ior;
  // glTF tints transmitted light by the base colour (KHR_materials_transmission); texture not included.
  mat.transmissionTint = base;
  if (g.emissiveFactor.size() == 3)
    mat.emission = glm::vec3(float(g.emissiveFactor[0]), float(g.emissiveFactor[1]), float(g.emissiveFactor[2])) *
                   x.emissiveStrength;
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
}

int texCoordOf(const tinygltf::ExtensionMap& e, int texCoord) {
  const tinygltf::Value* tt = ext(e, "KHR_texture_transform");
  return tt ? intOf(*tt, "texCoord", texCoord) : texCoord;
}

}  // namespace

// The metallic-roughness and transmission textures are not sampled per pixel (the engine has one Phong lobe per
// material): they scale the factors by their means, at first over the whole texture, then (applyFactorMaps)
// over the texels the material's own triangles cover. An atlas shared by a metal body and a paper shade
// (LightsPunctualLamp) would otherwise make the paper 62 % metal and fully transmissive.
Result<void> Importer::readFactorMaps(const tinygltf::Material& g, const std::string& id, std::size_t material) {
  factorMaps_.resize(std::max(factorMaps_.size(), material + 1));
  FactorMaps& maps = factorMaps_[material];
  const auto& pbr = g.pbrMetallicRoughness;
  if (pbr.metallicRoughnessTexture.index >= 0) {
    maps.metallicRoughness = texture(pbr.metallicRoughnessTexture.index, false, id + " metallic-roughness");
    if (budgetRefusal_) return *budgetRefusal_;
    maps.metallicRoughnessUv = textureTransform(pbr.metallicRoughnessTexture.extensions);
    maps.metallicRoughnessOnUv0 =
        texCoordOf(pbr.metallicRoughnessTexture.extensions, pbr.metallicRoughnessTexture.texCoord) == 0;
  }
  if (const tinygltf::Value* e = ext(g.extensions, "KHR_materials_transmission");
      e && e->IsObject() && e->Has("transmissionTexture") && e->Get("transmissionTexture").IsObject()) {
    const tinygltf::Value& info = e->Get("transmissionTexture");
    const int index = intOf(info, "index", -1);
    if (index >= int(m_.textures.size()))
      return err(id + ": KHR_materials_transmission.transmissionTexture.index " + std::to_string(index) +
                 " does not exist");
    maps.transmission = texture(index, false, id + " transmission");
    if (budgetRefusal_) return *budgetRefusal_;
    int texCoord = intOf(info, "texCoord", 0);
    if (info.Has("extensions") && info.Get("extensions").IsObject() &&
        info.Get("extensions").Has("KHR_texture_transform")) {
      const tinygltf::Value& tt = info.Get("extensions").Get("KHR_texture_transform");
      maps.transmissionUv = textureTransformOf(&tt);
      texCoord = intOf(tt, "texCoord", texCoord);
    }
    maps.transmissionOnUv0 = texCoord == 0;
  }
  // Only TEXCOORD_0 is read: a map on another set is taken by its whole texture's mean.
  if ((maps.metallicRoughness >= 0 && !maps.metallicRoughnessOnUv0) || (maps.transmission >= 0 && !maps.transmissionOnUv0))
    warn_(id + ": a metallic-roughness or transmission texture uses a TEXCOORD other than 0; its whole mean is used");
  return {};
}

glm::dvec4 Importer::wholeMean(int index) {
  // Once per texture, not per material: many materials may share one large map.
  auto [it, fresh] = textureMeans_.try_emplace(index, glm::dvec4(1.0));
  const Texture& t = out_.scene.textures[std::size_t(index)];
  const std::size_t texels = t.rgba8.size() / 4;
  if (fresh && texels > 0) {
    glm::dvec4 sum(0.0);
    for (std::size_t k = 0; k < texels; ++k)
      for (int c = 0; c < 4; ++c) sum[c] += t.rgba8[4 * k + std::size_t(c)];
    it->second = sum / (255.0 * double(texels));
  }
  return it->second;
}

namespace {

// A uv triangle's area (1: the whole texture).
double uvArea(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
}

// Samples `t` over the uv footprint of `meshes`' triangles (uv' = uvTransform·uv, repeat wrap, nearest texel),
// weighted by uv area: each triangle at stratified points, as many as the cells of a 256² grid it covers times
// `scale` (at least one, at most 1024); a triangle of no uv area (a palette atlas maps whole faces to one
// point) at its centroid, counted only where the material has no area at all. Empty without uvs.
std::optional<glm::dvec4> footprintMean(const Texture& t, const glm::mat3& uvTransform,
                                        const std::vector<const Mesh*>& meshes, double scale) {
  if (t.width <= 0 || t.height <= 0 || meshes.empty()) return std::nullopt;
  auto texel = [&](glm::dvec2 uv) {
    const double fu = uv.x - std::floor(uv.x), fv = uv.y - std::floor(uv.y);
    if (!std::isfinite(fu) || !std::isfinite(fv)) return glm::dvec4(-1.0);
    const std::size_t x = std::min(std::size_t(fu * t.width), std::size_t(t.width - 1));
    const std::size_t y = std::min(std::size_t(fv * t.height), std::size_t(t.height - 1));  // v down, row 0 on top
    const std::uint8_t* p = &t.rgba8[4 * (y * std::size_t(t.width) + x)];
    return glm::dvec4(p[0], p[1], p[2], p[3]);
  };
  const glm::dmat3 m(uvTransform);
  glm::dvec4 sum(0.0), flatSum(0.0);
  double weight = 0.0, flatCount = 0.0;
  for (const Mesh* mesh : meshes)
    for (std::size_t k = 0; k + 2 < mesh->indices.size(); k += 3) {
      const glm::dvec2 a(m * glm::dvec3(mesh->uvs[mesh->indices[k]], 1.0)), b(m * glm::dvec3(mesh->uvs[mesh->indices[k + 1]], 1.0)),
          c(m * glm::dvec3(mesh->uvs[mesh->indices[k + 2]], 1.0));
      const double area = uvArea(a, b, c);
      if (!std::isfinite(area)) continue;
      if (!(area > 0.0)) {
        const glm::dvec4 v = texel((a + b + c) / 3.0);
        if (v.x >= 0.0) flatSum += v, flatCount += 1.0;
        continue;
      }
      const int n = int(std::clamp(std::ceil(scale * std::min(1024.0, 65536.0 * area)), 1.0, 1024.0));
      for (int s = 0; s < n; ++s) {
        // A stratified point of the triangle: (s + ½)/n and the golden ratio's sequence, warped to barycentrics.
        const double r1 = (s + 0.5) / n, r2 = std::fmod(0.5 + s * 0.6180339887498949, 1.0);
        const double su = std::sqrt(r1);
        const glm::dvec4 v = texel((1.0 - su) * a + su * (1.0 - r2) * b + su * r2 * c);
        if (v.x < 0.0) continue;
        sum += (area / n) * v;
        weight += area / n;
      }
    }
  if (weight > 0.0) return sum / (255.0 * weight);
  if (flatCount > 0.0) return flatSum / (255.0 * flatCount);
  return std::nullopt;
}

}  // namespace

void Importer::applyFactorMaps() {
  // The meshes each scene material is drawn with, each once, in one pass over the instances (a material's
  // unposed skins' copy counts as the material).
  std::map<std::uint32_t, std::uint32_t> original;
  for (const auto& [from, copy] : unposedCopy_) original[copy] = from;
  std::vector<std::vector<const Mesh*>> meshesOf(out_.scene.materials.size());
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (const Instance& inst : out_.scene.instances) {
    std::uint32_t material = inst.material;
    if (auto it = original.find(material); it != original.end()) material = it->second;
    const Mesh& m = out_.scene.meshes[inst.mesh];
    if (m.uvs.size() != m.positions.size() || !seen.insert({material, inst.mesh}).second) continue;
    meshesOf[material].push_back(&m);
  }
  // One sample budget for the whole file (4 M samples beyond one a triangle): every material's share scaled
  // alike, so a file of many materials over large uv areas costs what one would.
  double cells = 0.0;
  for (std::size_t i = 0; i < factorMaps_.size() && i < m_.materials.size(); ++i) {
    const FactorMaps& maps = factorMaps_[i];
    if (maps.metallicRoughness < 0 && maps.transmission < 0) continue;
    for (const Mesh* mesh : meshesOf[std::size_t(materialOf_[i])])
      for (std::size_t k = 0; k + 2 < mesh->indices.size(); k += 3) {
        const double area = uvArea(mesh->uvs[mesh->indices[k]], mesh->uvs[mesh->indices[k + 1]], mesh->uvs[mesh->indices[k + 2]]);
        if (std::isfinite(area)) cells += 2.0 * std::min(1024.0, 65536.0 * area);  // two maps at most
      }
  }
  const double scale = cells > 4.0e6 ? 4.0e6 / cells : 1.0;
  for (std::size_t i = 0; i < factorMaps_.size() && i < m_.materials.size(); ++i) {
    const FactorMaps& maps = factorMaps_[i];
    if (maps.metallicRoughness < 0 && maps.transmission < 0) continue;
    const std::uint32_t material = std::uint32_t(materialOf_[i]);
    const std::vector<const Mesh*>& meshes = meshesOf[material];
    auto mean = [&](int texture, const glm::mat3& uv, bool footprint) {
      if (footprint)
        if (auto m = footprintMean(out_.scene.textures[std::size_t(texture)], uv, meshes, scale)) return *m;
      return wholeMean(texture);
    };
    const tinygltf::Material& g = m_.materials[i];
    const auto& pbr = g.pbrMetallicRoughness;
    float metallic = float(pbr.metallicFactor), rough = float(pbr.roughnessFactor);
    if (maps.metallicRoughness >= 0) {
      const glm::dvec4 mr = mean(maps.metallicRoughness, maps.metallicRoughnessUv, maps.metallicRoughnessOnUv0);
      rough *= float(mr.g);
      metallic *= float(mr.b);
    }
    MaterialExtensions x = readMaterialExtensions(g, "", warn_, false);
    if (maps.transmission >= 0) x.transmission *= float(mean(maps.transmission, maps.transmissionUv, maps.transmissionOnUv0).r);
    const glm::vec3 base(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
    setPhongTerms(out_.scene.materials[material], g, base, metallic, rough, x);
    if (auto copy = unposedCopy_.find(material); copy != unposedCopy_.end()) {
      Material both = out_.scene.materials[material];
      both.doubleSided = true;
      both.name = out_.scene.materials[copy->second].name;
      out_.scene.materials[copy->second] = std::move(both);
    }
  }
}

Result<void> Importer::attachMaterialTextures(Material& mat, const tinygltf::Material& g, const std::string& id) {
  const auto& pbr = g.pbrMetallicRoughness;
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
    warnOnce("unusedTextures", "occlusion textures are not used; metallic-roughness and transmission textures only "
                               "through their means over the texels each material covers");
  return {};
}

Result<void> Importer::buildMaterials() {
  for (std::size_t i = 0; i < m_.materials.size(); ++i) {
    const tinygltf::Material& g = m_.materials[i];
    const auto& pbr = g.pbrMetallicRoughness;
    const std::string id = "materials[" + std::to_string(i) + "]";
    Material mat;
    mat.name = g.name;
    const glm::vec3 base(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
    if (auto read = readFactorMaps(g, id, i); !read) return read;
    // The factors alone here: applyFactorMaps scales them by the maps once the triangles that use them exist.
    setPhongTerms(mat, g, base, float(pbr.metallicFactor), float(pbr.roughnessFactor), readMaterialExtensions(g, id, warn_));
    if (auto attached = attachMaterialTextures(mat, g, id); !attached) return attached;
    wantsTangents_.push_back(mat.normalTexture >= 0);
    materialOf_.push_back(int(out_.scene.materials.size()));
    out_.scene.materials.push_back(std::move(mat));
  }
  return {};
}

}  // namespace tandem::gltf
