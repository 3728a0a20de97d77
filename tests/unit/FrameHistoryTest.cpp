// The last frame and the next frame's reuse decisions (render/FrameHistory.h), without GL or Embree: when a frame
// reuses the last one's rays whole, when it keeps some shadow answers and what it is told changed. Worked out
// from the rules docs/reuse.md states; tests/gl/FrameDecisionsGLTest.cpp checks the frames that follow from them.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "render/FrameHistory.h"

namespace tandem {
namespace {

Scene twoThingsAndALight() {
  Scene s;
  s.instances.resize(2);
  s.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 0.0f, 0.0f));
  Light ambient;
  ambient.type = LightType::Ambient;
  Light key;
  key.posW = glm::vec3(0.0f, 4.0f, 0.0f);
  Light fill;
  fill.posW = glm::vec3(3.0f, 4.0f, 0.0f);
  s.lights = {ambient, key, fill};
  return s;
}

// A hybrid frame whose ray pass traces primary shadows (the only answers a frame can keep).
FramePlan shadowRays() {
  SceneFacts facts;
  facts.shadowLight = true;
  FrameSettings s;
  s.shadows = EffectMode::Ray;
  s.reflections = EffectMode::Off;
  s.refraction = EffectMode::Off;
  s.reuseRays = true;
  return planFrame(facts, s);
}

struct Drawn {
  Scene scene = twoThingsAndALight();
  Camera camera;
  FramePlan plan = shadowRays();
  FrameHistory last;
  Drawn() { last.remember(plan, camera, scene, false, 0); }
};

TEST(FrameHistory, AFrameReusesTheLastOnesRaysOnlyWhenNothingTheyDependOnChanged) {
  Drawn d;
  ASSERT_TRUE(d.plan.rayPass);
  EXPECT_TRUE(d.last.reusesRays(d.plan, d.camera, true, false));
  EXPECT_FALSE(d.last.reusesRays(d.plan, d.camera, false, false)) << "the last frame was not drawn";
  EXPECT_FALSE(d.last.reusesRays(d.plan, d.camera, true, true)) << "an adaptive round traces some pixels only";
  Camera moved = d.camera;
  moved.targetW.y += 0.01f;
  EXPECT_FALSE(d.last.reusesRays(d.plan, moved, true, false)) << "the camera turned";
  FramePlan deeper = d.plan;
  deeper.settings.maxDepth += 1;
  deeper.raySettings.maxDepth += 1;
  EXPECT_FALSE(d.last.reusesRays(deeper, d.camera, true, false)) << "a ray setting changed";
  FramePlan brighter = d.plan;
  brighter.settings.exposure = 2.0f;
  EXPECT_TRUE(d.last.reusesRays(brighter, d.camera, true, false)) << "the exposure is not the rays' business";
  FramePlan off = d.plan;
  off.settings.reuseRays = false;
  EXPECT_FALSE(d.last.reusesRays(off, d.camera, true, false)) << "reuse turned off";
  d.last.sceneChanged = true;
  EXPECT_FALSE(d.last.reusesRays(d.plan, d.camera, true, false)) << "the scene changed";
}

TEST(FrameHistory, WhatMovedAndWhichLightsChangedAreTheChangesKept) {
  Drawn d;
  FrameHistory::Changes changes;
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes))
      << "nothing changed: the rays are reused whole, not kept in part";
  const glm::mat4 before = d.scene.instances[1].worldFromObject;
  d.scene.instances[1].worldFromObject = glm::translate(before, glm::vec3(0.0f, 0.5f, 0.0f));
  d.scene.lights[2].posW.x += 1.0f;
  d.last.sceneChanged = true;
  ASSERT_TRUE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes));
  ASSERT_EQ(changes.moved.size(), 1u);
  EXPECT_EQ(changes.moved[0].first, 1u);
  EXPECT_EQ(changes.moved[0].second, before) << "the transform the kept frame drew it with";
  EXPECT_EQ(changes.changedLights, 2u) << "bit 1: the second direct light (the ambient one is not direct)";

  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, false, true, changes)) << "the last frame was not drawn";
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, true, false, changes)) << "no answers were left";
  Camera moved = d.camera;
  moved.posW.x += 0.01f;
  EXPECT_FALSE(d.last.keepsSome(d.plan, moved, d.scene, true, true, changes)) << "the camera moved";
  FramePlan noShadowRays = d.plan;
  noShadowRays.rays.primaryShadows = false;
  EXPECT_FALSE(d.last.keepsSome(noShadowRays, d.camera, d.scene, true, true, changes)) << "no shadow answers traced";
  Scene more = d.scene;
  more.instances.emplace_back();
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, more, true, true, changes)) << "another instance: not comparable";
  d.last.sceneReplaced = true;
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes)) << "setScene since";
}

TEST(FrameHistory, NothingIsKeptWhileAnythingMovesUnderAnOpenShutterNorJustAfter) {
  Drawn d;
  d.camera.shutter = 0.1f;
  d.scene.instances[0].velocity = glm::vec3(1.0f, 0.0f, 0.0f);
  d.last.remember(d.plan, d.camera, d.scene, false, 0);
  EXPECT_TRUE(d.last.moving);
  d.scene.instances[0].velocity = glm::vec3(0.0f);  // stopped now, but the last frame's rays saw it moving
  d.scene.instances[1].worldFromObject[3].y += 1.0f;
  d.last.sceneChanged = true;
  FrameHistory::Changes changes;
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes));
  d.last.remember(d.plan, d.camera, d.scene, false, 0);
  EXPECT_FALSE(d.last.moving);
  d.scene.instances[1].worldFromObject[3].y += 1.0f;
  d.last.sceneChanged = true;
  EXPECT_TRUE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes));
  d.scene.instances[0].velocity = glm::vec3(0.0f, 0.0f, 2.0f);  // moving now
  EXPECT_FALSE(d.last.keepsSome(d.plan, d.camera, d.scene, true, true, changes));
}

TEST(FrameHistory, RememberKeepsTheSceneOnlyWhenReuseIsOn) {
  Drawn d;
  EXPECT_TRUE(d.last.drawn);
  EXPECT_EQ(d.last.transforms.size(), 2u);
  EXPECT_EQ(d.last.directLights.size(), 2u);
  d.last.sceneChanged = d.last.sceneReplaced = true;
  FramePlan off = d.plan;
  off.settings.reuseRays = false;
  d.last.remember(off, d.camera, d.scene, true, 3);
  EXPECT_FALSE(d.last.sceneChanged);
  EXPECT_FALSE(d.last.sceneReplaced);
  EXPECT_TRUE(d.last.transforms.empty()) << "cost follows the settings";
  EXPECT_TRUE(d.last.directLights.empty());
  EXPECT_TRUE(d.last.shadowMaps);
  EXPECT_EQ(d.last.probeEffects, 3);
}

}  // namespace
}  // namespace tandem
