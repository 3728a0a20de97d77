// The JSON scene format: every construct, the defaults, and the errors (file, JSON path, reason).
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/Embedded.h"
#include "support/TestSupport.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

Result<Scene> parse(const std::string& text) { return parseSceneJson(text, "t.json", test::outputDir()); }

/// A valid scene with one mesh, one material and one instance; `extra` adds top-level keys.
std::string minimal(const std::string& extra = "") {
  return R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}},
             "instances": [{"mesh": "s", "material": "m"}])" +
         (extra.empty() ? std::string() : ", " + extra) + "}";
}

/// Parses and expects an error containing the file name, the JSON path and the reason.
void expectError(const std::string& text, const std::string& path, const std::string& reason) {
  Result<Scene> r = parse(text);
  ASSERT_FALSE(r) << "accepted:\n" << text;
  const std::string& m = r.error().message;
  EXPECT_EQ(m.rfind("t.json: ", 0), 0u) << m;
  EXPECT_NE(m.find(": " + path + ": "), std::string::npos) << "path '" << path << "' missing from: " << m;
  EXPECT_NE(m.find(reason), std::string::npos) << "reason '" << reason << "' missing from: " << m;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

glm::vec3 apply(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

void expectNear(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

// ---- constructs ----

TEST(SceneFile, ParsesEveryConstruct) {
  Result<Scene> r = parse(R"({
    // Comments are allowed: scene files are written by hand.
    "name": "everything",
    "meshes": {
      "ball":  {"primitive": "sphere", "radius": 2, "segments": 8, "rings": 4},
      "crate": {"primitive": "box", "size": [1, 2, 3]},
      "cube":  {"primitive": "box", "size": 0.5},
      "floor": {"primitive": "plane", "size": [4, 6], "divisions": 3},
      "tile":  {"primitive": "plane", "size": 2}
    },
    "materials": {
      "all": {"ka": [0.1, 0.2, 0.3], "kd": 0.5, "ks": [0.7, 0.8, 0.9], "ns": 100, "kr": 0.25, "kt": 0.5,
              "ior": 1.33, "emission": [1, 0, 0], "shading": "toon", "toonRamp": [[-1, 0.1], [0.5, 0.9]],
              "checker": {"color2": [0, 0, 1], "frequency": 4}, "opacity": 0.5, "alphaMode": "blend",
              "alphaCutoff": 0.25, "doubleSided": true, "unlit": true},
      "flat": {"shading": "flat"}, "gouraud": {"shading": "gouraud"}, "phong": {"shading": "phong"},
      "plain-checker": {"checker": {"color2": 0.2}}
    },
    "lights": [
      {"type": "ambient", "name": "amb", "color": [0.1, 0.2, 0.3], "intensity": 2},
      {"type": "point", "name": "bulb", "position": [1, 2, 3], "color": 0.5, "intensity": 3, "range": 10,
       "attenuation": [1, 0.5, 0.25], "castShadows": false},
      {"type": "spot", "position": [0, 5, 0], "direction": [0, -2, 0], "innerCone": 10, "outerCone": 20, "range": 7},
      {"type": "directional", "direction": [0, 0, -3], "castShadows": true}
    ],
    "instances": [
      {"name": "a", "mesh": "ball", "material": "all", "dynamic": true,
       "transform": {"translate": [1, 2, 3], "rotate": [0, 90, 0], "scale": 2}},
      {"mesh": "crate", "material": "flat", "transform": {"rotate": {"axis": [0, 0, 2], "angle": 90}, "scale": [1, 2, 3]}},
      {"mesh": "floor", "material": "gouraud",
       "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 5,6,7,1]}},
      {"mesh": "tile", "material": "phong"}, {"mesh": "cube", "material": "plain-checker"}
    ],
    "camera": {"position": [0, 1, 10], "target": [0, 1, 0], "up": [0, 1, 0], "fov": 60, "near": 0.5,
               "far": 500, "orthographic": true, "height": 8},
    "background": [0.25, 0.5, 1],
    "render": {"width": 640, "height": 480, "preset": "hybrid-full", "maxDepth": 3}
  })");
  ASSERT_TRUE(r) << r.error().message;
  const Scene& s = *r;
  EXPECT_EQ(s.name, "everything");

  ASSERT_EQ(s.meshes.size(), 5u);
  EXPECT_EQ(s.meshes[0].name, "ball");
  EXPECT_EQ(s.meshes[0].triangleCount(), 8u * (2u * 4u - 2u));
  EXPECT_NEAR(glm::length(s.meshes[0].positions[5]), 2.0f, 1e-5f);
  EXPECT_EQ(s.meshes[1].triangleCount(), 12u);
  glm::vec3 hi(0.0f);
  for (const glm::vec3& p : s.meshes[1].positions) hi = glm::max(hi, p);
  expectNear(hi, {0.5f, 1.0f, 1.5f});
  for (const glm::vec3& q : s.meshes[2].positions) expectNear(glm::abs(q), glm::vec3(0.25f));  // size 0.5 = [0.5, 0.5, 0.5]
  EXPECT_EQ(s.meshes[3].triangleCount(), 18u);
  EXPECT_EQ(s.meshes[4].triangleCount(), 2u);

  ASSERT_EQ(s.materials.size(), 5u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.name, "all");
  expectNear(m.ka, {0.1f, 0.2f, 0.3f});
  expectNear(m.kd, glm::vec3(0.5f));
  expectNear(m.ks, {0.7f, 0.8f, 0.9f});
  EXPECT_FLOAT_EQ(m.ns, 100.0f);
  EXPECT_FLOAT_EQ(m.kr, 0.25f);
  EXPECT_FLOAT_EQ(m.kt, 0.5f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  expectNear(m.emission, {1, 0, 0});
  EXPECT_EQ(m.shading, ShadingModel::Toon);
  ASSERT_EQ(m.toonRamp.size(), 2u);
  EXPECT_FLOAT_EQ(m.toonRamp[1].threshold, 0.5f);
  EXPECT_FLOAT_EQ(m.toonRamp[1].level, 0.9f);
  expectNear(m.kd2, {0, 0, 1});
  EXPECT_FLOAT_EQ(m.checkerFrequency, 4.0f);
  EXPECT_FLOAT_EQ(m.opacity, 0.5f);
  EXPECT_EQ(m.alphaMode, AlphaMode::Blend);
  EXPECT_FLOAT_EQ(m.alphaCutoff, 0.25f);
  EXPECT_TRUE(m.doubleSided);
  EXPECT_TRUE(m.unlit);
  EXPECT_EQ(s.materials[1].shading, ShadingModel::Flat);
  EXPECT_EQ(s.materials[2].shading, ShadingModel::Gouraud);
  EXPECT_EQ(s.materials[3].shading, ShadingModel::Phong);
  EXPECT_FLOAT_EQ(s.materials[4].checkerFrequency, 1.0f);  // frequency defaults to unit squares
  expectNear(s.materials[4].kd2, glm::vec3(0.2f));

  ASSERT_EQ(s.lights.size(), 4u);
  EXPECT_EQ(s.lights[0].type, LightType::Ambient);
  EXPECT_EQ(s.lights[0].name, "amb");
  expectNear(s.ambientIntensity(), {0.2f, 0.4f, 0.6f});
  const Light& p = s.lights[1];
  EXPECT_EQ(p.type, LightType::Point);
  expectNear(p.posW, {1, 2, 3});
  expectNear(p.color, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(p.intensity, 3.0f);
  EXPECT_FLOAT_EQ(p.range, 10.0f);
  expectNear(p.attenuation, {1, 0.5f, 0.25f});
  EXPECT_FALSE(p.castShadows);
  const Light& spot = s.lights[2];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_EQ(spot.name, "light2");  // unnamed lights are numbered by position
  expectNear(spot.dirW, {0, -1, 0});  // normalized
  EXPECT_FLOAT_EQ(spot.innerConeDeg, 10.0f);
  EXPECT_FLOAT_EQ(spot.outerConeDeg, 20.0f);
  EXPECT_FLOAT_EQ(spot.range, 7.0f);
  EXPECT_EQ(s.lights[3].type, LightType::Directional);
  expectNear(s.lights[3].dirW, {0, 0, -1});
  EXPECT_EQ(s.directLights().size(), 3u);

  ASSERT_EQ(s.instances.size(), 5u);
  const Instance& a = s.instances[0];
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(a.mesh, 0u);
  EXPECT_EQ(a.material, 0u);
  EXPECT_TRUE(a.dynamic);
  // T·R·S: scale 2, then 90° about Y takes +X to -Z, then translate.
  expectNear(apply(a.worldFromObject, {1, 0, 0}), {1, 2, 1});
  const Instance& b = s.instances[1];
  EXPECT_EQ(b.name, "crate");  // unnamed instances take their mesh's name
  EXPECT_FALSE(b.dynamic);
  EXPECT_EQ(b.material, 1u);
  // Scale [1,2,3] then 90° about the (normalized) Z axis: +Y·2 goes to -X·2.
  expectNear(apply(b.worldFromObject, {0, 1, 0}), {-2, 0, 0});
  expectNear(apply(b.worldFromObject, {0, 0, 1}), {0, 0, 3});
  // Column-major: the translation is elements 12..14.
  expectNear(apply(s.instances[2].worldFromObject, {0, 0, 0}), {5, 6, 7});

  const Camera& c = s.camera;
  expectNear(c.posW, {0, 1, 10});
  expectNear(c.targetW, {0, 1, 0});
  EXPECT_FLOAT_EQ(c.yFovDeg, 60.0f);
  EXPECT_FLOAT_EQ(c.nearZ, 0.5f);
  EXPECT_FLOAT_EQ(c.farZ, 500.0f);
  EXPECT_TRUE(c.orthographic);
  EXPECT_FLOAT_EQ(c.orthoHeight, 8.0f);
  expectNear(s.background, {0.25f, 0.5f, 1.0f});
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.preset, "hybrid-full");
  EXPECT_EQ(s.render.maxDepth, 3);
}

TEST(SceneFile, EulerRotationAppliesXThenYThenZ) {
  Result<Scene> r = parse(R"({"meshes": {"s": {"primitive": "box"}}, "materials": {"m": {}},
    "instances": [{"mesh": "s", "material": "m", "transform": {"rotate": [90, 90, 0]}}]})");
  ASSERT_TRUE(r) << r.error().message;
  // X first: +Y → +Z; then Y: +Z → +X. (Y first would leave +Y, then X would give +Z.)
  expectNear(apply(r->instances[0].worldFromObject, {0, 1, 0}), {1, 0, 0});
}

TEST(SceneFile, DefaultsMatchTheSceneModel) {
  Result<Scene> r = parse(minimal());
  ASSERT_TRUE(r) << r.error().message;
  const Scene& s = *r;
  EXPECT_EQ(s.name, "t");  // the file name without extension
  EXPECT_EQ(s.meshes[0].triangleCount(), 64u * (2u * 32u - 2u));  // sphere: 64 x 32
  EXPECT_NEAR(glm::length(s.meshes[0].positions[3]), 1.0f, 1e-5f);
  const Material def;
  const Material& m = s.materials[0];
  expectNear(m.ka, def.ka);
  expectNear(m.kd, def.kd);
  expectNear(m.ks, def.ks);
  EXPECT_EQ(m.ns, def.ns);
  EXPECT_EQ(m.kr, 0.0f);
  EXPECT_EQ(m.kt, 0.0f);
  EXPECT_EQ(m.ior, 1.5f);
  EXPECT_EQ(m.shading, ShadingModel::Phong);
  EXPECT_EQ(m.checkerFrequency, 0.0f);
  EXPECT_EQ(m.toonRamp.size(), def.toonRamp.size());
  EXPECT_EQ(m.kdTexture, -1);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_EQ(s.instances[0].worldFromObject, glm::mat4(1.0f));
  EXPECT_FALSE(s.instances[0].dynamic);
  const Camera defCam;
  expectNear(s.camera.posW, defCam.posW);
  EXPECT_EQ(s.camera.yFovDeg, defCam.yFovDeg);
  EXPECT_TRUE(std::isinf(s.camera.farZ));
  EXPECT_FALSE(s.camera.orthographic);
  expectNear(s.background, glm::vec3(0.0f));
  EXPECT_EQ(s.render.width, 1280);
  EXPECT_EQ(s.render.height, 720);
  EXPECT_EQ(s.render.preset, "");
  EXPECT_EQ(s.render.maxDepth, -1);

  Result<Scene> d = parse(R"({"meshes": {"b": {"primitive": "box"}, "p": {"primitive": "plane"}},
    "lights": [{"type": "point", "position": [0, 1, 0]}, {"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0]}]})");
  ASSERT_TRUE(d) << d.error().message;
  EXPECT_EQ(d->meshes[1].triangleCount(), 2u);  // plane: 10 x 10, one division
  expectNear(d->meshes[1].positions.back(), {5, 0, 5});
  expectNear(d->meshes[0].positions[0] * 2.0f, glm::sign(d->meshes[0].positions[0]));  // unit box
  const Light defLight;
  const Light& pl = d->lights[0];
  expectNear(pl.color, defLight.color);
  EXPECT_EQ(pl.intensity, 1.0f);
  EXPECT_EQ(pl.range, 0.0f);
  expectNear(pl.attenuation, {1, 0, 0});
  EXPECT_TRUE(pl.castShadows);
  EXPECT_EQ(d->lights[1].innerConeDeg, defLight.innerConeDeg);
  EXPECT_EQ(d->lights[1].outerConeDeg, defLight.outerConeDeg);
}

TEST(SceneFile, FarInfiniteAndEmptyScene) {
  Result<Scene> r = parse(R"({"camera": {"far": "infinite", "near": 0.01}})");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_TRUE(std::isinf(r->camera.farZ));
  EXPECT_TRUE(r->instances.empty());
}

TEST(SceneFile, AmbientLightsDoNotCountTowardsTheLimit) {
  std::string lights;
  for (int i = 0; i < kMaxLights; ++i) lights += R"({"type": "point", "position": [0, 1, 0]},)";
  lights += R"({"type": "ambient"}, {"type": "ambient"})";
  Result<Scene> r = parse(minimal("\"lights\": [" + lights + "]"));
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->directLights().size(), std::size_t(kMaxLights));
}

// ---- errors: file, JSON path, reason ----

TEST(SceneFileErrors, UnknownReferenceListsTheKnownNames) {
  Result<Scene> r = parse(R"({"meshes": {"s": {"primitive": "sphere"}},
    "materials": {"floor": {}, "mirror": {}, "glass": {}, "matte": {}},
    "instances": [{"mesh": "s", "material": "floor"}, {"mesh": "s", "material": "mirror"},
                  {"mesh": "s", "material": "glas"}]})");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "t.json: /instances/2/material: unknown material 'glas' (known: floor, mirror, glass, matte)");
  expectError(R"({"meshes": {"ball": {"primitive": "sphere"}}, "materials": {"m": {}},
    "instances": [{"mesh": "bal", "material": "m"}]})", "/instances/0/mesh", "unknown mesh 'bal' (known: ball)");
}

TEST(SceneFileErrors, SyntaxErrorsGiveLineAndColumn) {
  Result<Scene> r = parse("{\n  \"meshes\": {\n    \"s\": {\"primitive\": \"sphere\",}\n  }\n}");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("t.json: line 3, column "), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("syntax error"), std::string::npos) << r.error().message;
  Result<Scene> e = parse("");
  ASSERT_FALSE(e);
  EXPECT_NE(e.error().message.find("t.json: line 1"), std::string::npos) << e.error().message;
  // A number beyond double range: nlohmann refuses it; the message still says where.
  Result<Scene> big = parse("{\n\"background\": 1e400}");
  ASSERT_FALSE(big);
  EXPECT_NE(big.error().message.find("t.json: line 2, column 15"), std::string::npos) << big.error().message;
  EXPECT_NE(big.error().message.find("1e400"), std::string::npos) << big.error().message;
}

TEST(SceneFile, CameraLens) {
  auto s = parse(minimal(R"("camera": {"position": [0, 1, 5], "aperture": 0.25, "focusDistance": 4.5})"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->camera.aperture, 0.25f);
  EXPECT_EQ(s->camera.focusDistance, 4.5f);
  EXPECT_EQ(s->camera.lensUv, glm::vec2(0.5f));
  expectError(minimal(R"("camera": {"aperture": -1})"), "/camera/aperture", "-1");
  expectError(minimal(R"("camera": {"focusDistance": 0})"), "/camera/focusDistance", "0");
  expectError(minimal(R"("camera": {"orthographic": true, "aperture": 0.1})"), "/camera/aperture", "orthographic");
  // An aperture of 0 is the pinhole, on any camera.
  EXPECT_TRUE(parse(minimal(R"("camera": {"orthographic": true, "aperture": 0})")).ok());
}

TEST(SceneFile, InstanceMotionAndShutter) {
  auto s = parse(R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}},
                     "instances": [{"mesh": "s", "material": "m",
                                    "motion": {"velocity": [1, 0, -2], "angularVelocity": [0, 90, 0]}}],
                     "camera": {"shutter": 0.05}})");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->instances[0].velocity, glm::vec3(1.0f, 0.0f, -2.0f));
  EXPECT_NEAR(s->instances[0].angularVelocity.y, 1.5707963f, 1e-6f) << "degrees per second in the file, radians in the scene";
  EXPECT_EQ(s->camera.shutter, 0.05f);
  EXPECT_EQ(s->camera.timeU, 0.5f);
  expectError(R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}},
                  "instances": [{"mesh": "s", "material": "m", "motion": {"speed": 3}}]})",
              "/instances/0/motion/speed", "unknown key");
  expectError(R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}},
                  "instances": [{"mesh": "s", "material": "m", "motion": {"velocity": [1, 2]}}]})",
              "/instances/0/motion/velocity", "array of 2");
  expectError(minimal(R"("camera": {"shutter": -0.1})"), "/camera/shutter", "-0.1");
}

