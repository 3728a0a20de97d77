// The loaders' resource contract in small, exact cases (docs/gltf.md and docs/scene-format.md,
// "Resources"): what is charged, what is refused with which message, and what is kept once. The
// adversarial files at 400 KB and 4 MB are in tests/resource.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/AdversarialFiles.h"
#include "io/LoadBudget.h"
#include "tandem/Gltf.h"
#include "tandem/Image.h"
#include "tandem/Log.h"
#include "tandem/Primitives.h"
#include "tandem/SceneFile.h"
#include "unit/GltfTestUtil.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::Bytes;
using test::freshDir;
using test::triangleDoc;
using test::writeBytes;
using test::writeText;

struct Quiet {
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  ~Quiet() { setLogSink(old); }
};

Result<GltfAsset> load(const fs::path& p, GltfOptions opt = {}) {
  Quiet q;
  opt.onWarning = [](const std::string&) {};
  return loadGltfAsset(p.string(), opt);
}

TEST(LoadBudget, LimitGrowsWithInputAndChargesRefuseWithoutTaking) {
  LoadBudget b(1000, 4);
  EXPECT_EQ(b.limit(), 1000u);
  b.addInput(100);
  EXPECT_EQ(b.limit(), 1400u);
  EXPECT_TRUE(b.charge(1400));
  EXPECT_FALSE(b.charge(1));
  EXPECT_EQ(b.used(), 1400u);
  b.addInput(1);
  EXPECT_TRUE(b.charge(4));
  EXPECT_FALSE(b.charge(~std::uint64_t(0)));
  LoadBudget huge(~std::uint64_t(0) - 5, 1u << 20);
  huge.addInput(~std::uint64_t(0));
  EXPECT_EQ(huge.limit(), ~std::uint64_t(0)) << "saturates instead of wrapping";
  EXPECT_NE(b.refusal("the thing", 9).find("the thing would take 9 more bytes; the load has used 1404 of its budget of 1404 bytes (1000 + 4 per input byte × 101 input bytes)"),
            std::string::npos)
      << b.refusal("the thing", 9);
}

TEST(LoadBudget, LongKeyOverManyArraysLoadsWithoutCopyingThePath) {
  // The reported file, scaled down: one key of 200 000 bytes over 100 000 empty arrays. The walk used to
  // keep a copy of the path per item (20 GB at this size).
  auto dir = freshDir("budget-longkey");
  const std::string text = R"({"asset":{"version":"2.0"},")" + std::string(200000, 'k') + "\":[" +
                           [] {
                             std::string s;
                             for (int i = 0; i < 100000; ++i) s += i ? ",[]" : "[]";
                             return s;
                           }() +
                           "]}";
  auto r = load(writeText(dir / "k.gltf", text));
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->stats.inputBytes, text.size());
  EXPECT_LT(r->stats.modelEstimate, 2 * text.size()) << "unknown top-level keys cost tinygltf nothing";
}

TEST(LoadBudget, TypeErrorsStillNameTheirPath) {
  json d = triangleDoc();
  d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 1.5;
  d["extras"] = {{"free", {{"attributes", {{"x", "not checked"}}}}}};
  auto dir = freshDir("budget-path");
  auto r = load(writeText(dir / "p.gltf", d.dump()));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("p.gltf: /meshes/0/primitives/0/attributes/POSITION: 1.5 is not an integer"),
            std::string::npos)
      << r.error().message;
  // A long key in an error path is shortened, not copied whole.
  d = triangleDoc();
  d["nodes"][0][std::string(5000, 'n')] = {{"mesh", -1}};
  r = load(writeText(dir / "q.gltf", d.dump()));
  ASSERT_FALSE(r);
  EXPECT_LT(r.error().message.size(), 300u) << r.error().message;
  EXPECT_NE(r.error().message.find("/nodes/0/nnnn"), std::string::npos) << r.error().message;
}

TEST(LoadBudget, ManyTinyMaterialsRefusedBeforeTinygltfBuildsThem) {
  // "{}" costs 3 bytes of JSON and 2 KB as a tinygltf::Material.
  auto dir = freshDir("budget-materials");
  std::string mats;
  for (int i = 0; i < 50000; ++i) mats += i ? ",{}" : "{}";
  GltfOptions opt;
  opt.limits.budgetBaseBytes = 16u << 20;
  auto r = load(writeText(dir / "m.gltf", R"({"asset":{"version":"2.0"},"materials":[)" + mats + "]}"), opt);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("the parsed model (estimated before parsing) would take"), std::string::npos)
      << r.error().message;
  // The same file with a budget that fits loads: the estimate is a charge, not a ban.
  opt.limits.budgetBaseBytes = 256u << 20;
  EXPECT_TRUE(load(dir / "m.gltf", opt));
}

