// coplanarOverlaps (tandem/Scene.h): faces of two instances in one plane that can be seen fighting for depth.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "tandem/Log.h"
#include "tandem/Primitives.h"
#include "tandem/Scene.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

// A floor plane (y = 0, facing up) and a unit box standing on it, its base at y = lift.
Scene boxOnFloor(float lift, float kt = 0.9f) {
  Scene s;
  s.meshes = {makePlane({10.0f, 10.0f}, 4), makeBox(glm::vec3(1.0f))};
  Material floor;
  Material glass;
  glass.kt = kt;
  s.materials = {floor, glass};
  Instance f;
  f.name = "floor";
  Instance b;
  b.name = "pillar";
  b.mesh = 1;
  b.material = 1;
  b.worldFromObject = glm::translate(glm::mat4(1.0f), {2.0f, 0.5f + lift, -1.0f});
  s.instances = {f, b};
  return s;
}

TEST(SceneChecks, GlassBoxStandingOnTheFloorFights) {
  const auto w = coplanarOverlaps(boxOnFloor(0.0f));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("instances 0 'floor' and 1 'pillar' have overlapping faces in one plane"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("normal (0, 1, 0), offset 0"), std::string::npos) << w[0];
}

TEST(SceneChecks, LiftedSunkOrOpaqueDoesNot) {
  EXPECT_TRUE(coplanarOverlaps(boxOnFloor(1e-3f)).empty()) << "lifted by 1 mm";
  EXPECT_TRUE(coplanarOverlaps(boxOnFloor(-0.01f)).empty()) << "sunk into the floor: its base is below it";
  EXPECT_TRUE(coplanarOverlaps(boxOnFloor(0.0f, 0.0f)).empty())
      << "an opaque box's base cannot be seen from above, nor the floor from inside the box";
  Scene off = boxOnFloor(0.0f);
  off.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), {20.0f, 0.5f, 0.0f});
  EXPECT_TRUE(coplanarOverlaps(off).empty()) << "in the floor's plane but beside it";
}

TEST(SceneChecks, FacesLookingTheSameWayFightEvenWhenOpaque) {
  // A decal-like second floor in the same plane, rotated and larger: both face up, both seen.
  Scene s = boxOnFloor(0.02f, 0.0f);
  s.instances.push_back(s.instances[0]);
  s.instances[2].name = "decal";
  s.instances[2].worldFromObject = glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0, 1, 0));
  const auto w = coplanarOverlaps(s);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("'floor' and 2 'decal'"), std::string::npos) << w[0];
}

TEST(SceneChecks, TouchingEdgesAndCurvedMeshesAreNotReported) {
  Scene s = boxOnFloor(0.0f);
  // Two glass boxes side by side share a face: that overlaps; placed corner to corner they only touch.
  s.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), {0.0f, 5.0f, 0.0f});
  s.instances.push_back(s.instances[1]);
  s.instances[2].name = "touching";
  s.instances[2].worldFromObject = glm::translate(glm::mat4(1.0f), {1.0f, 6.0f, 0.0f});
  EXPECT_TRUE(coplanarOverlaps(s).empty()) << "an edge in common is not an area";
  s.instances[2].worldFromObject = glm::translate(glm::mat4(1.0f), {1.0f, 5.0f, 0.0f});
  EXPECT_EQ(coplanarOverlaps(s).size(), 1u) << "a whole face in common";
  Scene round = boxOnFloor(0.0f);
  round.meshes[1] = makeSphere(0.5f, 32, 16);
  round.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), {0.0f, 0.5f, 0.0f});
  EXPECT_TRUE(coplanarOverlaps(round).empty()) << "curved meshes are not checked";
}

TEST(SceneChecks, TheSceneFileLoaderWarns) {
  std::vector<std::string> logged;
  LogSink old = setLogSink([&](LogLevel l, std::string_view m) {
    if (l == LogLevel::Warning) logged.emplace_back(m);
  });
  auto r = parseSceneJson(R"({"meshes": {"floor": {"primitive": "plane", "size": 10}, "box": {"primitive": "box"}},
    "materials": {"matte": {}, "glass": {"kt": 0.9}},
    "instances": [{"name": "floor", "mesh": "floor", "material": "matte"},
                  {"name": "pillar", "mesh": "box", "material": "glass", "transform": {"translate": [0, 0.5, 0]}}]})",
                          "c.json", ".");
  setLogSink(old);
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(logged.size(), 1u);
  EXPECT_NE(logged[0].find("c.json: instances 0 'floor' and 1 'pillar' have overlapping faces"), std::string::npos)
      << logged[0];
}

}  // namespace
}  // namespace tandem