TEST(SceneFileErrors, WrongTypes) {
  expectError(R"([1, 2])", "/", "expected an object, got an array");
  expectError(minimal(R"("background": "blue")"), "/background", "expected [x, y, z] or a number, got a string");
  expectError(minimal(R"("background": [1, 2])"), "/background", "expected [x, y, z] or a number, got an array of 2");
  expectError(minimal(R"("camera": {"position": [0, "1", 5]})"), "/camera/position/1", "expected a number, got a string");
  expectError(minimal(R"("lights": {"type": "point"})"), "/lights", "expected an array, got an object");
  expectError(minimal(R"("render": {"width": 640.5})"), "/render/width", "expected an integer, got 640.5");
  expectError(minimal(R"("camera": {"orthographic": 1})"), "/camera/orthographic", "expected true or false, got a number");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "segments": "64"}}})", "/meshes/s/segments",
              "expected an integer, got a string");
  expectError(R"({"materials": {"m": {"shading": 2}}})", "/materials/m/shading", "expected a string, got a number");
  expectError(R"({"materials": {"m": []}})", "/materials/m", "expected an object, got an array");
  expectError(R"({"materials": {"m": {"toonRamp": [[0, 1], [0.5]]}}})", "/materials/m/toonRamp/1",
              "expected [threshold, level], got an array of 1");
}

