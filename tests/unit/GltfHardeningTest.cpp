// Hostile glTF files (docs: ../shared/docs/bad-inputs.md case ids in the test names): every one is
// rejected with a message naming object, index and reason, or skipped with a warning; nothing is
// opened outside the asset folder.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "tandem/Gltf.h"
#include "tandem/Log.h"
#include "unit/GltfTestUtil.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::Bytes;
using test::freshDir;
using test::triangleDoc;
using test::writeBytes;
using test::pngBytes;
using test::writeText;

using Outcome = test::LoadOutcome;

Outcome loadPath(const std::string& path, GltfOptions opt = {}) { return test::loadRecording(path, std::move(opt)); }

Outcome loadDoc(const std::string& name, const json& doc, GltfOptions opt = {}) {
  auto dir = freshDir(name);
  return loadPath(writeText(dir / (name + ".gltf"), doc.dump()), opt);
}

// Every file the loader opened lies inside `dir`.
void expectConfined(const Outcome& o, const fs::path& dir) {
  const std::string root = fs::canonical(dir).string() + "/";
  for (const auto& f : o.opened) EXPECT_EQ(f.compare(0, root.size(), root), 0) << "opened outside: " << f;
}

#define EXPECT_REJECT(outcome, text)                                                          \
  do {                                                                                        \
    EXPECT_FALSE((outcome).ok);                                                               \
    EXPECT_NE((outcome).error.find(text), std::string::npos) << "message: " << (outcome).error; \
  } while (0)

// A triangle whose buffer is the external file `uri`, with `bin` written as <dir>/tri.bin.
json externalTriangle(const std::string& uri, std::vector<std::uint8_t>* bin) {
  Bytes b;
  json d = triangleDoc(&b);
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", uri}};
  *bin = b.data;
  return d;
}

TEST(GltfHardening, ExternalBufferInsideTheFolderLoads) {
  std::vector<std::uint8_t> bin;
  json d = externalTriangle("sub%20dir/a%60b%24(c)~.bin", &bin);  // U7, U10: literal characters, %20
  auto dir = freshDir("external");
  fs::create_directories(dir / "sub dir");
  writeBytes(dir / "sub dir" / "a`b$(c)~.bin", bin);
  auto o = loadPath(writeText(dir / "m.gltf", d.dump()));
  EXPECT_TRUE(o.ok) << o.error;
  EXPECT_EQ(o.opened.size(), 2u);
  expectConfined(o, dir);
}

