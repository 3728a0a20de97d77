// glTF import on small files the tests write themselves: geometry, topology, materials, lights,
// cameras, instancing, animation.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "tandem/Gltf.h"
#include "tandem/Log.h"
#include "unit/GltfTestUtil.h"

namespace tandem {
namespace {

using nlohmann::json;
using test::Bytes;
using test::freshDir;
using test::triangleDoc;
using test::writeText;

struct Loaded {
  Result<GltfAsset> asset;
  std::vector<std::string> warnings;
  std::vector<std::string> opened;
};

Loaded load(const std::string& path, GltfOptions opt = {}) {
  std::vector<std::string> warnings, opened;
  opt.onWarning = [&](const std::string& w) { warnings.push_back(w); };
  opt.onFileOpened = [&](const std::string& f) { opened.push_back(f); };
  LogSink old = setLogSink([](LogLevel, std::string_view) {});  // keep test output readable
  auto r = loadGltfAsset(path, opt);
  setLogSink(old);
  return Loaded{std::move(r), warnings, opened};
}

Loaded loadDoc(const std::string& name, const json& doc, GltfOptions opt = {}) {
  auto dir = freshDir(name);
  return load(writeText(dir / (name + ".gltf"), doc.dump()), opt);
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  for (const auto& x : v)
    if (x.find(s) != std::string::npos) return true;
  return false;
}

TEST(GltfImport, TriangleLoadsWithGeneratedNormalsAndDefaults) {
  auto l = loadDoc("triangle", triangleDoc());
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.meshes[0].positions.size(), 3u);
  EXPECT_EQ(s.meshes[0].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(s.meshes[0].normals.size(), 3u);
  EXPECT_NEAR(s.meshes[0].normals[0].z, 1.0f, 1e-6f);
  // No camera and no lights in the file: a framing camera and a headlight; the default sky lights the rest
  // (docs/environment.md), with no ambient light of its own.
  EXPECT_GT(s.camera.posW.z, 0.5f);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::Directional);
  EXPECT_EQ(s.environment.kind, Environment::Kind::Sky);
  EXPECT_TRUE(s.environment.lightsAmbient);
  ASSERT_EQ(l.opened.size(), 1u);  // the main file only: the buffer is a data URI
  EXPECT_TRUE(l.asset->animation.empty());
}

TEST(GltfImport, NegativeScaleFlipsWindingOnlyForTheMirroredInstance) {
  json d = triangleDoc();
  d["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}, {"scale", {-1, 1, 1}}}};
  d["scenes"][0]["nodes"] = {0, 1};
  auto l = loadDoc("negscale", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.instances.size(), 2u);
  ASSERT_EQ(s.meshes.size(), 2u);
  const Mesh& plain = s.meshes[s.instances[0].mesh];
  const Mesh& mirrored = s.meshes[s.instances[1].mesh];
  EXPECT_EQ(plain.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(mirrored.indices, (std::vector<std::uint32_t>{0, 2, 1}));
  // Object-space normals are the same; the world transform mirrors them.
  EXPECT_NEAR(mirrored.normals[0].z, 1.0f, 1e-6f);
  // World-space winding of the mirrored instance is counter-clockwise seen from +Z, like the original.
  auto worldNormal = [&](const Instance& inst, const Mesh& m) {
    glm::vec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = glm::vec3(inst.worldFromObject * glm::vec4(m.positions[m.indices[std::size_t(k)]], 1));
    return glm::cross(p[1] - p[0], p[2] - p[0]);
  };
  EXPECT_GT(worldNormal(s.instances[0], plain).z, 0.0f);
  EXPECT_GT(worldNormal(s.instances[1], mirrored).z, 0.0f);
}

TEST(GltfImport, StripsAndFansAreConvertedPointsAndLinesSkipped) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"] = {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 48}}};
  d["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}};
  d["meshes"][0]["primitives"] = {{{"attributes", {{"POSITION", 0}}}, {"mode", 5}},
                                  {{"attributes", {{"POSITION", 0}}}, {"mode", 6}},
                                  {{"attributes", {{"POSITION", 0}}}, {"mode", 0}},
                                  {{"attributes", {{"POSITION", 0}}}, {"mode", 1}}};
  auto l = loadDoc("modes", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.meshes[s.instances[0].mesh].indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(s.meshes[s.instances[1].mesh].indices, (std::vector<std::uint32_t>{1, 2, 0, 2, 3, 0}));
  EXPECT_TRUE(contains(l.warnings, "points are not rendered"));
  EXPECT_TRUE(contains(l.warnings, "lines are not rendered"));
}

TEST(GltfImport, NonIndexedByteIndicesAndVertexColours) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t c = b.add(std::vector<std::uint8_t>{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128});
  const std::size_t i = b.add(std::vector<std::uint8_t>{2, 1, 0});
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"] = {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 36}},
                      {{"buffer", 0}, {"byteOffset", c}, {"byteLength", 12}},
                      {{"buffer", 0}, {"byteOffset", i}, {"byteLength", 3}}};
  d["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                    {{"bufferView", 1}, {"componentType", 5121}, {"normalized", true}, {"count", 3}, {"type", "VEC4"}},
                    {{"bufferView", 2}, {"componentType", 5121}, {"count", 3}, {"type", "SCALAR"}}};
  d["meshes"][0]["primitives"] = {{{"attributes", {{"POSITION", 0}, {"COLOR_0", 1}}}},
                                  {{"attributes", {{"POSITION", 0}}}, {"indices", 2}}};
  auto l = loadDoc("colours", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.instances.size(), 2u);
  const Mesh& m0 = s.meshes[s.instances[0].mesh];
  EXPECT_EQ(m0.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(m0.colors.size(), 3u);
  EXPECT_FLOAT_EQ(m0.colors[0].x, 1.0f);
  EXPECT_NEAR(m0.colors[2].w, 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(s.meshes[s.instances[1].mesh].indices, (std::vector<std::uint32_t>{2, 1, 0}));
}

TEST(GltfImport, MaterialMapping) {
  json d = triangleDoc();
  d["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_emissive_strength", "KHR_materials_unlit",
                         "KHR_materials_ior", "KHR_materials_volume"};
  d["materials"] = {
      {{"name", "mirror"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}},
      {{"name", "glass"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                       {"KHR_materials_ior", {{"ior", 1.33}}},
                       {"KHR_materials_volume", {{"thicknessFactor", 1}}}}}},
      {{"name", "glow"},
       {"emissiveFactor", {1, 0.5, 0}},
       {"alphaMode", "BLEND"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 0.25}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
      {{"name", "flat"}, {"extensions", {{"KHR_materials_unlit", json::object()}}}}};
  d["meshes"][0]["primitives"] = {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}},
                                  {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 1}},
                                  {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 2}},
                                  {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 3}}};
  auto l = loadDoc("materials", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const auto& mats = l.asset->scene.materials;
  ASSERT_EQ(mats.size(), 4u);
  // Smooth red metal: no diffuse, red specular, a perfect mirror, tight highlight.
  EXPECT_NEAR(mats[0].kd.x, 0.0f, 1e-6f);
  EXPECT_NEAR(mats[0].ks.x, 1.0f, 1e-6f);
  EXPECT_NEAR(mats[0].ks.y, 0.0f, 1e-6f);
  EXPECT_NEAR(mats[0].kr, 1.0f, 1e-6f);
  EXPECT_GE(mats[0].ns, 1000.0f);
  // Thick glass: transmits, refracts with its IOR, F0 from the IOR.
  EXPECT_NEAR(mats[1].kt, 1.0f, 1e-6f);
  EXPECT_NEAR(mats[1].ior, 1.33f, 1e-6f);
  EXPECT_NEAR(mats[1].ks.x, std::pow(0.33f / 2.33f, 2.0f), 1e-5f);
  EXPECT_NEAR(mats[1].kd.x, 0.0f, 1e-6f);
  // Emission times strength; rough dielectric; blend with opacity.
  EXPECT_NEAR(mats[2].emission.x, 4.0f, 1e-6f);
  EXPECT_NEAR(mats[2].emission.y, 2.0f, 1e-6f);
  EXPECT_NEAR(mats[2].ns, 1.0f, 1e-6f);
  EXPECT_NEAR(mats[2].kr, 0.0f, 1e-6f);
  EXPECT_EQ(mats[2].alphaMode, AlphaMode::Blend);
  EXPECT_NEAR(mats[2].opacity, 0.25f, 1e-6f);
  EXPECT_NEAR(mats[2].kd.x, 0.5f, 1e-6f);
  EXPECT_TRUE(mats[3].unlit);
  EXPECT_NEAR(mats[3].kd.x, 1.0f, 1e-6f);
  // Transmission is tinted by the base colour; BLEND passes light straight through (IOR 1).
  EXPECT_EQ(mats[0].transmissionTint, glm::vec3(1, 0, 0));
  EXPECT_EQ(mats[1].transmissionTint, glm::vec3(1.0f));
  EXPECT_FLOAT_EQ(mats[2].ior, 1.0f);
}