TEST(SceneFileErrors, MissingRequiredKeys) {
  expectError(R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}}, "instances": [{"mesh": "s"}]})",
              "/instances/0", "missing required key 'material'");
  expectError(R"({"materials": {"m": {}}, "instances": [{"material": "m"}]})", "/instances/0",
              "missing required key 'mesh'");
  expectError(minimal(R"("lights": [{"intensity": 1}])"), "/lights/0", "missing required key 'type'");
  expectError(minimal(R"("lights": [{"type": "point"}])"), "/lights/0", "missing required key 'position'");
  expectError(minimal(R"("lights": [{"type": "spot", "position": [0, 1, 0]}])"), "/lights/0",
              "missing required key 'direction'");
  expectError(R"({"meshes": {"s": {"radius": 1}}})", "/meshes/s", "missing required key 'primitive', 'gltf' or 'csg'");
  expectError(R"({"materials": {"m": {"checker": {"frequency": 2}}}})", "/materials/m/checker",
              "missing required key 'color2'");
  expectError(R"({"meshes": {"s": {"primitive": "box"}}, "materials": {"m": {}},
                  "instances": [{"mesh": "s", "material": "m", "transform": {"rotate": {"angle": 30}}}]})",
              "/instances/0/transform/rotate", "missing required key 'axis'");
}

