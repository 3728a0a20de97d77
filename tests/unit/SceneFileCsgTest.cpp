// Exact solids and CSG in the JSON scene format (docs/scene-format.md, docs/csg.md): every shape and
// operation, placements on nodes, the proxy the raster draws, and the errors (file, JSON path, reason); and
// the procedural textures of materials (docs/procedural.md).
#include <gtest/gtest.h>

#include <cmath>

#include "core/Solids.h"
#include "support/TestSupport.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

Result<Scene> parse(const std::string& text) { return parseSceneJson(text, "t.json", test::outputDir()); }

std::string withMesh(const std::string& mesh) {
  return R"({"meshes": {"x": )" + mesh + R"(}, "materials": {"m": {}}, "instances": [{"mesh": "x", "material": "m"}]})";
}

void expectError(const std::string& mesh, const std::string& path, const std::string& reason) {
  Result<Scene> r = parse(withMesh(mesh));
  ASSERT_FALSE(r) << "accepted: " << mesh;
  const std::string& m = r.error().message;
  EXPECT_NE(m.find(": " + path + ": "), std::string::npos) << "path '" << path << "' missing from: " << m;
  EXPECT_NE(m.find(reason), std::string::npos) << "reason '" << reason << "' missing from: " << m;
}

TEST(SceneFileCsg, ParsesEveryShapeAndOperation) {
  Result<Scene> r = parse(withMesh(R"({"csg": "union", "of": [
      {"csg": "intersection", "of": [
        {"primitive": "sphere", "radius": 1, "translate": [0, 0, -0.7]},
        {"primitive": "sphere", "radius": 1, "translate": [0, 0, 0.7]}]},
      {"csg": "difference", "translate": [3, 0, 0], "of": [
        {"primitive": "box", "size": 1},
        {"primitive": "sphere", "radius": 0.12, "translate": [0, 0.5, 0]}]},
      {"csg": "merge", "translate": [-3, 0, 0], "of": [
        {"primitive": "cylinder", "radius": 0.5, "height": 2, "rotate": {"axis": [1, 0, 0], "angle": 90}},
        {"primitive": "cone", "radius": 0.5, "topRadius": 0.1, "height": 1, "translate": [0, 1.5, 0]}]},
      {"csg": "intersection", "translate": [0, 5, 0], "of": [
        {"primitive": "torus", "radius": 1, "tube": 0.2, "scale": [1, 2, 1]},
        {"primitive": "plane", "translate": [0, 0.1, 0]}]}]})"));
  ASSERT_TRUE(r) << r.error().message;
  const Mesh& mesh = r->meshes[0];
  ASSERT_TRUE(mesh.exact.has_value());
  const solid::Solid& s = *mesh.exact;
  EXPECT_EQ(solid::validate(s), "");
  EXPECT_EQ(s.nodes.size(), 13u);
  EXPECT_EQ(s.nodes[s.root].op, solid::Op::Union);
  // The lens: along z through its middle, it spans the two spheres' overlap, [-0.3, 0.3].
  const solid::Hits lens = solid::intersect(s, solid::Ray{{0.0, 0.0, -10.0}, {0.0, 0.0, 1.0}});
  solid::Crossing c;
  ASSERT_TRUE(solid::firstHit(lens, 0.0, 1e30, c));
  EXPECT_NEAR(c.t, 9.7, 1e-6);  // the file's numbers are floats
  // The die was placed at x = 3: straight down into its dimple.
  ASSERT_TRUE(solid::firstHit(solid::intersect(s, solid::Ray{{3.0, 5.0, 0.0}, {0.0, -1.0, 0.0}}), 0.0, 1e30, c));
  EXPECT_NEAR(c.t, 5.0 - 0.38, 1e-6);
  // The raster's proxy: a box around the solid's bounds.
  const solid::Bounds b = solid::bounds(s);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(lo[a], b.lo[a]);
    EXPECT_GE(hi[a], b.hi[a]);
  }
}