TEST(GltfImport, ThinWalledTransmissionDoesNotBend) {
  json d = triangleDoc();
  d["materials"] = {{{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                     {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.5}}},
                                     {"KHR_materials_ior", {{"ior", 1.5}}}}}}};
  d["meshes"][0]["primitives"][0]["material"] = 0;
  auto l = loadDoc("thin", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  EXPECT_NEAR(l.asset->scene.materials[0].ior, 1.0f, 1e-6f);
  EXPECT_NEAR(l.asset->scene.materials[0].kt, 0.5f, 1e-6f);
}

// One texture atlas for two materials (LightsPunctualLamp's metal body and paper shade): its left half metal
// and opaque, its right half dielectric and transmissive. Each material's factors scale by the maps' means
// over the texels its own triangles cover, not over the whole atlas (which made the paper half metal and
// half transmissive).
// `shadeUvs`: the second triangle's three uvs.
json atlasDoc(const std::vector<float>& shadeUvs) {
  Bytes b;
  // Two triangles, the first over the left half of the atlas (uvs x in [0, 0.5]).
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0});
  std::vector<float> uvs{0.05f, 0.1f, 0.45f, 0.1f, 0.05f, 0.9f};
  uvs.insert(uvs.end(), shadeUvs.begin(), shadeUvs.end());
  const std::size_t u = b.add(uvs);
  const std::size_t i0 = b.add(std::vector<std::uint16_t>{0, 1, 2});
  const std::size_t i1 = b.add(std::vector<std::uint16_t>{3, 4, 5});
  json d = triangleDoc();
  d["extensionsUsed"] = {"KHR_materials_transmission"};
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"] = {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 72}},
                      {{"buffer", 0}, {"byteOffset", i0}, {"byteLength", 6}},
                      {{"buffer", 0}, {"byteOffset", u}, {"byteLength", 48}},
                      {{"buffer", 0}, {"byteOffset", i1}, {"byteLength", 6}}};
  d["accessors"] = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"},
                     {"min", {0, 0, 0}}, {"max", {3, 1, 0}}},
                    {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}},
                    {{"bufferView", 2}, {"componentType", 5126}, {"count", 6}, {"type", "VEC2"}},
                    {{"bufferView", 3}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}};
  return d;
}