TEST(SceneFileErrors, NumbersOutOfRangeOrTooLargeForAFloat) {
  // JSON cannot hold NaN or inf, but 1e39 overflows a float to inf.
  expectError(minimal(R"("camera": {"position": [0, 1e39, 5]})"), "/camera/position/1", "too large (not a finite float)");
  expectError(R"({"meshes": {"b": {"primitive": "box", "size": [1, -2, 1]}}})", "/meshes/b/size/1", "must be > 0, got -2");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "radius": 0}}})", "/meshes/s/radius", "must be > 0, got 0");
  expectError(R"({"meshes": {"p": {"primitive": "plane", "size": [1, -1]}}})", "/meshes/p/size/1", "must be > 0");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "segments": 5000}}})", "/meshes/s/segments",
              "must be in [3, 4096], got 5000");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "rings": 1}}})", "/meshes/s/rings", "must be in [2, 4096], got 1");
  expectError(R"({"meshes": {"p": {"primitive": "plane", "divisions": 0}}})", "/meshes/p/divisions", "must be in [1, 4096]");
  // Each side within its cap, but together absurd: rejected before allocating anything.
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "segments": 4096, "rings": 4096}}})", "/meshes/s",
              "tessellation gives 33546240 triangles, more than the limit");
  expectError(R"({"meshes": {"p": {"primitive": "plane", "divisions": 4096}}})", "/meshes/p", "more than the limit");
  expectError(R"({"materials": {"m": {"kr": 1.5}}})", "/materials/m/kr", "must be in [0, 1], got 1.5");
  expectError(R"({"materials": {"m": {"kd": [0.5, -0.1, 0]}}})", "/materials/m/kd/1", "must be >= 0, got -0.1");
  expectError(R"({"materials": {"m": {"ior": 0}}})", "/materials/m/ior", "must be in (0, 10], got 0");
  expectError(R"({"materials": {"m": {"ns": -1}}})", "/materials/m/ns", "must be in [0, 10000]");
  expectError(R"({"materials": {"m": {"toonRamp": [[2, 1]]}}})", "/materials/m/toonRamp/0/0", "must be in [-1, 1], got 2");
  expectError(R"({"materials": {"m": {"checker": {"color2": 1, "frequency": 0}}}})", "/materials/m/checker/frequency",
              "must be in (0, 1e+06]");
  expectError(minimal(R"("lights": [{"type": "point", "position": [0, 1, 0], "intensity": -1}])"), "/lights/0/intensity",
              "must be >= 0, got -1");
  expectError(minimal(R"("lights": [{"type": "point", "position": [0, 1, 0], "attenuation": [0, 0, 0]}])"),
              "/lights/0/attenuation", "at least one of constant, linear, quadratic must be > 0");
  expectError(minimal(R"("lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "innerCone": 40, "outerCone": 30}])"),
              "/lights/0/innerCone", "must not exceed outerCone");
  expectError(minimal(R"("lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "outerCone": 90}])"),
              "/lights/0/outerCone", "must be in [0, 90)");
  expectError(minimal(R"("lights": [{"type": "directional", "direction": [0, 0, 0]}])"), "/lights/0/direction",
              "must be a non-zero vector");
  expectError(minimal(R"("render": {"width": 0})"), "/render/width", "must be in [1, 16384], got 0");
  expectError(minimal(R"("render": {"maxDepth": 65})"), "/render/maxDepth", "must be in [0, 64], got 65");
}