TEST(SceneFileCsg, ExactPrimitivesKeepAProxyThatCoversThem) {
  // An exact sphere's tessellation lies outside the sphere everywhere (faces included), so the raster covers
  // every pixel the sphere does; the rays see the sphere.
  Result<Scene> r = parse(withMesh(R"({"primitive": "sphere", "radius": 2, "segments": 8, "rings": 4, "exact": true})"));
  ASSERT_TRUE(r) << r.error().message;
  const Mesh& mesh = r->meshes[0];
  ASSERT_TRUE(mesh.exact.has_value());
  EXPECT_EQ(mesh.exact->nodes[0].primitive.shape, solid::Shape::Sphere);
  EXPECT_EQ(mesh.exact->nodes[0].primitive.size.x, 2.0);
  for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
    const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                    c = mesh.positions[mesh.indices[3 * t + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (glm::length(n) < 1e-9f) continue;  // the poles' degenerate slivers
    EXPECT_GE(std::abs(glm::dot(glm::normalize(n), a)), 2.0f) << "triangle " << t << " cuts into the sphere";
  }
  // A plain sphere stays a mesh; an exact box's proxy is the box itself.
  ASSERT_FALSE(parse(withMesh(R"({"primitive": "sphere"})"))->meshes[0].exact.has_value());
  Result<Scene> box = parse(withMesh(R"({"primitive": "box", "size": [1, 2, 3], "exact": true})"));
  ASSERT_TRUE(box);
  EXPECT_EQ(box->meshes[0].exact->nodes[0].primitive.size, glm::dvec3(0.5, 1.0, 1.5));
  // The exact-only shapes at the top level.
  Result<Scene> torus = parse(withMesh(R"({"primitive": "torus", "radius": 1, "tube": 0.3})"));
  ASSERT_TRUE(torus) << torus.error().message;
  EXPECT_EQ(torus->meshes[0].exact->nodes[0].primitive.shape, solid::Shape::Torus);
}

TEST(SceneFileCsg, ErrorsNameThePathAndTheReason) {
  expectError(R"({"csg": "xor", "of": [{"primitive": "sphere"}]})", "/meshes/x/csg", "unknown operation 'xor'");
  expectError(R"({"csg": "union", "of": []})", "/meshes/x/of", "non-empty array");
  expectError(R"({"csg": "union"})", "/meshes/x", "missing required key 'of'");
  expectError(R"({"csg": "union", "of": [{"primitive": "blob"}]})", "/meshes/x/of/0/primitive", "unknown solid 'blob'");
  expectError(R"({"csg": "union", "of": [{"primitive": "torus", "radius": 1, "tube": 1}]})", "/meshes/x/of/0/tube",
              "less than the radius");
  expectError(R"({"csg": "union", "of": [{"primitive": "sphere", "radius": -1}]})", "/meshes/x/of/0/radius", "must be");
  expectError(R"({"csg": "union", "of": [{"primitive": "sphere", "colour": 1}]})", "/meshes/x/of/0/colour",
              "unknown key 'colour'");
  expectError(R"({"csg": "union", "of": [{"primitive": "plane"}]})", "/meshes/x", "unbounded");
  expectError(R"({"csg": "union", "of": [{"primitive": "sphere", "scale": [1, 0, 1]}]})", "/meshes/x/of/0/scale/1", "must be");
  expectError(R"({"csg": "union", "of": [{"csg": "union", "of": [{}]}]})", "/meshes/x/of/0/of/0", "expected 'csg'");
  expectError(R"({"primitive": "sphere", "csg": "union", "of": []})", "/meshes/x", "not several");
  // Depth: 33 nested unions.
  std::string deep = R"({"primitive": "sphere"})";
  for (int i = 0; i < solid::kMaxCsgDepth; ++i) deep = R"({"csg": "union", "of": [)" + deep + "]}";
  Result<Scene> r = parse(withMesh(deep));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("deeper than"), std::string::npos) << r.error().message;
}

std::string withMaterial(const std::string& material) {
  return R"({"meshes": {"x": {"primitive": "box"}}, "materials": {"m": )" + material +
         R"(}, "instances": [{"mesh": "x", "material": "m"}]})";
}