TEST(GltfImport, FactorMapsAreReadOverTheTexelsEachMaterialCovers) {
  json d = atlasDoc({0.55f, 0.1f, 0.95f, 0.1f, 0.55f, 0.9f});  // the shade over the right half
  auto dir = freshDir("factor-maps");
  // Metallic-roughness: blue (metal) 255 on the left, 0 on the right; green (roughness) 51 everywhere.
  test::writeBytes(dir / "mr.png", test::pngOf(8, 8, [](int x, int) {
    return std::array<std::uint8_t, 4>{0, 51, std::uint8_t(x < 4 ? 255 : 0), 255};
  }));
  // Transmission (red): 0 on the left, 102 (0.4) on the right.
  test::writeBytes(dir / "t.png", test::pngOf(8, 8, [](int x, int) {
    return std::array<std::uint8_t, 4>{std::uint8_t(x < 4 ? 0 : 102), 0, 0, 255};
  }));
  d["images"] = {{{"uri", "mr.png"}}, {{"uri", "t.png"}}};
  d["textures"] = {{{"source", 0}}, {{"source", 1}}};
  const json pbr = {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicRoughnessTexture", {{"index", 0}}}};
  const json extensions = {{"KHR_materials_transmission", {{"transmissionFactor", 1}, {"transmissionTexture", {{"index", 1}}}}}};
  d["materials"] = {{{"name", "body"}, {"pbrMetallicRoughness", pbr}, {"extensions", extensions}},
                    {{"name", "shade"}, {"pbrMetallicRoughness", pbr}, {"extensions", extensions}}};
  d["meshes"][0]["primitives"] = {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 2}}}, {"indices", 1}, {"material", 0}},
                                  {{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 2}}}, {"indices", 3}, {"material", 1}}};
  auto l = load(writeText(dir / "atlas.gltf", d.dump()));
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const auto& mats = l.asset->scene.materials;
  ASSERT_EQ(mats.size(), 2u);
  // The body: all metal (ks the base colour, no diffuse), opaque; roughness 0.2 from the map's green.
  EXPECT_NEAR(mats[0].ks.x, 0.8f, 1e-3f);
  EXPECT_NEAR(mats[0].kd.x, 0.0f, 1e-3f);
  EXPECT_NEAR(mats[0].kt, 0.0f, 1e-3f);
  EXPECT_NEAR(mats[0].roughness, 0.2f, 1e-3f);
  // The shade: a dielectric transmitting 0.4 (the map's red), the rest diffuse.
  EXPECT_NEAR(mats[1].ks.x, 0.04f, 1e-3f);
  EXPECT_NEAR(mats[1].kt, 0.4f, 1e-3f);
  EXPECT_NEAR(mats[1].kd.x, 0.8f * 0.6f, 1e-3f);
  EXPECT_NEAR(mats[1].roughness, 0.2f, 1e-3f);
  // A palette atlas maps whole faces to one texel: the shade's triangle at one point of the right half.
  json palette = atlasDoc({0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f});
  palette["images"] = d["images"];
  palette["textures"] = d["textures"];
  palette["materials"] = d["materials"];
  palette["meshes"] = d["meshes"];
  palette["extensionsUsed"] = d["extensionsUsed"];
  auto flat = load(writeText(dir / "atlas-palette.gltf", palette.dump()));
  ASSERT_TRUE(flat.asset.ok()) << flat.asset.error().message;
  EXPECT_NEAR(flat.asset->scene.materials[1].kt, 0.4f, 1e-3f) << "the palette texel's transmission";
  EXPECT_NEAR(flat.asset->scene.materials[1].ks.x, 0.04f, 1e-3f) << "the palette texel's dielectric";
  // A material no triangle uses would keep the whole atlas's means; one without uvs too (the triangle doc).
  d["meshes"][0]["primitives"] = {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 1}}};
  auto whole = load(writeText(dir / "atlas-no-uvs.gltf", d.dump()));
  ASSERT_TRUE(whole.asset.ok()) << whole.asset.error().message;
  EXPECT_NEAR(whole.asset->scene.materials[1].kt, 0.2f * 0.5f, 1e-3f);  // transmission 0.2, times 1 − metallic ½
}

