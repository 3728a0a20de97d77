// glTF in the JSON scene format: glTF meshes and placements (transform, material overrides, lights,
// index remapping). Uses a one-triangle glTF written to the test output folder.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "support/TestSupport.h"
#include "tandem/Gltf.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

/// tri.gltf + tri.bin: mesh "Tri" (one triangle, material "Paint") on a node translated by (0, 0, 1),
/// and a point light on a node at (0, 2, 0).
std::string writeTriangleGltf() {
  // One folder per test: ctest runs the tests of this file as parallel processes, and two writing the same
  // files made one read a half-written glTF (a flaky PlacementErrors).
  const fs::path dir = fs::path(test::outputDir()) /
                       ("scene-gltf-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::create_directories(dir);
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint16_t indices[4] = {0, 1, 2, 0};  // padded to 4 bytes
  std::ofstream bin(dir / "tri.bin", std::ios::binary);
  bin.write(reinterpret_cast<const char*>(positions), sizeof positions);
  bin.write(reinterpret_cast<const char*>(indices), sizeof indices);
  bin.close();
  std::ofstream(dir / "tri.gltf") << R"({
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1], "intensity": 5}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0, "translation": [0, 0, 1]},
              {"translation": [0, 2, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "meshes": [{"name": "Tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"name": "Paint", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}],
    "buffers": [{"uri": "tri.bin", "byteLength": 44}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
  })";
  return dir.string();
}

Result<Scene> parseIn(const std::string& dir, const std::string& text) { return parseSceneJson(text, "g.json", dir); }

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

void expectNear(glm::vec3 a, glm::vec3 b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST(SceneFileGltf, TheFixtureLoads) {
  const std::string dir = writeTriangleGltf();
  Result<Scene> g = loadGltf(dir + "/tri.gltf");
  ASSERT_TRUE(g) << g.error().message;
  ASSERT_EQ(g->meshes.size(), 1u);
  ASSERT_EQ(g->instances.size(), 1u);
}

TEST(SceneFileGltf, WholeFileAsOneMeshKeepsNodeTransforms) {
  const std::string dir = writeTriangleGltf();
  Result<Scene> r = parseIn(dir, R"({"meshes": {"tri": {"gltf": "tri.gltf"}}, "materials": {"m": {}},
                                     "instances": [{"mesh": "tri", "material": "m"}]})");
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r->meshes.size(), 1u);
  const Mesh& m = r->meshes[0];
  EXPECT_EQ(m.name, "tri");
  ASSERT_EQ(m.triangleCount(), 1u);
  expectNear(m.positions[m.indices[0]], {0, 0, 1});  // the node's translation is baked in
  EXPECT_TRUE(r->lights.empty());                   // a glTF mesh brings geometry only
}

TEST(SceneFileGltf, OneMeshByNameOrIndexInObjectSpace) {
  const std::string dir = writeTriangleGltf();
  Result<Scene> g = loadGltf(dir + "/tri.gltf");
  ASSERT_TRUE(g) << g.error().message;
  const std::string name = g->meshes[0].name;  // however the loader names primitives
  for (const std::string& sel : {"\"" + name + "\"", std::string("0")}) {
    Result<Scene> r = parseIn(dir, R"({"meshes": {"tri": {"gltf": "tri.gltf", "mesh": )" + sel + "}}}");
    ASSERT_TRUE(r) << r.error().message;
    const Mesh& m = r->meshes[0];
    ASSERT_EQ(m.triangleCount(), 1u);
    expectNear(m.positions[m.indices[0]], {0, 0, 0});
  }
  Result<Scene> bad = parseIn(dir, R"({"meshes": {"tri": {"gltf": "tri.gltf", "mesh": "Trii"}}})");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("g.json: /meshes/tri/mesh: no mesh named 'Trii' in the glTF file (known: " + name),
            std::string::npos)
      << bad.error().message;
  Result<Scene> out = parseIn(dir, R"({"meshes": {"tri": {"gltf": "tri.gltf", "mesh": 3}}})");
  ASSERT_FALSE(out);
  EXPECT_NE(out.error().message.find("g.json: /meshes/tri/mesh: must be in [0, 0], got 3"), std::string::npos)
      << out.error().message;
}