TEST(SceneFileErrors, InvalidCamera) {
  expectError(minimal(R"("camera": {"fov": 180})"), "/camera/fov", "must be in (0, 180), got 180");
  expectError(minimal(R"("camera": {"near": 0})"), "/camera/near", "must be > 0, got 0");
  expectError(minimal(R"("camera": {"near": 2, "far": 1})"), "/camera/far", "must be greater than near");
  expectError(minimal(R"("camera": {"far": "forever"})"), "/camera/far", "expected a number or \"infinite\"");
  expectError(minimal(R"("camera": {"position": [1, 1, 1], "target": [1, 1, 1]})"), "/camera/target",
              "target must differ from position");
  expectError(minimal(R"("camera": {"position": [0, 5, 0], "target": [0, 0, 0]})"), "/camera/up",
              "up is parallel to the view direction");
  expectError(minimal(R"("camera": {"height": -2})"), "/camera/height", "must be > 0");
}

TEST(SceneFileErrors, InvalidTransforms) {
  auto with = [](const std::string& transform) {
    return R"({"meshes": {"s": {"primitive": "box"}}, "materials": {"m": {}},
               "instances": [{"mesh": "s", "material": "m", "transform": )" + transform + "}]}";
  };
  const std::string p = "/instances/0/transform";
  expectError(with(R"({"scale": 0})"), p + "/scale", "must be in (0, 1e+06], got 0");
  expectError(with(R"({"scale": [1, -1, 1]})"), p + "/scale/1", "must be in (0, 1e+06], got -1");
  expectError(with(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "translate": [1, 0, 0]})"), p + "/matrix",
              "cannot be combined");
  expectError(with(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0]})"), p + "/matrix", "expected 16 numbers (column-major), got an array of 12");
  expectError(with(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,1, 0,0,0,1]})"), p + "/matrix", "not an affine transform");
  expectError(with(R"({"matrix": [1,0,0,0, 0,0,0,0, 0,0,1,0, 0,0,0,1]})"), p + "/matrix", "singular");
  expectError(with(R"({"matrix": [-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})"), p + "/matrix", "mirrors");
  expectError(with(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,1e39,0,1]})"), p + "/matrix/13", "too large");
  expectError(with(R"({"rotate": {"axis": [0, 0, 0], "angle": 10}})"), p + "/rotate/axis", "must be a non-zero vector");
  expectError(with(R"({"rotate": "x"})"), p + "/rotate", "expected [x, y, z] Euler degrees or {\"axis\", \"angle\"}");
}