// glTF's sidedness: single-sided unless the material says otherwise, the default material too; a skinned
// node's mesh is drawn unposed (skins are ignored), so its faces turn no way the author meant: it gets a
// double-sided copy of its material, and the unskinned node keeps the single-sided one.
TEST(GltfImport, SingleSidedByDefaultAndUnposedSkinsShowBothSides) {
  json d = triangleDoc();
  d["materials"] = {{{"name", "paper"}}, {{"name", "card"}, {"doubleSided", true}}};
  d["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}},
                 {{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 1}}}}},
                 {{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}};
  d["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}, {"skin", 0}}, {{"mesh", 1}, {"skin", 0}}, {{"mesh", 2}}};
  d["scenes"][0]["nodes"] = {0, 1, 2, 3};
  d["skins"] = {{{"joints", {0}}}};
  auto l = loadDoc("sidedness", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.instances.size(), 4u);
  auto material = [&](std::size_t i) { return s.materials[s.instances[i].material]; };
  EXPECT_FALSE(material(0).doubleSided) << "glTF's default is single-sided";
  EXPECT_TRUE(material(1).doubleSided) << "the skinned node's copy";
  EXPECT_EQ(material(1).kd, material(0).kd);
  EXPECT_TRUE(material(2).doubleSided) << "double-sided as the file says";
  EXPECT_EQ(s.instances[2].material, 1u) << "a double-sided material needs no copy";
  EXPECT_FALSE(material(3).doubleSided) << "the default material";
}