TEST(GltfHardening, U1_DotDotTraversalRejected) {
  std::vector<std::uint8_t> bin;
  auto base = freshDir("traversal");
  fs::create_directories(base / "asset");
  json d = externalTriangle("../outside.bin", &bin);
  writeBytes(base / "outside.bin", bin);
  auto o = loadPath(writeText(base / "asset" / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "'..' leaves the asset folder");
  expectConfined(o, base / "asset");
  // U2: percent-encoded, and hidden behind a subfolder that exists.
  fs::create_directories(base / "asset" / "sub");
  d["buffers"][0]["uri"] = "sub/%2e%2e/%2E%2E/outside.bin";
  o = loadPath(writeText(base / "asset" / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "'..' leaves the asset folder");
  expectConfined(o, base / "asset");
}

TEST(GltfHardening, U3_U8_AbsoluteFileAndNetworkUrisRejected) {
  std::vector<std::uint8_t> bin;
  auto base = freshDir("absolute");
  writeBytes(base / "tri.bin", bin);
  const std::string abs = fs::canonical(base).string() + "/tri.bin";
  for (const std::string& uri : {abs, "file://" + abs, std::string("http://127.0.0.1:9/x.bin"),
                                 std::string("https://example.com/x.bin"), std::string("data:text/plain;base64,AAAA")}) {
    json d = externalTriangle(uri, &bin);
    writeBytes(base / "tri.bin", bin);
    auto o = loadPath(writeText(base / "m.gltf", d.dump()));
    EXPECT_FALSE(o.ok) << uri;
    // tinygltf itself refuses data: URIs of other media types ("Failed to decode").
    const bool named = o.error.find("absolute path") != std::string::npos ||
                       o.error.find("URI scheme not allowed") != std::string::npos ||
                       o.error.find("Failed to decode") != std::string::npos;
    EXPECT_TRUE(named) << uri << " → " << o.error;
    EXPECT_EQ(o.opened.size(), 1u) << uri;  // only the main file
  }
}

TEST(GltfHardening, U4_CurrentDirectoryFallbackNotUsed) {
  std::vector<std::uint8_t> bin;
  auto base = freshDir("cwd");
  fs::create_directories(base / "cwd");
  fs::create_directories(base / "asset");
  json d = externalTriangle("only-in-cwd.bin", &bin);
  writeBytes(base / "cwd" / "only-in-cwd.bin", bin);
  const std::string gltf = writeText(base / "asset" / "m.gltf", d.dump());
  const fs::path old = fs::current_path();
  fs::current_path(base / "cwd");
  auto o = loadPath(gltf);
  fs::current_path(old);
  EXPECT_REJECT(o, "File not found");
  expectConfined(o, base / "asset");
}

TEST(GltfHardening, U5_SymlinkOutRejected) {
  std::vector<std::uint8_t> bin;
  auto base = freshDir("symlink");
  fs::create_directories(base / "asset");
  json d = externalTriangle("link.bin", &bin);
  writeBytes(base / "secret.bin", bin);
  fs::create_symlink(base / "secret.bin", base / "asset" / "link.bin");
  auto o = loadPath(writeText(base / "asset" / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "outside the asset folder");
  expectConfined(o, base / "asset");
  // A symlink that stays inside is fine.
  writeBytes(base / "asset" / "real.bin", bin);
  fs::remove(base / "asset" / "link.bin");
  fs::create_symlink("real.bin", base / "asset" / "link.bin");
  o = loadPath(writeText(base / "asset" / "m.gltf", d.dump()));
  EXPECT_TRUE(o.ok) << o.error;
}

TEST(GltfHardening, U6_FifoAndDirectoryRejected) {
  std::vector<std::uint8_t> bin;
  auto dir = freshDir("fifo");
  ASSERT_EQ(::mkfifo((dir / "pipe.bin").c_str(), 0600), 0);
  json d = externalTriangle("pipe.bin", &bin);
  auto o = loadPath(writeText(dir / "m.gltf", d.dump()));  // would block forever if opened
  EXPECT_REJECT(o, "not a regular file");
  fs::create_directories(dir / "folder.bin");
  d["buffers"][0]["uri"] = "folder.bin";
  o = loadPath(writeText(dir / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "not a regular file");
}

TEST(GltfHardening, U12_MissingOrShortBufferRejected) {
  std::vector<std::uint8_t> bin;
  auto dir = freshDir("shortbuf");
  json d = externalTriangle("tri.bin", &bin);
  auto o = loadPath(writeText(dir / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "File not found");
  bin.resize(10);
  writeBytes(dir / "tri.bin", bin);
  o = loadPath(writeText(dir / "m.gltf", d.dump()));
  EXPECT_REJECT(o, "size mismatch");
}

TEST(GltfHardening, J1_J2_EmptyAndBrokenJson) {
  auto dir = freshDir("json");
  EXPECT_REJECT(loadPath(writeText(dir / "empty.gltf", "")), "empty file");
  EXPECT_REJECT(loadPath(writeText(dir / "trunc.gltf", "{\"asset\": {\"version\": ")), "parse error");
  EXPECT_REJECT(loadPath(writeText(dir / "array.gltf", "[1, 2]")), "root is not an object");
  EXPECT_REJECT(loadPath(dir / "does-not-exist.gltf"), "cannot open");
}

TEST(GltfHardening, J3_DeepNestingRejectedBeforeParsing) {
  json d = triangleDoc();
  std::string text = d.dump();
  text.pop_back();
  text += ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  auto dir = freshDir("deep");
  EXPECT_REJECT(loadPath(writeText(dir / "deep.gltf", text)), "maxJsonDepth = 64");
}

TEST(GltfHardening, J4_L1_FileSizeCap) {
  GltfOptions opt;
  opt.limits.maxFileBytes = 100;
  EXPECT_REJECT(loadDoc("sizecap", triangleDoc(), opt), "maxFileBytes = 100");
}

TEST(GltfHardening, J5_HugeOrNonIntegerIndices) {
  json d = triangleDoc();
  d["meshes"][0]["primitives"][0]["indices"] = 4294967297.0;  // would wrap to 1 in tinygltf
  EXPECT_REJECT(loadDoc("hugeindex", d), "/meshes/0/primitives/0/indices");
  d = triangleDoc();
  d["accessors"][0]["bufferView"] = 0.5;
  EXPECT_REJECT(loadDoc("floatindex", d), "/accessors/0/bufferView");
  d = triangleDoc();
  d["nodes"][0]["mesh"] = "0";
  EXPECT_REJECT(loadDoc("stringindex", d), "expected an integer");
  auto dir = freshDir("bignum");
  EXPECT_REJECT(loadPath(writeText(dir / "m.gltf", R"({"asset":{"version":"2.0"},"nodes":[{"mesh":1e400}]})")),
                "parse error");
}

TEST(GltfHardening, J6_J7_VersionAndRequiredExtensions) {
  json d = triangleDoc();
  d["asset"]["minVersion"] = "2.1";
  EXPECT_REJECT(loadDoc("minversion", d), "asset.minVersion 2.1");
  d = triangleDoc();
  d["asset"]["version"] = "3.0";
  EXPECT_REJECT(loadDoc("version", d), "asset.version '3.0'");
  d = triangleDoc();
  d["extensionsUsed"] = {"EXT_unknown_a", "KHR_texture_transform", "EXT_unknown_b"};
  d["extensionsRequired"] = {"EXT_unknown_a", "KHR_texture_transform", "EXT_unknown_b"};
  EXPECT_REJECT(loadDoc("required", d), "unsupported extensions: EXT_unknown_a, EXT_unknown_b");
  d = triangleDoc();
  d["extensionsUsed"] = {"EXT_unknown_a"};  // J8: optional unknown extensions are ignored
  d["nodes"][0]["extensions"] = {{"EXT_unknown_a", {{"x", 1}}}};
  d["unknownProperty"] = {{"y", 2}};
  EXPECT_TRUE(loadDoc("optional", d).ok);
}

// Files that need an extension Tandem lacks are refused naming it, whatever their buffers hold: a Draco
// file's accessors have no data of their own, which tinygltf refused first as "invalid bufferView".
TEST(GltfHardening, J7_RequiredCompressionIsRefusedByItsName) {
  json d = triangleDoc();
  d["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  d["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  d["accessors"][0].erase("bufferView");
  d["accessors"][1].erase("bufferView");
  d["meshes"][0]["primitives"][0]["extensions"] = {
      {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
  Outcome draco = loadDoc("draco", d);
  EXPECT_REJECT(draco, "extensionsRequired names unsupported extensions: KHR_draco_mesh_compression");
  EXPECT_EQ(draco.error.find("invalid bufferView"), std::string::npos) << draco.error;

  d = triangleDoc();
  d["extensionsUsed"] = {"EXT_meshopt_compression"};
  d["extensionsRequired"] = {"EXT_meshopt_compression"};
  d["bufferViews"][0]["extensions"] = {{"EXT_meshopt_compression",
                                        {{"buffer", 0}, {"byteLength", 20}, {"byteStride", 12}, {"count", 3},
                                         {"mode", "ATTRIBUTES"}}}};
  EXPECT_REJECT(loadDoc("meshopt-required", d), "unsupported extensions: EXT_meshopt_compression");
  // A hostile list: eight names, then how many more.
  d = triangleDoc();
  d["extensionsRequired"] = json::array();
  for (int k = 0; k < 20; ++k) d["extensionsRequired"].push_back("EXT_unknown_" + std::to_string(k));
  Outcome many = loadDoc("many-required", d);
  EXPECT_REJECT(many, "EXT_unknown_7 and 12 more");
  EXPECT_EQ(many.error.find("EXT_unknown_8"), std::string::npos) << many.error;
}

// A file that only uses EXT_meshopt_compression carries its data uncompressed too (the extension's
// fallback buffer), and loads from that. The "compressed" buffer here is filler a decoder would refuse:
// reading it instead of the fallback would put the triangle somewhere else or fail.
TEST(GltfHardening, J8_MeshoptUsedButNotRequiredLoadsFromTheFallback) {
  Bytes fallback;
  json d = triangleDoc(&fallback);
  const std::vector<std::uint8_t> filler(64, 0xA5);
  d["extensionsUsed"] = {"EXT_meshopt_compression"};
  d["buffers"].push_back({{"byteLength", filler.size()},
                          {"uri", "data:application/octet-stream;base64," + test::base64(filler)}});
  d["bufferViews"][0]["extensions"] = {{"EXT_meshopt_compression",
                                        {{"buffer", 1}, {"byteOffset", 0}, {"byteLength", 40}, {"byteStride", 12},
                                         {"count", 3}, {"mode", "ATTRIBUTES"}, {"filter", "NONE"}}}};
  d["bufferViews"][1]["extensions"] = {{"EXT_meshopt_compression",
                                        {{"buffer", 1}, {"byteOffset", 40}, {"byteLength", 24}, {"byteStride", 2},
                                         {"count", 3}, {"mode", "TRIANGLES"}}}};
  auto dir = freshDir("meshopt-fallback");
  const std::string path = writeText(dir / "m.gltf", d.dump());
  Outcome o = loadPath(path);
  ASSERT_TRUE(o.ok) << o.error;
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  auto scene = loadGltf(path);
  setLogSink(old);
  ASSERT_TRUE(scene.ok());
  ASSERT_EQ(scene->meshes.size(), 1u);
  const Mesh& mesh = scene->meshes[0];
  ASSERT_EQ(mesh.indices.size(), 3u);
  const glm::vec3 corners[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 p = mesh.positions[mesh.indices[std::size_t(i)]];
    EXPECT_EQ(p, corners[i]) << "corner " << i;
  }
}

TEST(GltfHardening, B2_B3_B5_RangesPastViewsAndBuffers) {
  json d = triangleDoc();
  d["bufferViews"][1]["byteLength"] = 4000;
  EXPECT_REJECT(loadDoc("viewpast", d), "bufferViews[1]: byteOffset 36 + byteLength 4000 runs past buffers[0] (length 42)");
  d = triangleDoc();
  d["accessors"][0]["count"] = 2147483647;
  EXPECT_REJECT(loadDoc("hugecount", d), "accessors[0]: byteOffset 0 + 2147483647×12 bytes runs past bufferViews[0] (length 36)");
  d = triangleDoc();
  d["accessors"][0]["count"] = 0;  // B6
  EXPECT_REJECT(loadDoc("zerocount", d), "accessors[0]: count 0");
  d = triangleDoc();
  d["accessors"][0].erase("bufferView");
  d["accessors"][0]["count"] = 2000000000;  // zeros, nothing backs it: capped before allocating
  EXPECT_REJECT(loadDoc("viewless", d), "without a bufferView exceeds the cap maxFileBytes");
  d = triangleDoc();
  d["meshes"][0]["primitives"][0]["indices"] = 7;  // B1
  EXPECT_REJECT(loadDoc("badref", d), "indices accessor");  // tinygltf's own check words this one
}

TEST(GltfHardening, B7_B8_StrideAndAlignment) {
  json d = triangleDoc();
  d["bufferViews"][0]["byteStride"] = 6;
  EXPECT_REJECT(loadDoc("stride6", d), "byteStride");
  d = triangleDoc();
  d["bufferViews"][0]["byteStride"] = 8;
  EXPECT_REJECT(loadDoc("stride8", d), "smaller than the element size 12");
  d = triangleDoc();
  d["accessors"][0]["byteOffset"] = 2;
  EXPECT_REJECT(loadDoc("misaligned", d), "not aligned");
}

TEST(GltfHardening, B10_SparseIndicesOutOfRange) {
  Bytes b;
  json d = triangleDoc(&b);
  const std::size_t si = b.add(std::vector<std::uint16_t>{1, 7});
  const std::size_t sv = b.add(std::vector<float>{0, 0, 1, 0, 0, 2});
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", si}, {"byteLength", 4}});
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", sv}, {"byteLength", 24}});
  d["accessors"][0]["sparse"] = {{"count", 2},
                                 {"indices", {{"bufferView", 2}, {"componentType", 5123}}},
                                 {"values", {{"bufferView", 3}}}};
  EXPECT_REJECT(loadDoc("sparsebad", d), "accessors[0]: sparse.indices[1] = 7 is not below count 3");
}

TEST(GltfHardening, SparseAccessorApplied) {
  Bytes b;
  json d = triangleDoc(&b);
  const std::size_t si = b.add(std::vector<std::uint8_t>{2});
  const std::size_t sv = b.add(std::vector<float>{0, 5, 0});
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", si}, {"byteLength", 1}});
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", sv}, {"byteLength", 12}});
  d["accessors"][0]["sparse"] = {{"count", 1},
                                 {"indices", {{"bufferView", 2}, {"componentType", 5121}}},
                                 {"values", {{"bufferView", 3}}}};
  auto dir = freshDir("sparseok");
  auto r = loadGltf(writeText(dir / "m.gltf", d.dump()));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FLOAT_EQ(r->meshes[0].positions[2].y, 5.0f);
}

TEST(GltfHardening, B11_NonFinitePositions) {
  Bytes b;
  json d = triangleDoc(&b);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Bytes c;
  c.add(std::vector<float>{0, 0, 0, nan, 0, 0, 0, 1, 0});
  c.add(std::vector<std::uint16_t>{0, 1, 2});
  d["buffers"][0] = {{"byteLength", c.data.size()}, {"uri", c.dataUri()}};
  EXPECT_REJECT(loadDoc("nanpos", d), "meshes[0].primitives[0]: POSITION 1 is NaN or infinite");
}

TEST(GltfHardening, M1_M3_M4_M5_IndexProblems) {
  Bytes b;
  b.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  b.add(std::vector<std::uint16_t>{0, 1, 3});
  json d = triangleDoc();
  d["buffers"][0] = {{"byteLength", b.data.size()}, {"uri", b.dataUri()}};
  EXPECT_REJECT(loadDoc("indexrange", d), "meshes[0].primitives[0]: index 2 = 3 is not below the vertex count 3");
  Bytes r;
  r.add(std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  r.add(std::vector<std::uint16_t>{0, 1, 0xFFFF});
  d["buffers"][0] = {{"byteLength", r.data.size()}, {"uri", r.dataUri()}};
  EXPECT_REJECT(loadDoc("restart", d), "primitive-restart value 65535");
  d = triangleDoc();
  d["accessors"][1]["count"] = 2;
  EXPECT_REJECT(loadDoc("notthree", d), "2 indices for a triangle list");
  d = triangleDoc();
  d["meshes"][0]["primitives"][0]["attributes"] = {{"NORMAL", 0}};
  auto o = loadDoc("noposition", d);
  EXPECT_TRUE(o.ok) << o.error;
  ASSERT_FALSE(o.warnings.empty());
  EXPECT_NE(o.warnings[0].find("no POSITION attribute; primitive skipped"), std::string::npos);
  d = triangleDoc();
  d["meshes"][0]["primitives"][0]["mode"] = 9;
  EXPECT_REJECT(loadDoc("badmode", d), "mode 9");
}

TEST(GltfHardening, S1_S2_NodeGraph) {
  json d = triangleDoc();
  d["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {2}}}, {{"children", {1}}}};
  EXPECT_REJECT(loadDoc("cycle", d), "nodes[2]: child 1 already has parent 0");
  d["nodes"] = {{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}};
  EXPECT_REJECT(loadDoc("cycle2", d), "part of a cycle");
  d["nodes"] = {{{"mesh", 0}, {"children", {0}}}};
  EXPECT_REJECT(loadDoc("selfchild", d), "nodes[0]: is its own child");
  d["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"mesh", 0}}};
  d["scenes"][0]["nodes"] = {0, 1};
  EXPECT_REJECT(loadDoc("notroot", d), "scenes[0]: node 1 is not a root");
}

TEST(GltfHardening, S4_HundredThousandDeepChain) {
  json d = triangleDoc();
  const int n = 100000;
  json nodes = json::array();
  for (int i = 0; i < n - 1; ++i) nodes.push_back({{"children", {i + 1}}, {"translation", {0.001, 0, 0}}});
  nodes.push_back({{"mesh", 0}});
  d["nodes"] = nodes;
  auto dir = freshDir("deepchain");
  auto r = loadGltf(writeText(dir / "m.gltf", d.dump()));
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->instances.size(), 1u);
  EXPECT_NEAR(r->instances[0].worldFromObject[3].x, 0.001f * (n - 1), 0.5f);
  GltfOptions o;
  o.limits.maxNodes = 1000;
  EXPECT_REJECT(loadPath(dir / "m.gltf", o), "exceed the cap maxNodes = 1000");
}

TEST(GltfHardening, S7_SingularTransformSkipped) {
  json d = triangleDoc();
  d["nodes"][0]["scale"] = {0, 1, 1};
  auto o = loadDoc("zeroscale", d);
  EXPECT_TRUE(o.ok) << o.error;
  ASSERT_FALSE(o.warnings.empty());
  EXPECT_NE(o.warnings[0].find("singular"), std::string::npos);
  d = triangleDoc();
  d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  o = loadDoc("singularmatrix", d);
  EXPECT_TRUE(o.ok) << o.error;
  ASSERT_FALSE(o.warnings.empty());
  EXPECT_NE(o.warnings[0].find("singular"), std::string::npos);
}

TEST(GltfHardening, L1_TriangleCap) {
  GltfOptions opt;
  opt.limits.maxTriangles = 0;
  EXPECT_REJECT(loadDoc("tricap", triangleDoc(), opt), "cap maxTriangles = 0");
}

TEST(GltfHardening, G1_G2_GlbContainer) {
  auto dir = freshDir("glb");
  auto glb = [](const std::string& jsonText, const std::vector<std::uint8_t>& bin, std::uint32_t version = 2) {
    std::string js = jsonText;
    while (js.size() % 4) js += ' ';
    std::vector<std::uint8_t> out{'g', 'l', 'T', 'F'};
    auto u32 = [&](std::uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
    };
    const std::uint32_t total = std::uint32_t(12 + 8 + js.size() + (bin.empty() ? 0 : 8 + bin.size()));
    u32(version);
    u32(total);
    u32(std::uint32_t(js.size()));
    u32(0x4E4F534A);
    out.insert(out.end(), js.begin(), js.end());
    if (!bin.empty()) {
      u32(std::uint32_t(bin.size()));
      u32(0x004E4942);
      out.insert(out.end(), bin.begin(), bin.end());
    }
    return out;
  };
  Bytes b;
  json d = triangleDoc(&b);
  d["buffers"][0] = {{"byteLength", b.data.size()}};
  while (b.data.size() % 4) b.data.push_back(0);  // chunks are padded to 4 bytes
  auto good = glb(d.dump(), b.data);
  auto o = loadPath(writeBytes(dir / "good.glb", good));
  EXPECT_TRUE(o.ok) << o.error;
  EXPECT_REJECT(loadPath(writeBytes(dir / "v1.glb", glb(d.dump(), b.data, 1))), "container version 1");
  auto lie = good;
  lie[8] = std::uint8_t(lie[8] + 4);
  EXPECT_REJECT(loadPath(writeBytes(dir / "lie.glb", lie)), "differs from the file size");
  auto trunc = good;
  trunc.resize(trunc.size() - 8);
  trunc[8] = std::uint8_t(trunc.size());
  trunc[9] = std::uint8_t(trunc.size() >> 8);
  EXPECT_REJECT(loadPath(writeBytes(dir / "trunc.glb", trunc)), "runs past the file");
  EXPECT_REJECT(loadPath(writeBytes(dir / "tiny.glb", {'g', 'l', 'T', 'F', 2, 0, 0, 0})), "GLB");
  d["buffers"][0]["byteLength"] = 0;  // G2: tinygltf would throw std::out_of_range
  EXPECT_FALSE(loadPath(writeBytes(dir / "zero.glb", glb(d.dump(), b.data))).ok);
}

TEST(GltfHardening, I2_I3_I4_ImagesSkippedWithFallback) {
  auto dir = freshDir("images");
  Bytes b;
  json d = triangleDoc(&b);
  writeBytes(dir / "ok.png", pngBytes(2, 3));
  writeText(dir / "fake.png", "GIF89a not a png at all");
  auto huge = pngBytes(1, 1);
  // IHDR width/height at bytes 16..23 (big-endian): claim 8192 × 8192 without the pixels.
  for (int k : {16, 20}) {
    huge[std::size_t(k)] = 0;
    huge[std::size_t(k + 1)] = 0;
    huge[std::size_t(k + 2)] = 0x20;
    huge[std::size_t(k + 3)] = 0;
  }
  writeBytes(dir / "huge.png", huge);
  auto trunc = pngBytes(16, 16);
  trunc.resize(trunc.size() / 2);
  writeBytes(dir / "trunc.png", trunc);
  d["images"] = {{{"uri", "ok.png"}}, {{"uri", "fake.png"}}, {{"uri", "huge.png"}}, {{"uri", "trunc.png"}}};
  d["textures"] = {{{"source", 0}}, {{"source", 1}}, {{"source", 2}}, {{"source", 3}}};
  d["materials"] = json::array();
  d["meshes"][0]["primitives"] = json::array();
  for (int i = 0; i < 4; ++i) {
    d["materials"].push_back({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
    d["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", i}});
  }
  auto path = writeText(dir / "m.gltf", d.dump());
  std::vector<std::string> warnings;
  GltfOptions opt;
  opt.onWarning = [&](const std::string& w) { warnings.push_back(w); };
  LogSink old = setLogSink([](LogLevel, std::string_view) {});
  auto r = loadGltf(path, opt);
  setLogSink(old);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const Scene& s = *r;
  ASSERT_EQ(s.materials.size(), 4u);
  const Texture& t0 = s.textures[std::size_t(s.materials[0].kdTexture)];
  EXPECT_EQ(t0.width, 2);
  EXPECT_EQ(t0.height, 3);
  EXPECT_TRUE(t0.srgb);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(s.textures[std::size_t(s.materials[std::size_t(i)].kdTexture)].name, "fallback");
  std::string all;
  for (auto& w : warnings) all += w + "\n";
  EXPECT_NE(all.find("not PNG or JPEG"), std::string::npos) << all;
  EXPECT_NE(all.find("8192×8192 exceeds the cap maxImagePixels"), std::string::npos) << all;
  EXPECT_NE(all.find("images[3]"), std::string::npos) << all;
}

TEST(GltfHardening, ImageInBufferViewPastItsBufferRejected) {
  Bytes b;
  json d = triangleDoc(&b);
  d["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 40}, {"byteLength", 100000}});
  d["images"] = {{{"bufferView", 2}, {"mimeType", "image/png"}}};
  EXPECT_REJECT(loadDoc("imageview", d), "bufferViews[2]: byteOffset 40 + byteLength 100000 runs past buffers[0]");
}

}  // namespace
}  // namespace tandem