TEST(SceneFileErrors, UnknownKeysAndValuesNameTheKey) {
  expectError(minimal(R"("instance": [])"), "/instance", "unknown key 'instance' (allowed: name, meshes, materials");
  expectError(R"({"materials": {"m": {"kdd": 0.5}}})", "/materials/m/kdd", "unknown key 'kdd'");
  expectError(R"({"materials": {"m": {"checker": {"color2": 1, "freq": 2}}}})", "/materials/m/checker/freq",
              "unknown key 'freq' (allowed: color2, frequency)");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "size": 2}}})", "/meshes/s/size",
              "unknown key 'size' for a sphere (allowed: primitive, radius, segments, rings, exact)");
  expectError(R"({"meshes": {"s": {"primitive": "pyramid"}}})", "/meshes/s/primitive", "unknown primitive 'pyramid'");
  expectError(R"({"meshes": {"s": {"primitive": "box", "gltf": "a.gltf"}}})", "/meshes/s", "one of 'primitive', 'gltf' or 'csg', not several");
  // A key that belongs to another light type is a mistake too.
  expectError(minimal(R"("lights": [{"type": "directional", "direction": [0, -1, 0], "position": [0, 1, 0]}])"),
              "/lights/0/position", "unknown key 'position' for a directional light");
  expectError(minimal(R"("lights": [{"type": "point", "position": [0, 1, 0], "innerCone": 10}])"), "/lights/0/innerCone",
              "unknown key 'innerCone' for a point light");
  expectError(minimal(R"("lights": [{"type": "sun"}])"), "/lights/0/type", "unknown light type 'sun'");
  expectError(R"({"materials": {"m": {"shading": "smooth"}}})", "/materials/m/shading",
              "unknown shading model 'smooth' (known: flat, gouraud, phong, toon)");
  expectError(R"({"materials": {"m": {"alphaMode": "cutout"}}})", "/materials/m/alphaMode", "unknown alpha mode 'cutout'");
  expectError(minimal(R"("render": {"preset": "fast"})"), "/render/preset", "unknown preset 'fast' (known: raster");
  expectError(minimal(R"("camera": {"fovy": 30})"), "/camera/fovy", "unknown key 'fovy'");
  expectError(R"({"meshes": {"s": {"primitive": "box"}}, "materials": {"m": {}},
                  "instances": [{"mesh": "s", "material": "m", "transform": {"rotation": [0, 1, 0]}}]})",
              "/instances/0/transform/rotation", "unknown key 'rotation' (allowed: translate, rotate, scale, matrix)");
}

TEST(SceneFileErrors, DuplicateNames) {
  // Duplicate object keys: nlohmann would keep the last one silently.
  expectError(R"({"materials": {"m": {}, "n": {}, "m": {"kd": 1}}})", "/materials/m", "duplicate key 'm'");
  expectError(R"({"materials": {"m": {"kd": 1, "kd": 0}}})", "/materials/m/kd", "duplicate key 'kd'");
  expectError(R"({"lights": [{"type": "ambient"}, {"type": "point", "position": [0, 1, 0], "position": [1, 1, 1]}]})",
              "/lights/1/position", "duplicate key 'position'");
  expectError(minimal(R"("lights": [{"type": "ambient", "name": "a"}, {"type": "ambient", "name": "a"}])"),
              "/lights/1/name", "duplicate light name 'a'");
  expectError(R"({"meshes": {"s": {"primitive": "box"}}, "materials": {"m": {}},
                  "instances": [{"name": "x", "mesh": "s", "material": "m"}, {"name": "x", "mesh": "s", "material": "m"}]})",
              "/instances/1/name", "duplicate instance name 'x'");
  expectError(R"({"meshes": {"": {"primitive": "box"}}})", "/meshes/", "mesh names must not be empty");
}

TEST(SceneFileErrors, PathsEscapeSlashesInNames) {
  expectError(R"({"materials": {"a/b~c": {"kr": 2}}})", "/materials/a~1b~0c/kr", "must be in [0, 1]");
}

TEST(SceneFileErrors, TooManyLights) {
  std::string lights;
  for (int i = 0; i <= kMaxLights; ++i) lights += std::string(i ? "," : "") + R"({"type": "point", "position": [0, 1, 0]})";
  expectError(minimal("\"lights\": [" + lights + "]"), "/lights/" + std::to_string(kMaxLights),
              "too many lights: " + std::to_string(kMaxLights + 1) + " non-ambient lights, the limit is " +
                  std::to_string(kMaxLights));
}

TEST(SceneFileErrors, DeepNestingIsRefused) {
  std::string deep = "{\"background\": " + std::string(200, '[') + std::string(200, ']') + "}";
  Result<Scene> r = parse(deep);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("t.json: /background/0/0"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("nesting deeper than 64 levels"), std::string::npos) << r.error().message;
}

TEST(SceneFileErrors, FilesThatCannotBeRead) {
  Result<Scene> r = loadSceneFile(test::outputDir() + "/no-such-scene.json");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("no-such-scene.json: no such file"), std::string::npos) << r.error().message;

  const std::string path = test::outputDir() + "/scene-file-typo.json";
  std::ofstream(path) << R"({"materials": {"m": {"ks": 0.5, "nss": 3}}})";
  Result<Scene> t = loadSceneFile(path);
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("scene-file-typo.json: /materials/m/nss: unknown key 'nss'"), std::string::npos)
      << t.error().message;
}