TEST(GltfImport, LightsCameraAndInstancing) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t i = b.add(std::vector<std::uint16_t>{0, 1, 2});
  const std::size_t t = b.add(std::vector<float>{0, 0, 0, 10, 0, 0, 20, 0, 0});
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", t}, {"byteLength", 36}});
  d["bufferViews"][0]["byteOffset"] = p;
  d["bufferViews"][1]["byteOffset"] = i;
  d["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
  d["extensionsUsed"] = {"KHR_lights_punctual", "EXT_mesh_gpu_instancing"};
  d["extensions"] = {{"KHR_lights_punctual",
                      {{"lights",
                        {{{"type", "point"}, {"intensity", 5}, {"color", {1, 0.5, 0.25}}, {"range", 3}},
                         {{"type", "spot"}, {"intensity", 2}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
                         {{"type", "directional"}, {"intensity", 3}},
                         {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.5}, {"outerConeAngle", 0.4}}}}}}}}};
  d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"zfar", 100}}}}};
  d["nodes"] = {{{"mesh", 0}, {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", 2}}}}}}}},
                {{"camera", 0}, {"translation", {0, 0, 10}}},
                {{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                {{"rotation", {-0.7071068, 0, 0, 0.7071068}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
                {{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}},
                {{"extensions", {{"KHR_lights_punctual", {{"light", 3}}}}}},
                {{"extensions", {{"KHR_lights_punctual", {{"light", 9}}}}}}};
  d["scenes"][0]["nodes"] = {0, 1, 2, 3, 4, 5, 6};
  auto l = loadDoc("lights", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Scene& s = l.asset->scene;
  ASSERT_EQ(s.instances.size(), 3u);
  EXPECT_NEAR(s.instances[2].worldFromObject[3].x, 20.0f, 1e-6f);
  EXPECT_NEAR(s.camera.yFovDeg, glm::degrees(0.5f), 1e-4f);
  EXPECT_NEAR(s.camera.posW.z, 10.0f, 1e-6f);
  EXPECT_NEAR(s.camera.targetW.z, 9.0f, 1e-6f);
  ASSERT_EQ(s.lights.size(), 3u);  // the bad cone and the missing light are skipped, no defaults added
  EXPECT_EQ(s.lights[0].type, LightType::Point);
  EXPECT_EQ(s.lights[0].posW, glm::vec3(1, 2, 3));
  EXPECT_EQ(s.lights[0].attenuation, glm::vec3(0, 0, 1));
  // Candela / π: glTF's Lambertian BRDF is albedo/π, the engine's diffuse term has no 1/π.
  EXPECT_NEAR(s.lights[0].intensity, 5.0 / 3.14159265358979, 1e-5);
  EXPECT_NEAR(s.lights[2].intensity, 3.0 / 3.14159265358979, 1e-5);
  EXPECT_EQ(s.background, glm::vec3(0.05f));  // glTF has none: the documented dark grey, under
  EXPECT_EQ(s.environment.kind, Environment::Kind::Sky);  // the default sky, with the file's lights too
  EXPECT_FLOAT_EQ(s.lights[0].range, 3.0f);
  EXPECT_EQ(s.lights[1].type, LightType::Spot);
  EXPECT_NEAR(s.lights[1].dirW.y, -1.0f, 1e-5f);  // −Z rotated −90° about X points down
  EXPECT_NEAR(s.lights[1].outerConeDeg, glm::degrees(0.4f), 1e-4f);
  EXPECT_EQ(s.lights[2].type, LightType::Directional);
  EXPECT_TRUE(contains(l.warnings, "spot cone"));
  EXPECT_TRUE(contains(l.warnings, "light 9 does not exist"));
}

TEST(GltfImport, InvalidCameraIsSkippedForTheDefault) {
  json d = triangleDoc();
  d["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 2}, {"zfar", 1}}}}};
  d["nodes"].push_back({{"camera", 0}});
  d["scenes"][0]["nodes"] = {0, 1};
  auto l = loadDoc("badcamera", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  EXPECT_TRUE(contains(l.warnings, "camera skipped"));
  EXPECT_GT(l.asset->scene.camera.posW.z, 0.5f);  // the framing default
}

TEST(GltfImport, SceneSelection) {
  json d = triangleDoc();
  d["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}}, {{"mesh", 0}}};
  d["scenes"] = {{{"nodes", {0}}}, {{"nodes", {1, 2}}, {"name", "second"}}};
  d["scene"] = 1;
  auto l = loadDoc("scenes", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  EXPECT_EQ(l.asset->scene.instances.size(), 2u);
  EXPECT_EQ(l.asset->scene.name, "second");
  GltfOptions o;
  o.sceneIndex = 0;
  auto l0 = load(std::string(test::outputDir()) + "/gltf/scenes/scenes.gltf", o);
  ASSERT_TRUE(l0.asset.ok());
  EXPECT_EQ(l0.asset->scene.instances.size(), 1u);
  o.sceneIndex = 5;
  auto l5 = load(std::string(test::outputDir()) + "/gltf/scenes/scenes.gltf", o);
  ASSERT_FALSE(l5.asset.ok());
  EXPECT_NE(l5.asset.error().message.find("scene 5 does not exist"), std::string::npos);
}

TEST(GltfImport, NormalMapGetsTangents) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t u = b.add(std::vector<float>{0, 0, 1, 0, 0, 1});
  const std::size_t i = b.add(std::vector<std::uint16_t>{0, 1, 2});
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"] = {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 36}},
                      {{"buffer", 0}, {"byteOffset", i}, {"byteLength", 6}},
                      {{"buffer", 0}, {"byteOffset", u}, {"byteLength", 24}}};
  d["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC2"}});
  auto dir = freshDir("tangents");
  test::writeBytes(dir / "n.png", test::pngBytes(2, 2));
  d["images"] = {{{"uri", "n.png"}}, {{"uri", "missing.png"}}};
  d["textures"] = {{{"source", 0}}, {{"source", 1}}};
  // The second material's image is missing on disk: its base colour falls back with a warning.
  d["materials"] = {{{"normalTexture", {{"index", 0}}}, {"emissiveTexture", {{"index", 0}}}},
                    {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}};
  d["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2;
  d["meshes"][0]["primitives"][0]["material"] = 0;
  auto l = load(writeText(dir / "tangents.gltf", d.dump()));
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  const Mesh& m = l.asset->scene.meshes[0];
  ASSERT_EQ(m.tangents.size(), 3u);
  EXPECT_NEAR(m.tangents[0].x, 1.0f, 1e-5f);
  EXPECT_FLOAT_EQ(m.tangents[0].w, 1.0f);
  EXPECT_FALSE(l.asset->scene.textures[std::size_t(l.asset->scene.materials[0].normalTexture)].srgb);
  // The same image as an emissive texture is a second, sRGB-decoded texture.
  ASSERT_GE(l.asset->scene.materials[0].emissiveTexture, 0);
  EXPECT_TRUE(l.asset->scene.textures[std::size_t(l.asset->scene.materials[0].emissiveTexture)].srgb);
  EXPECT_TRUE(contains(l.warnings, "missing.png"));
  EXPECT_EQ(l.asset->scene.textures[std::size_t(l.asset->scene.materials[1].kdTexture)].name, "fallback");
}

TEST(GltfAnimation, SamplersInterpolate) {
  AnimChannel c;
  c.path = AnimPath::Translation;
  c.times = {0.0f, 1.0f, 3.0f};
  c.values = {{0, 0, 0, 0}, {2, 0, 0, 0}, {2, 4, 0, 0}};
  c.interpolation = AnimInterpolation::Linear;
  EXPECT_NEAR(sampleChannel(c, 0.5f).x, 1.0f, 1e-6f);
  EXPECT_NEAR(sampleChannel(c, 2.0f).y, 2.0f, 1e-6f);
  EXPECT_NEAR(sampleChannel(c, -1.0f).x, 0.0f, 1e-6f);  // clamped before the first key
  EXPECT_NEAR(sampleChannel(c, 9.0f).y, 4.0f, 1e-6f);   // and after the last
  c.interpolation = AnimInterpolation::Step;
  EXPECT_NEAR(sampleChannel(c, 0.99f).x, 0.0f, 1e-6f);
  EXPECT_NEAR(sampleChannel(c, 1.0f).x, 2.0f, 1e-6f);
  // CUBICSPLINE with zero tangents is smoothstep between the keys.
  AnimChannel cs;
  cs.path = AnimPath::Translation;
  cs.interpolation = AnimInterpolation::CubicSpline;
  cs.times = {0.0f, 1.0f};
  cs.values = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 0}};
  EXPECT_NEAR(sampleChannel(cs, 0.25f).x, 3 * 0.0625f - 2 * 0.015625f, 1e-6f);
  // Rotation: slerp halfway between identity and 90° about Z is 45°, via the shortest path.
  AnimChannel r;
  r.path = AnimPath::Rotation;
  r.interpolation = AnimInterpolation::Linear;
  r.times = {0.0f, 1.0f};
  const float h = std::sqrt(0.5f);
  r.values = {{0, 0, 0, 1}, {0, 0, -h, -h}};  // the second key's sign is flipped: same rotation
  const glm::vec4 q = sampleChannel(r, 0.5f);
  EXPECT_NEAR(std::abs(q.z), std::sin(glm::radians(22.5f)), 1e-5f);
  EXPECT_NEAR(std::abs(q.w), std::cos(glm::radians(22.5f)), 1e-5f);
}

TEST(GltfAnimation, ImportedAnimationMovesInstances) {
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::size_t i = b.add(std::vector<std::uint16_t>{0, 1, 2});
  const std::size_t t = b.add(std::vector<float>{0, 2});
  const std::size_t v = b.add(std::vector<float>{0, 0, 0, 4, 0, 0});
  const std::size_t bad = b.add(std::vector<float>{1, 1});  // equal key times: skipped
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"] = {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 36}},
                      {{"buffer", 0}, {"byteOffset", i}, {"byteLength", 6}},
                      {{"buffer", 0}, {"byteOffset", t}, {"byteLength", 8}},
                      {{"buffer", 0}, {"byteOffset", v}, {"byteLength", 24}},
                      {{"buffer", 0}, {"byteOffset", bad}, {"byteLength", 8}}};
  d["accessors"].push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
  d["accessors"].push_back({{"bufferView", 3}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
  d["accessors"].push_back({{"bufferView", 4}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
  // Parent node 0 is animated; child node 1 carries the mesh with its own offset.
  d["nodes"] = {{{"children", {1}}}, {{"mesh", 0}, {"translation", {0, 1, 0}}}};
  d["animations"] = {{{"samplers", {{{"input", 2}, {"output", 3}}, {{"input", 4}, {"output", 3}}}},
                      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                                    {{"sampler", 1}, {"target", {{"node", 1}, {"path", "scale"}}}}}}}};
  auto l = loadDoc("animation", d);
  ASSERT_TRUE(l.asset.ok()) << l.asset.error().message;
  GltfAsset& a = *l.asset;
  ASSERT_EQ(a.animation.clips.size(), 1u);
  EXPECT_EQ(a.animation.clips[0].channels.size(), 1u);
  EXPECT_FLOAT_EQ(a.animation.clips[0].duration, 2.0f);
  EXPECT_TRUE(contains(l.warnings, "strictly increasing"));
  ASSERT_EQ(a.scene.instances.size(), 1u);
  EXPECT_TRUE(a.scene.instances[0].dynamic);
  a.animation.apply(0, 1.0f, a.scene);
  EXPECT_NEAR(a.scene.instances[0].worldFromObject[3].x, 2.0f, 1e-5f);
  EXPECT_NEAR(a.scene.instances[0].worldFromObject[3].y, 1.0f, 1e-5f);
}

}  // namespace
}  // namespace tandem