TEST(LoadBudget, GlbOnlyTheFirstBufferMayBeTheBinChunk) {
  auto dir = freshDir("budget-glb");
  Bytes b;
  json d = triangleDoc(&b);
  while (b.data.size() % 4) b.data.push_back(0);
  d["buffers"] = json::array({{{"byteLength", b.data.size()}}, {{"byteLength", b.data.size()}}});
  std::string js = d.dump();
  while (js.size() % 4) js += ' ';
  std::vector<std::uint8_t> glb{'g', 'l', 'T', 'F'};
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) glb.push_back(std::uint8_t(v >> (8 * i)));
  };
  u32(2);
  u32(std::uint32_t(12 + 8 + js.size() + 8 + b.data.size()));
  u32(std::uint32_t(js.size()));
  u32(0x4E4F534A);
  glb.insert(glb.end(), js.begin(), js.end());
  u32(std::uint32_t(b.data.size()));
  u32(0x004E4942);
  glb.insert(glb.end(), b.data.begin(), b.data.end());
  auto r = load(writeBytes(dir / "two.glb", glb));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("/buffers/1: has no uri, but only buffers[0] may refer to the GLB's BIN chunk"),
            std::string::npos)
      << r.error().message;
}

TEST(LoadBudget, RepeatedReadsOfOneFileAreCharged) {
  auto dir = freshDir("budget-repeat");
  Bytes b;
  json d = triangleDoc(&b);
  std::vector<std::uint8_t> big(1u << 20, 0);
  std::memcpy(big.data(), b.data.data(), b.data.size());
  writeBytes(dir / "data.bin", big);
  d["buffers"] = json::array();
  for (int i = 0; i < 40; ++i) d["buffers"].push_back({{"byteLength", big.size()}, {"uri", "data.bin"}});
  GltfOptions opt;
  opt.limits.budgetBaseBytes = 8u << 20;
  opt.limits.budgetBytesPerInputByte = 4;
  auto r = load(writeText(dir / "r.gltf", d.dump()), opt);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("data.bin': reading it once more would take 1048576 more bytes"), std::string::npos)
      << r.error().message;
  // A few repeats fit the budget and load.
  while (d["buffers"].size() > 3) d["buffers"].erase(d["buffers"].size() - 1);
  r = load(writeText(dir / "r3.gltf", d.dump()), opt);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->stats.inputBytes, fs::file_size(dir / "r3.gltf") + big.size()) << "a file counts once as input";
}

TEST(LoadBudget, ImagesNamingOneFileDecodeOnce) {
  auto dir = freshDir("budget-images");
  writeBytes(dir / "tex.png", test::pngBytes(64, 32));
  json d = triangleDoc();
  d["images"] = json::array();
  d["textures"] = json::array();
  d["materials"] = json::array();
  for (int i = 0; i < 20; ++i) {
    d["images"].push_back({{"uri", i % 2 ? "tex.png" : "./tex.png"}});
    d["textures"].push_back({{"source", i}});
    d["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
  }
  auto r = load(writeText(dir / "i.gltf", d.dump()));
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->scene.textures.size(), 1u) << "one decode for 20 images of the same bytes";
  EXPECT_EQ(r->scene.textures[0].width, 64);
  ASSERT_GE(r->scene.materials.size(), 20u);
  for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(r->scene.materials[i].kdTexture, 0);
  EXPECT_LT(r->stats.decodedBytes, 2u * 64 * 32 * 4 + 4096) << "texels charged once";
}

TEST(LoadBudget, PrimitivesReadingTheSameAccessorsShareOneMesh) {
  auto dir = freshDir("budget-sharedmesh");
  json d = triangleDoc();
  d["meshes"] = json::array();
  d["nodes"] = json::array();
  d["scenes"][0]["nodes"] = json::array();
  for (int i = 0; i < 10; ++i) {
    d["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}});
    d["nodes"].push_back({{"mesh", i}, {"translation", {i, 0, 0}}});
    d["scenes"][0]["nodes"].push_back(i);
  }
  auto r = load(writeText(dir / "s.gltf", d.dump()));
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->scene.meshes.size(), 1u);
  ASSERT_EQ(r->scene.instances.size(), 10u);
  for (const Instance& inst : r->scene.instances) EXPECT_EQ(inst.mesh, 0u);
  EXPECT_FLOAT_EQ(r->scene.instances[9].worldFromObject[3][0], 9.0f);
}