TEST(SceneFileTexture, ParsesEveryPatternAndItsKeys) {
  Result<Scene> r = parse(withMaterial(R"({"kd": [0.9, 0.8, 0.7], "texture": {"type": "marble", "space": "world",
      "scale": 2.5, "turbulence": 3, "octaves": 6, "color2": [0.1, 0.2, 0.3], "bump": 0.01}})"));
  ASSERT_TRUE(r) << r.error().message;
  const Material& m = r->materials[0];
  EXPECT_EQ(m.procedural, (ProceduralTexture{Pattern::Marble, true, 2.5f, 3.0f, 6, 0.01f}));
  EXPECT_EQ(m.kd2, glm::vec3(0.1f, 0.2f, 0.3f));
  // Defaults: object space, scale and turbulence 1, 4 octaves, no bump, kd2 = kd (a pattern that only bumps).
  const std::pair<const char*, Pattern> types[] = {{"noise", Pattern::Noise}, {"fbm", Pattern::Fbm},
                                                   {"turbulence", Pattern::Turbulence}, {"marble", Pattern::Marble},
                                                   {"wood", Pattern::Wood}, {"granite", Pattern::Granite}};
  for (const auto& [name, pattern] : types) {
    Result<Scene> t = parse(withMaterial(R"({"kd": 0.5, "texture": {"type": ")" + std::string(name) + R"("}})"));
    ASSERT_TRUE(t) << name << ": " << t.error().message;
    EXPECT_EQ(t->materials[0].procedural, (ProceduralTexture{pattern, false, 1.0f, 1.0f, 4, 0.0f})) << name;
    EXPECT_EQ(t->materials[0].kd2, glm::vec3(0.5f)) << name;
  }
  // No texture: none.
  EXPECT_EQ(parse(withMaterial("{}"))->materials[0].procedural.type, Pattern::None);
}

TEST(SceneFileTexture, ErrorsNameThePathAndTheReason) {
  auto expectMaterialError = [](const std::string& material, const std::string& path, const std::string& reason) {
    Result<Scene> r = parse(withMaterial(material));
    ASSERT_FALSE(r) << "accepted: " << material;
    const std::string& m = r.error().message;
    EXPECT_NE(m.find(": " + path + ": "), std::string::npos) << "path '" << path << "' missing from: " << m;
    EXPECT_NE(m.find(reason), std::string::npos) << "reason '" << reason << "' missing from: " << m;
  };
  expectMaterialError(R"({"texture": {"type": "paisley"}})", "/materials/m/texture/type", "unknown pattern 'paisley'");
  expectMaterialError(R"({"texture": {}})", "/materials/m/texture", "missing required key 'type'");
  expectMaterialError(R"({"texture": {"type": "wood", "space": "screen"}})", "/materials/m/texture/space",
                      "unknown space 'screen'");
  expectMaterialError(R"({"texture": {"type": "wood", "scale": 0}})", "/materials/m/texture/scale", "must be");
  expectMaterialError(R"({"texture": {"type": "wood", "octaves": 9}})", "/materials/m/texture/octaves", "");
  expectMaterialError(R"({"texture": {"type": "wood", "octaves": 2.5}})", "/materials/m/texture/octaves", "integer");
  expectMaterialError(R"({"texture": {"type": "wood", "bump": -1}})", "/materials/m/texture/bump", "must be");
  expectMaterialError(R"({"texture": {"type": "wood", "grain": 1}})", "/materials/m/texture/grain", "unknown key 'grain'");
  expectMaterialError(R"({"checker": {"color2": 0}, "texture": {"type": "wood"}})", "/materials/m/texture",
                      "a checker or a texture, not both");
}

TEST(SceneFileTexture, ValidateSceneRefusesBadTexturesMadeInCode) {
  Scene s = *parse(withMaterial(R"({"texture": {"type": "granite"}})"));
  ASSERT_TRUE(validateScene(s));
  for (auto bad : {+[](ProceduralTexture& t) { t.scale = 0.0f; }, +[](ProceduralTexture& t) { t.octaves = 0; },
                   +[](ProceduralTexture& t) { t.octaves = 9; }, +[](ProceduralTexture& t) { t.bump = -0.1f; },
                   +[](ProceduralTexture& t) { t.turbulence = std::nanf(""); },
                   +[](ProceduralTexture& t) { t.type = static_cast<Pattern>(42); }}) {
    Scene copy = s;
    bad(copy.materials[0].procedural);
    EXPECT_FALSE(validateScene(copy));
  }
}

}  // namespace
}  // namespace tandem