TEST(SceneFileGltf, PlacementAppendsWithRemappedIndicesAndTransform) {
  const std::string dir = writeTriangleGltf();
  Result<Scene> r = parseIn(dir, R"({
    "meshes": {"ball": {"primitive": "sphere", "segments": 8, "rings": 4}},
    "materials": {"red": {"kd": [1, 0, 0]}},
    "instances": [{"mesh": "ball", "material": "red"},
                  {"name": "prop", "gltf": "tri.gltf", "dynamic": true,
                   "transform": {"translate": [10, 0, 0], "scale": 2}}]})");
  ASSERT_TRUE(r) << r.error().message;
  const Scene& s = *r;
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[1].name.rfind("prop/", 0), 0u) << s.materials[1].name;
  ASSERT_EQ(s.instances.size(), 2u);
  const Instance& i = s.instances[1];
  EXPECT_EQ(i.mesh, 1u);      // after the file's own meshes
  EXPECT_EQ(i.material, 1u);  // after the file's own materials
  EXPECT_TRUE(i.dynamic);
  // Placement · node: (0,0,0) → node (0,0,1) → scale 2, translate → (10,0,2).
  expectNear(apply(i.worldFromObject, {0, 0, 0}), {10, 0, 2});
  // The glTF's point light moves with the placement: node (0,2,0) → (10,4,0).
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::Point);
  expectNear(s.lights[0].posW, {10, 4, 0});
}

TEST(SceneFileGltf, PlacementMaterialOverridesAndDroppedLights) {
  const std::string dir = writeTriangleGltf();
  for (const std::string key : {"Paint", "*"}) {
    Result<Scene> r = parseIn(dir, R"({"materials": {"chrome": {"kr": 0.9}},
      "instances": [{"gltf": "tri.gltf", "lights": "drop", "materialOverrides": {")" + key + R"(": "chrome"}}]})");
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->materials.size(), 1u) << "an overridden glTF material is not copied";
    ASSERT_EQ(r->instances.size(), 1u);
    EXPECT_EQ(r->instances[0].material, 0u);
    EXPECT_TRUE(r->lights.empty());
    EXPECT_EQ(r->instances[0].name.rfind("tri/", 0), 0u) << "placements are named after the file by default";
  }
}

TEST(SceneFileGltf, PlacementErrors) {
  const std::string dir = writeTriangleGltf();
  auto expectError = [&](const std::string& text, const std::string& needle) {
    Result<Scene> r = parseIn(dir, text);
    ASSERT_FALSE(r) << text;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expectError(R"({"materials": {"chrome": {}}, "instances": [{"gltf": "tri.gltf", "materialOverrides": {"Pain": "chrome"}}]})",
              "g.json: /instances/0/materialOverrides/Pain: no material named 'Pain' in the glTF file (known: Paint)");
  expectError(R"({"materials": {"chrome": {}}, "instances": [{"gltf": "tri.gltf", "materialOverrides": {"Paint": "crome"}}]})",
              "g.json: /instances/0/materialOverrides/Paint: unknown material 'crome' (known: chrome)");
  expectError(R"({"instances": [{"gltf": "tri.gltf", "lights": "off"}]})",
              "g.json: /instances/0/lights: expected 'keep' or 'drop', got 'off'");
  expectError(R"({"instances": [{"gltf": "tri.gltf", "mesh": "Tri"}]})",
              "g.json: /instances/0/mesh: unknown key 'mesh' for a glTF placement");
  expectError(R"({"instances": [{"gltf": "missing.gltf"}]})", "g.json: /instances/0/gltf: cannot load glTF");
  expectError(R"({"meshes": {"m": {"gltf": "missing.gltf"}}})", "g.json: /meshes/m/gltf: cannot load glTF");
  expectError(R"({"meshes": {"m": {"gltf": ""}}})", "g.json: /meshes/m/gltf: must not be empty");
  // Nine point lights brought in by placements exceed the limit; the message points at the placement.
  std::string many;
  for (int i = 0; i <= kMaxLights; ++i) many += std::string(i ? "," : "") + R"({"name": "p)" + std::to_string(i) + R"(", "gltf": "tri.gltf"})";
  expectError(R"({"instances": [)" + many + "]}", "g.json: /instances/" + std::to_string(kMaxLights) + ": too many lights");
}

}  // namespace
}  // namespace tandem