TEST(LoadBudget, APrimitiveKeepsOnlyTheVerticesItIndexes) {
  // Two primitives index disjoint halves of one 6-vertex array: each mesh holds its own 3 vertices, in
  // index order, and the triangles are the same points as before.
  auto dir = freshDir("budget-compact");
  Bytes b;
  const std::size_t p = b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 6, 5, 5, 5, 6, 5});
  const std::size_t i0 = b.add(std::vector<std::uint16_t>{0, 1, 2, 0});
  const std::size_t i1 = b.add(std::vector<std::uint16_t>{5, 3, 4, 0});
  json d = {{"asset", {{"version", "2.0"}}},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}},
                                         {{"attributes", {{"POSITION", 0}}}, {"indices", 2}}}}}}},
            {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"}},
                           {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}},
                           {{"bufferView", 2}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
            {"bufferViews", {{{"buffer", 0}, {"byteOffset", p}, {"byteLength", 72}},
                             {{"buffer", 0}, {"byteOffset", i0}, {"byteLength", 6}},
                             {{"buffer", 0}, {"byteOffset", i1}, {"byteLength", 6}}}},
            {"buffers", {{{"byteLength", b.data.size()}, {"uri", b.dataUri()}}}}};
  auto r = load(writeText(dir / "c.gltf", d.dump()));
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->scene.meshes.size(), 2u);
  const Mesh& a = r->scene.meshes[0];
  const Mesh& m = r->scene.meshes[1];
  ASSERT_EQ(a.positions.size(), 3u) << "all of its vertices used: order kept";
  EXPECT_EQ(a.positions[1], glm::vec3(1, 0, 0));
  ASSERT_EQ(m.positions.size(), 3u);
  ASSERT_EQ(m.normals.size(), 3u);
  ASSERT_EQ(m.indices.size(), 3u);
  EXPECT_EQ(m.positions[m.indices[0]], glm::vec3(5, 6, 5));
  EXPECT_EQ(m.positions[m.indices[1]], glm::vec3(5, 5, 5));
  EXPECT_EQ(m.positions[m.indices[2]], glm::vec3(6, 5, 5));
}

TEST(LoadBudget, InstancesAreCountedAndRefusedBeforeTheyAreMade) {
  auto dir = freshDir("budget-instances");
  json d = triangleDoc();
  d["meshes"][0]["primitives"] = json::array();
  for (int i = 0; i < 1000; ++i) d["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"indices", 1}});
  d["nodes"] = json::array();
  d["scenes"][0]["nodes"] = json::array();
  for (int i = 0; i < 1000; ++i) {
    d["nodes"].push_back({{"mesh", 0}});
    d["scenes"][0]["nodes"].push_back(i);
  }
  GltfOptions opt;
  opt.limits.budgetBaseBytes = 32u << 20;
  auto r = load(writeText(dir / "n.gltf", d.dump()), opt);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("1000000 instances (nodes × primitives × GPU instances) would take"), std::string::npos)
      << r.error().message;
}

TEST(LoadBudget, ScenePlacementsShareTheFilesMeshes) {
  auto dir = freshDir("budget-placements");
  Bytes b;
  writeText(dir / "t.gltf", triangleDoc(&b).dump());
  std::string inst;
  for (int i = 0; i < 500; ++i) inst += std::string(i ? "," : "") + R"({"name":"p)" + std::to_string(i) + R"(","gltf":"t.gltf"})";
  const std::string text = R"({"instances":[)" + inst + "]}";
  Quiet q;
  auto r = parseSceneJson(text, "s.json", dir.string());
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->meshes.size(), 1u) << "one copy of the file's mesh for 500 placements";
  EXPECT_EQ(r->materials.size(), 1u);
  ASSERT_EQ(r->instances.size(), 500u);
  EXPECT_EQ(r->instances[499].name.rfind("p499/", 0), 0u) << r->instances[499].name;
  EXPECT_EQ(r->meshes[0].name.rfind("p0/", 0), 0u) << "shared data keeps its first placement's name";
}