// Damaged input never throws and never passes: every prefix of the real scene, and the scene with each
// value replaced by the wrong type.
TEST(SceneFileErrors, DamagedTextNeverThrows) {
  const std::string text = readText(test::sourceDir() + "/assets/scenes/whitted.json");
  ASSERT_FALSE(text.empty());
  const std::size_t end = text.find_last_of('}');
  for (std::size_t n = 0; n < end; n += 7) {
    Result<Scene> r = Result<Scene>(Error{});
    EXPECT_NO_THROW(r = parse(text.substr(0, n)));
    EXPECT_FALSE(r) << "prefix of " << n << " bytes was accepted";
  }
  int replaced = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    // Replace each number that starts after a space or "[" by a string, outside comment lines.
    if (!(std::isdigit(static_cast<unsigned char>(text[i])) && i >= 1 && (text[i - 1] == ' ' || text[i - 1] == '[')))
      continue;
    const std::size_t lineStart = text.rfind('\n', i) + 1;  // npos + 1 = 0 on the first line
    const std::size_t firstChar = text.find_first_not_of(' ', lineStart);
    if (text.compare(firstChar, 2, "//") == 0) continue;
    std::size_t j = i;
    while (j < text.size() && (std::isdigit(static_cast<unsigned char>(text[j])) || text[j] == '.')) ++j;
    std::string damaged = text.substr(0, i) + "\"x\"" + text.substr(j);
    Result<Scene> r = Result<Scene>(Error{});
    EXPECT_NO_THROW(r = parse(damaged));
    if (!r) {
      ++replaced;
      EXPECT_NE(r.error().message.find("expected"), std::string::npos) << r.error().message;
    } else {
      ADD_FAILURE() << "a string in place of the number at byte " << i << " was accepted";
    }
  }
  EXPECT_GT(replaced, 50);
}

// ---- the shipped scenes ----

TEST(SceneFileAssets, WhittedSceneIsTheClassicOne) {
  Result<Scene> r = loadSceneFile(test::sourceDir() + "/assets/scenes/whitted.json");
  ASSERT_TRUE(r) << r.error().message;
  const Scene& s = *r;
  EXPECT_TRUE(validateScene(s));
  EXPECT_EQ(s.name, "whitted");
  auto material = [&](const std::string& name) -> const Material& {
    for (const Material& m : s.materials)
      if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return s.materials.front();
  };
  const Material& floor = material("floor");
  EXPECT_EQ(floor.checkerFrequency, 0.5f);                            // squares of 2 units
  EXPECT_GT(floor.kd.r, floor.kd.g * 4);                              // red squares
  EXPECT_GT(floor.kd2.r, 0.5f);                                       // yellow squares
  EXPECT_GT(floor.kd2.g, 0.5f);
  const Material& mirror = material("mirror");
  EXPECT_GE(mirror.kr, 0.8f);
  EXPECT_LE(glm::length(mirror.kd), 0.1f);
  const Material& glass = material("glass");
  EXPECT_NEAR(glass.kt, 0.9f, 0.05f);
  EXPECT_FLOAT_EQ(glass.ior, 1.5f);
  EXPECT_LE(glm::length(glass.kd), 0.1f);
  EXPECT_GE(glass.ks.x, 0.5f);
  for (const Material& m : s.materials) EXPECT_EQ(m.shading, ShadingModel::Phong) << m.name;
  // Two direct lights of different types and an ambient one.
  std::vector<const Light*> direct = s.directLights();
  ASSERT_EQ(direct.size(), 2u);
  EXPECT_NE(direct[0]->type, direct[1]->type);
  const glm::vec3 ia = s.ambientIntensity();  // the sky light: (0.6, 0.75, 1.0) × 0.15
  EXPECT_NEAR(ia.x, 0.09f, 1e-6f);
  EXPECT_NEAR(ia.y, 0.1125f, 1e-6f);
  EXPECT_NEAR(ia.z, 0.15f, 1e-6f);
  EXPECT_EQ(s.render.width * 9, s.render.height * 16);
  EXPECT_GT(s.background.b, s.background.r);  // sky blue
  EXPECT_EQ(s.instances.size(), 4u);
  for (const Instance& i : s.instances) {
    if (s.meshes[i.mesh].name == "sphere") {
      EXPECT_EQ(s.meshes[i.mesh].triangleCount(), 64u * 62u);
    }
  }
  // The camera frames the objects: every instance origin projects inside the image.
  const glm::mat4 vp = s.camera.clipFromView(16.0f / 9.0f) * s.camera.viewFromWorld();
  for (const Instance& i : s.instances) {
    glm::vec4 c = vp * i.worldFromObject * glm::vec4(0, 0, 0, 1);
    ASSERT_GT(c.w, 0.0f) << i.name;
    EXPECT_LT(std::abs(c.x / c.w), 1.0f) << i.name;
    EXPECT_LT(std::abs(c.y / c.w), 1.0f) << i.name;
  }
}

TEST(SceneFileAssets, EmbeddedDefaultIsWhittedJson) {
  EXPECT_EQ(defaultSceneText(), readText(test::sourceDir() + "/assets/scenes/whitted.json"));
  Result<Scene> r = loadDefaultScene();
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_TRUE(validateScene(*r));
  EXPECT_EQ(r->name, "whitted");
  EXPECT_EQ(r->instances.size(), 4u);
}

TEST(SceneFileAssets, EveryShippedSceneLoads) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(test::sourceDir() + "/assets/scenes")) {
    if (e.path().extension() != ".json") continue;
    ++count;
    Result<Scene> r = loadSceneFile(e.path().string());
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_TRUE(validateScene(*r)) << e.path();
    EXPECT_FALSE(r->instances.empty()) << e.path();
    // Shipped scenes are embedded too, so tools can run without the checkout.
    EXPECT_TRUE(findEmbedded("assets/scenes/" + e.path().filename().string())) << e.path();
  }
  EXPECT_GE(count, 2);
}