TEST(LoadBudget, SceneMeshesAreChargedBeforeTheyAreBuilt) {
  std::string meshes;
  for (int i = 0; i < 8; ++i)
    meshes += std::string(i ? "," : "") + "\"m" + std::to_string(i) + R"(":{"primitive":"sphere","segments":2048,"rings":1024})";
  Quiet q;
  auto r = parseSceneJson(R"({"meshes":{)" + meshes + "}}", "s.json", ".");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("s.json: /meshes/m0: the mesh would take"), std::string::npos) << r.error().message;
}

TEST(LoadBudget, SceneObjectsWithManyKeysParseInLinearTime) {
  // 200 000 keys in one object: nlohmann's ordered map made this n² (tens of seconds); the reader appends.
  std::string mats;
  for (int i = 0; i < 200000; ++i) mats += std::string(i ? "," : "") + "\"m" + std::to_string(i) + R"(":{"kd":0.5})";
  Quiet q;
  auto r = parseSceneJson(R"({"materials":{)" + mats + R"(},"materials2":1})", "s.json", ".");
  ASSERT_FALSE(r) << "materials2 is not a key of the format";
  EXPECT_NE(r.error().message.find("unknown key 'materials2'"), std::string::npos) << r.error().message;
  auto dup = parseSceneJson(R"({"materials":{"a":{},"b":{},"a":{}}})", "s.json", ".");
  ASSERT_FALSE(dup);
  EXPECT_NE(dup.error().message.find("s.json: /materials/a: duplicate key 'a'"), std::string::npos)
      << dup.error().message;
}

TEST(LoadBudget, PngBombIsRefusedNotInflated) {
  auto dir = freshDir("budget-png");
  auto r = readPng(writeBytes(dir / "bomb.png", test::pngBomb(1, 1, 64u << 20)));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("decoding needs more memory than the image's size allows"), std::string::npos)
      << r.error().message;
  // Dimensions are read from the header and checked before anything is decoded.
  r = readPng(writeBytes(dir / "big.png", test::pngHeaderOnly(4000, 4000)), 1u << 20);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("4000x4000 pixels, more than the limit of 1048576"), std::string::npos)
      << r.error().message;
  // A real image still decodes, and the same bomb inside a glTF only costs the image (fallback texture).
  auto ok = readPng(writeBytes(dir / "flat.png", test::flatPng(300, 200)));
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_EQ(ok->width, 300);
  json d = triangleDoc();
  writeBytes(dir / "bomb2.png", test::pngBomb(2, 2, 32u << 20));
  d["images"] = {{{"uri", "bomb2.png"}}};
  d["textures"] = {{{"source", 0}}};
  d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  std::vector<std::string> warnings;
  GltfOptions opt;
  opt.onWarning = [&](const std::string& w) { warnings.push_back(w); };
  Quiet q;
  auto g = loadGltfAsset(writeText(dir / "g.gltf", d.dump()).c_str(), opt);
  ASSERT_TRUE(g) << g.error().message;
  bool warned = false;
  for (const auto& w : warnings) warned |= w.find("decoding needs more memory than its declared size allows") != std::string::npos;
  EXPECT_TRUE(warned);
}

// ---- each decode charged exactly what it keeps ----
// The charges are worked out here from what the load keeps (the texels, the mesh's arrays), so that a charge
// that is too small (an undercharge lets a hostile file past the budget) or too large fails. Each case also
// sets the budget between the right charge and a plausible wrong one, so an undercharge is refused there.

std::vector<std::uint8_t> encodedImage(const std::string& format, int w, int h, int channels) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h * channels));
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>((i * 37) % 251);
  std::vector<std::uint8_t> out;
  auto sink = [](void* ctx, void* data, int size) {
    auto* o = static_cast<std::vector<std::uint8_t>*>(ctx);
    o->insert(o->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
  };
  if (format == "png") stbi_write_png_to_func(sink, &out, w, h, channels, px.data(), w * channels);
  else stbi_write_jpg_to_func(sink, &out, w, h, channels, px.data(), 90);
  return out;
}

TEST(LoadBudget, EachImageIsChargedTheTexelsItKeepsWhateverItsFileFormat) {
  auto dir = freshDir("budget-texels");
  json d = triangleDoc();
  d["images"] = {{{"uri", "tex.img"}}};
  d["textures"] = {{{"source", 0}}};
  d["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  d["meshes"][0]["primitives"][0]["material"] = 0;
  const std::string doc = writeText(dir / "t.gltf", d.dump());
  // The baseline: a 1×1 RGBA image keeps 4 bytes, whichever way they are counted.
  writeBytes(dir / "tex.img", encodedImage("png", 1, 1, 4));
  auto base = load(doc);
  ASSERT_TRUE(base) << base.error().message;
  ASSERT_EQ(base->scene.textures.size(), 1u);
  ASSERT_EQ(base->scene.textures[0].rgba8.size(), 4u);
  const std::uint64_t modelEstimate = base->stats.modelEstimate, decodedBase = base->stats.decodedBytes;
  struct Case {
    const char* format;
    int channels;  // in the file; the texture keeps 4
  };
  for (const Case c : {Case{"png", 1}, Case{"png", 2}, Case{"png", 3}, Case{"png", 4}, Case{"jpg", 1}, Case{"jpg", 3}}) {
    SCOPED_TRACE(std::string(c.format) + " with " + std::to_string(c.channels) + " channels");
    const int w = 37, h = 21;
    const std::uint64_t texels = std::uint64_t(w) * h * 4;
    writeBytes(dir / "tex.img", encodedImage(c.format, w, h, c.channels));
    auto r = load(doc);
    ASSERT_TRUE(r) << r.error().message;
    ASSERT_EQ(r->scene.textures.size(), 1u);
    EXPECT_EQ(r->scene.textures[0].rgba8.size(), texels);
    EXPECT_EQ(r->stats.modelEstimate, modelEstimate);
    EXPECT_EQ(r->stats.decodedBytes - decodedBase, texels - 4) << "the texels kept, 4 bytes each";
    // The whole load's charge, worked out from the baseline: a budget one byte short of it (between the right
    // charge and, say, the file's channels per texel) refuses the load; that charge exactly is enough. (A
    // budget per input byte of 0: the limit is the base.)
    const std::uint64_t total = modelEstimate + decodedBase - 4 + texels;
    GltfOptions tight;
    tight.limits.budgetBytesPerInputByte = 0;
    tight.limits.budgetBaseBytes = total - 1;
    auto refused = load(doc, tight);
    ASSERT_FALSE(refused) << "a budget one byte short of the texels kept";
    EXPECT_NE(refused.error().message.find("would take"), std::string::npos) << refused.error().message;
    tight.limits.budgetBaseBytes = total;
    auto fits = load(doc, tight);
    EXPECT_TRUE(fits) << fits.error().message;
  }
}

TEST(LoadBudget, EachVertexAttributeIsChargedWhatTheMeshKeeps) {
  // The triangle with one more attribute, read from an accessor of 3 elements: the load reads the accessor
  // as floats (charged: 3 × its components × 4 bytes) and the mesh keeps its own array (charged: its size).
  auto dir = freshDir("budget-attributes");
  std::uint64_t texelBytes = 0;  // of the last load's textures
  auto decodedOf = [&](const json& d, const std::string& name, const Mesh** mesh = nullptr) -> std::uint64_t {
    static Result<GltfAsset> kept = Error{""};
    kept = load(writeText(dir / name, d.dump()));
    EXPECT_TRUE(kept) << kept.error().message;
    if (!kept) return 0;
    EXPECT_EQ(kept->scene.meshes.size(), 1u);
    if (mesh) *mesh = &kept->scene.meshes[0];
    texelBytes = 0;
    for (const Texture& tex : kept->scene.textures) texelBytes += tex.rgba8.size();
    return kept->stats.decodedBytes;
  };
  Bytes plainBytes;
  const json plain = triangleDoc(&plainBytes);
  const std::uint64_t base = decodedOf(plain, "plain.gltf");
  struct Case {
    const char* attribute;
    const char* type;
    int components;
    int componentType;  // 5126 float, 5121 unsigned byte (normalized)
    std::size_t keptBytes;  // what the mesh keeps per vertex
  };
  for (const Case c : {Case{"TEXCOORD_0", "VEC2", 2, 5126, sizeof(glm::vec2)}, Case{"COLOR_0", "VEC3", 3, 5126, sizeof(glm::vec4)},
                       Case{"COLOR_0", "VEC4", 4, 5126, sizeof(glm::vec4)}, Case{"COLOR_0", "VEC3", 3, 5121, sizeof(glm::vec4)},
                       Case{"NORMAL", "VEC3", 3, 5126, 0}}) {  // normals are kept (made) without the attribute too
    SCOPED_TRACE(std::string(c.attribute) + " " + c.type + " of " + std::to_string(c.componentType));
    Bytes b = plainBytes;
    std::size_t offset = 0, length = 0;
    if (c.componentType == 5126) {
      std::vector<float> v(static_cast<std::size_t>(3 * c.components), 0.5f);
      if (std::string(c.attribute) == "NORMAL") v = {0, 0, 1, 0, 0, 1, 0, 0, 1};
      offset = b.add(v);
      length = v.size() * sizeof(float);
    } else {
      std::vector<std::uint8_t> v(static_cast<std::size_t>(3 * c.components), 128);
      offset = b.add(v);
      length = v.size();
    }
    json d = plain;
    d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
    d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}});
    json accessor = {{"bufferView", 2}, {"componentType", c.componentType}, {"count", 3}, {"type", c.type}};
    if (c.componentType != 5126) accessor["normalized"] = true;
    d["accessors"].push_back(accessor);
    d["meshes"][0]["primitives"][0]["attributes"][c.attribute] = 2;
    const Mesh* mesh = nullptr;
    const std::uint64_t with = decodedOf(d, "with.gltf", &mesh);
    ASSERT_NE(mesh, nullptr);
    const std::size_t kept = std::string(c.attribute) == "TEXCOORD_0" ? mesh->uvs.size() * sizeof(glm::vec2)
                             : std::string(c.attribute) == "COLOR_0" ? mesh->colors.size() * sizeof(glm::vec4)
                                                                      : 0;
    EXPECT_EQ(kept, 3 * c.keptBytes);
    EXPECT_EQ(with - base, 3u * static_cast<std::uint64_t>(c.components) * sizeof(float) + kept);
  }
  // A normal-mapped primitive keeps 3 tangents; without uvs to make them from, 3 zero uvs too.
  json mapped = plain;
  writeBytes(dir / "n.png", test::pngBytes(2, 2));
  mapped["images"] = {{{"uri", "n.png"}}};
  mapped["textures"] = {{{"source", 0}}};
  mapped["materials"] = {{{"normalTexture", {{"index", 0}}}}};
  mapped["meshes"][0]["primitives"][0]["material"] = 0;
  const Mesh* mesh = nullptr;
  const std::uint64_t withMap = decodedOf(mapped, "mapped.gltf", &mesh);
  const std::uint64_t mapTexels = texelBytes;
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->tangents.size(), 3u);
  EXPECT_EQ(mesh->uvs.size(), 3u);
  json unmapped = mapped;
  unmapped["meshes"][0]["primitives"][0].erase("material");  // the same image decoded, no tangents
  unmapped["materials"][0]["occlusionTexture"] = {{"index", 0}};
  unmapped["materials"][0].erase("normalTexture");
  unmapped["meshes"][0]["primitives"][0]["material"] = 0;
  const std::uint64_t withoutMap = decodedOf(unmapped, "unmapped.gltf", &mesh);
  ASSERT_NE(mesh, nullptr);
  EXPECT_TRUE(mesh->tangents.empty());
  EXPECT_EQ(withMap - mapTexels - (withoutMap - texelBytes), 3 * (sizeof(glm::vec4) + sizeof(glm::vec2)));
}