TEST(SceneFileAssets, ShadowsSceneHasNoMirrorsOrGlass) {
  Result<Scene> r = loadSceneFile(test::sourceDir() + "/assets/scenes/shadows.json");
  ASSERT_TRUE(r) << r.error().message;
  for (const Material& m : r->materials) {
    EXPECT_EQ(m.kr, 0.0f) << m.name;
    EXPECT_EQ(m.kt, 0.0f) << m.name;
  }
  std::vector<const Light*> direct = r->directLights();
  ASSERT_EQ(direct.size(), 2u);
  EXPECT_EQ(direct[0]->type, LightType::Directional);
  EXPECT_EQ(direct[1]->type, LightType::Spot);
}

}  // namespace
}  // namespace tandem

namespace tandem {
namespace {

// docs/scene-format.md: "Integers must be integral (`64`, `64.0`; not `64.5`)", each within its key's
// documented range. Every integer key of the format, at both ends of its range, written as an integer, as a
// float with a zero fraction and in exponent form; its neighbours outside the range and a fraction refused,
// naming the key. The ranges come from the format's table, not from the reader.
TEST(SceneFileIntegers, EveryIntegerKeyTakesIntegralNumbersAndRefusesTheRestByName) {
  struct Key {
    const char* path;  // the JSON path the error names
    int lo, hi;
    std::function<std::string(const std::string&)> scene;  // the scene with the key set to the text
    std::function<int(const Scene&)> read;                  // where the value lands
  };
  const std::vector<Key> keys = {
      {"/meshes/s/segments", 3, 4096,
       [](const std::string& v) { return R"({"meshes": {"s": {"primitive": "sphere", "rings": 2, "segments": )" + v + "}}}"; },
       // a sphere of n segments and 2 rings has (n + 1) · 3 vertices
       [](const Scene& s) { return static_cast<int>(s.meshes.at(0).positions.size() / 3) - 1; }},
      {"/meshes/s/rings", 2, 4096,
       [](const std::string& v) { return R"({"meshes": {"s": {"primitive": "sphere", "segments": 3, "rings": )" + v + "}}}"; },
       [](const Scene& s) { return static_cast<int>(s.meshes.at(0).positions.size() / 4) - 1; }},
      {"/meshes/s/divisions", 1, 512,  // 4096 is the format's bound; 512² quads stay within the load budget
       [](const std::string& v) { return R"({"meshes": {"s": {"primitive": "plane", "divisions": )" + v + "}}}"; },
       [](const Scene& s) { return static_cast<int>(std::lround(std::sqrt(double(s.meshes.at(0).positions.size())))) - 1; }},
      {"/materials/m/texture/octaves", 1, 8,
       [](const std::string& v) { return R"({"materials": {"m": {"texture": {"type": "fbm", "octaves": )" + v + "}}}}"; },
       [](const Scene& s) { return s.materials.at(0).procedural.octaves; }},
      {"/render/width", 1, 16384,
       [](const std::string& v) { return R"({"render": {"width": )" + v + "}}"; },
       [](const Scene& s) { return s.render.width; }},
      {"/render/height", 1, 16384,
       [](const std::string& v) { return R"({"render": {"height": )" + v + "}}"; },
       [](const Scene& s) { return s.render.height; }},
      {"/render/maxDepth", 0, 64,
       [](const std::string& v) { return R"({"render": {"maxDepth": )" + v + "}}"; },
       [](const Scene& s) { return s.render.maxDepth; }},
  };
  for (const Key& k : keys) {
    SCOPED_TRACE(k.path);
    for (int n : {k.lo, k.hi}) {
      const std::string text = std::to_string(n);
      for (const std::string& written : {text, text + ".0", text + ".000", text + "e0"}) {
        Result<Scene> r = parse(k.scene(written));
        ASSERT_TRUE(r) << written << ": " << r.error().message;
        EXPECT_EQ(k.read(*r), n) << written;
      }
    }
    expectError(k.scene(std::to_string(k.lo) + ".5"), k.path, "expected an integer, got " + std::to_string(k.lo) + ".5");
    expectError(k.scene(std::to_string(k.hi) + ".25"), k.path, "expected an integer, got " + std::to_string(k.hi) + ".25");
    expectError(k.scene(std::to_string(k.lo) + ".000001"), k.path, "expected an integer");
    const std::string range = "must be in [" + std::to_string(k.lo) + ", ";
    expectError(k.scene(std::to_string(k.lo - 1)), k.path, range);
    expectError(k.scene(std::to_string(k.lo - 1) + ".0"), k.path, range);
    if (k.hi < 4096 && std::string(k.path).find("divisions") == std::string::npos) {
      expectError(k.scene(std::to_string(k.hi + 1)), k.path, range);
      expectError(k.scene(std::to_string(k.hi + 1) + ".0"), k.path, range);
    }
    expectError(k.scene("1e300"), k.path, range);
    expectError(k.scene("-1e300"), k.path, range);
    expectError(k.scene("true"), k.path, "expected an integer, got");
  }
  // The upper bounds of the tessellation keys, refused one past them (the plane's without building it).
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "rings": 2, "segments": 4097}}})", "/meshes/s/segments",
              "must be in [3, 4096], got 4097");
  expectError(R"({"meshes": {"s": {"primitive": "sphere", "segments": 3, "rings": 4097.0}}})", "/meshes/s/rings",
              "must be in [2, 4096], got 4097");
  expectError(R"({"meshes": {"s": {"primitive": "plane", "divisions": 4097}}})", "/meshes/s/divisions",
              "must be in [1, 4096], got 4097");
}

}  // namespace
}  // namespace tandem