TEST(LoadBudget, SceneFileMeshesAreChargedWhatTheyKeep) {
  // The charge a built-in mesh is refused for is the size of the mesh it would have built: positions,
  // normals and uvs per vertex, three indices per triangle (tandem/Primitives.h builds the same mesh here).
  // This sphere's mesh needs 115 MB, over the 64 MB budget of a small file.
  Quiet q;
  auto r = parseSceneJson(R"({"meshes": {"big": {"primitive": "sphere", "segments": 2048, "rings": 1000}}})", "s.json", ".");
  ASSERT_FALSE(r);
  const Mesh sphere = makeSphere(1.0f, 2048, 1000);
  EXPECT_TRUE(sphere.tangents.empty() && sphere.colors.empty());
  const std::uint64_t kept = sphere.bytes() - sphere.name.size();
  EXPECT_NE(r.error().message.find("/meshes/big: the mesh would take " + std::to_string(kept) + " more bytes"),
            std::string::npos)
      << r.error().message << " (the mesh keeps " << kept << " bytes)";
  auto p = parseSceneJson(R"({"meshes": {"big": {"primitive": "plane", "divisions": 1400}}})", "s.json", ".");
  ASSERT_FALSE(p);
  const Mesh plane = makePlane(glm::vec2(10.0f), 1400);
  const std::uint64_t planeKept = plane.bytes() - plane.name.size();
  EXPECT_NE(p.error().message.find("/meshes/big: the mesh would take " + std::to_string(planeKept) + " more bytes"),
            std::string::npos)
      << p.error().message << " (the mesh keeps " << planeKept << " bytes)";
}

}  // namespace
}  // namespace tandem
