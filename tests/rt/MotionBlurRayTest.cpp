// Motion blur in the ray scene (rt/EmbreeScene.h; docs/motion-blur.md): a moving instance is an Embree
// motion-blur instance whose rays find it where their time puts it, the transform that rebuilds their hits is
// the one Embree interpolates, the time travels from a hit to the rays it spawns, and a changed shutter or
// motion reaches the steps without a rebuild.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/Motion.h"
#include "core/RenderSpace.h"
#include "rt/EmbreeScene.h"
#include "rt/RtTestScenes.h"
#include "rt/Wavefront.h"
#include "rt/Whitted.h"

namespace tandem::rt {
namespace {

using namespace test;

struct Rolling {
  Scene scene;
  std::uint32_t ball = 0, floor = 0;
};

// A unit sphere at (0, 1, 0) moving along +x at 4 units per second and spinning, over a floor.
Rolling rolling() {
  Rolling r;
  const std::uint32_t mat = addMaterial(r.scene, diffuse(glm::vec3(0.7f)));
  r.floor = addInstance(r.scene, addMesh(r.scene, makePlane({40.0f, 40.0f}, 1)), mat, glm::mat4(1.0f));
  r.ball = addInstance(r.scene, addMesh(r.scene, makeSphere(1.0f, 64, 32)), mat, translate({0.0f, 1.0f, 0.0f}));
  r.scene.instances[r.ball].velocity = glm::vec3(4.0f, 0.0f, 0.0f);
  r.scene.instances[r.ball].angularVelocity = glm::vec3(0.0f, 0.0f, -4.0f);
  r.scene.lights.push_back(directional({0.0f, -1.0f, 0.0f}));
  r.scene.camera.posW = {0.0f, 3.0f, 8.0f};
  r.scene.camera.targetW = {0.0f, 1.0f, 0.0f};
  return r;
}

TEST(MotionBlurRays, RaysFindTheInstanceWhereTheirTimePutsIt) {
  Rolling r = rolling();
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  const float shutter = 0.5f;  // the ball's centre runs from x = -1 to x = +1
  auto embree = EmbreeScene::build(**device, r.scene, shutter);
  ASSERT_TRUE(embree.ok());
  EXPECT_TRUE((*embree)->hasMotion());
  FrameSettings s = settingsFor(16, 16);
  FrameShading frame(r.scene, s.shadingOverride, (*embree)->anchor());
  Whitted whitted(r.scene, **embree, frame, TraceModes::reference(s));
  for (float u : {0.0f, 0.25f, 0.5f, 0.8f, 1.0f}) {
    const float centreX = 4.0f * (u - 0.5f) * shutter;
    // Straight down through where the centre is at time u: the ball's top, at height 2.
    const glm::vec3 from = toRenderSpace(glm::vec3(centreX, 5.0f, 0.0f), (*embree)->anchor());
    std::uint32_t instance = 0, triangle = 0;
    ASSERT_TRUE(whitted.intersect(from, glm::vec3(0, -1, 0), 0.0f, 100.0f, instance, triangle, u)) << u;
    EXPECT_EQ(instance, r.ball) << u;
    // The hit rebuilt with the transform at that time lies on the moved sphere.
    const SurfaceHit hit = resolveHit(r.scene, (*embree)->transformAt(instance, u), instance, triangle,
                                      Ray{from, glm::vec3(0, -1, 0)});
    const glm::vec3 centre = toRenderSpace(glm::vec3(centreX, 1.0f, 0.0f), (*embree)->anchor());
    EXPECT_NEAR(glm::length(hit.posW - centre), 1.0f, 2e-3f) << u;  // the tessellated sphere's sag
    // Beside where the ball is then (1.3 units off its centre): the floor.
    const glm::vec3 beside = toRenderSpace(glm::vec3(centreX + (u < 0.5f ? 1.3f : -1.3f), 5.0f, 0.0f), (*embree)->anchor());
    ASSERT_TRUE(whitted.intersect(beside, glm::vec3(0, -1, 0), 0.0f, 100.0f, instance, triangle, u));
    EXPECT_EQ(instance, r.floor) << "at time " << u << " the ball is elsewhere";
  }
  // transformAt is Embree's interpolation of the steps, and the middle of the shutter is the transform.
  const std::vector<glm::mat4> steps = motionSteps(r.scene.instances[r.ball], shutter, (*embree)->anchor());
  for (float u : {0.1f, 0.5f, 0.77f})
    EXPECT_EQ((*embree)->transformAt(r.ball, u).worldFromObject, motionAt(steps, u));
  EXPECT_EQ((*embree)->transformAt(r.ball, 0.5f).worldFromObject, (*embree)->transform(r.ball).worldFromObject);
  EXPECT_EQ((*embree)->transformAt(r.floor, 0.9f).worldFromObject, (*embree)->transform(r.floor).worldFromObject);
}

TEST(MotionBlurRays, ShadowRaysRunAtTheirHitsTime) {
  // The ball's shadow on the floor below x = -0.9 at time 0 (the ball is there) and not at time 1.
  Rolling r = rolling();
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  auto embree = EmbreeScene::build(**device, r.scene, 0.5f);
  ASSERT_TRUE(embree.ok());
  FrameSettings s = settingsFor(16, 16);
  FrameShading frame(r.scene, s.shadingOverride, (*embree)->anchor());
  Whitted whitted(r.scene, **embree, frame, TraceModes::reference(s));
  RayCounts counts;
  auto floorHit = [&](float x, float time) {
    Ray ray{toRenderSpace(glm::vec3(x, 0.5f, 0.3f), (*embree)->anchor()), glm::vec3(0.0f, -1.0f, 0.0f)};
    SurfaceHit h = resolveHit(r.scene, (*embree)->transformAt(r.floor, time), r.floor, 0, ray);
    h.time = time;
    return h;
  };
  EXPECT_EQ(whitted.lightMask(floorHit(-0.9f, 0.0f), counts), 0u) << "under the ball at the shutter's opening";
  EXPECT_EQ(whitted.lightMask(floorHit(-0.9f, 1.0f), counts), 1u) << "the ball has rolled on by its closing";
  EXPECT_EQ(whitted.lightMask(floorHit(0.9f, 1.0f), counts), 0u);
  // Batched (rtcOccluded packets) the same.
  ShadowBatch batch;
  LightMask masks[2] = {0, 0};
  masks[0] = static_cast<LightMask>(batch.add(whitted, 1, floorHit(-0.9f, 0.0f), 0));
  masks[1] = static_cast<LightMask>(batch.add(whitted, 1, floorHit(-0.9f, 1.0f), 1));
  batch.trace((*embree)->top(), masks, counts);
  EXPECT_EQ(masks[0], 0u);
  EXPECT_EQ(masks[1], 1u);
}

TEST(MotionBlurRays, ShutterAndMotionChangesReachTheSteps) {
  Rolling r = rolling();
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  auto embree = EmbreeScene::build(**device, r.scene);  // shutter closed: nothing moves
  ASSERT_TRUE(embree.ok());
  EXPECT_FALSE((*embree)->hasMotion());
  (*embree)->updateTransforms(r.scene, 0.5f);
  EXPECT_TRUE((*embree)->hasMotion());
  EXPECT_NE((*embree)->transformAt(r.ball, 1.0f).worldFromObject, (*embree)->transform(r.ball).worldFromObject);
  r.scene.instances[r.ball].velocity = glm::vec3(0.0f);
  r.scene.instances[r.ball].angularVelocity = glm::vec3(0.0f);
  (*embree)->updateTransforms(r.scene, 0.5f);
  EXPECT_FALSE((*embree)->hasMotion());
  EXPECT_EQ((*embree)->transformAt(r.ball, 1.0f).worldFromObject, (*embree)->transform(r.ball).worldFromObject);
  // A non-finite motion keeps the last one (per-frame code never fails), and the build refuses one.
  r.scene.instances[r.ball].velocity = glm::vec3(std::nanf(""), 0.0f, 0.0f);
  (*embree)->updateTransforms(r.scene, 0.5f);
  EXPECT_FALSE((*embree)->hasMotion());
  EXPECT_FALSE(EmbreeScene::build(**device, r.scene, 0.5f).ok());
}

// The floating origin (core/RenderSpace.h): a new anchor handed to updateTransforms re-reads every instance,
// still or moving, as a scene built at that anchor has it, to the bit, with the anchor the rays are given in;
// the same anchor again changes nothing.
TEST(MotionBlurRays, ANewAnchorReadsEveryInstanceAsABuildThereWould) {
  Rolling r = rolling();
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  auto moved = EmbreeScene::build(**device, r.scene, 0.5f);
  ASSERT_TRUE(moved.ok());
  EXPECT_EQ((*moved)->anchor(), r.scene.camera.posW);
  const glm::vec3 there(1234.5f, -67.25f, 89.0f);
  (*moved)->updateTransforms(r.scene, 0.5f, there);
  auto built = EmbreeScene::build(**device, r.scene, 0.5f, there);
  ASSERT_TRUE(built.ok());
  EXPECT_EQ((*moved)->anchor(), there);
  for (std::size_t i = 0; i < r.scene.instances.size(); ++i)
    for (const float u : {0.0f, 0.3f, 0.5f, 1.0f}) {
      EXPECT_EQ((*moved)->transformAt(i, u).worldFromObject, (*built)->transformAt(i, u).worldFromObject) << i << " " << u;
      EXPECT_EQ((*moved)->transformAt(i, u).anchor, there);
    }
  EXPECT_EQ((*moved)->transform(r.floor).worldFromObject, (*built)->transform(r.floor).worldFromObject);
  // The same ray (render space of `there`) meets the same triangle at the same distance in both.
  std::vector<float> distances;
  for (EmbreeScene* e : {moved->get(), built->get()}) {
    RTCRayHit hit{};
    const glm::vec3 from = toRenderSpace(glm::vec3(0.3f, 5.0f, 0.2f), there);
    hit.ray.org_x = from.x, hit.ray.org_y = from.y, hit.ray.org_z = from.z;
    hit.ray.dir_x = 0.0f, hit.ray.dir_y = -1.0f, hit.ray.dir_z = 0.0f;
    hit.ray.tnear = 0.0f, hit.ray.tfar = 1e30f, hit.ray.time = 0.5f, hit.ray.mask = ~0u;
    hit.hit.geomID = hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(e->top(), &context, &hit);
    EXPECT_EQ(hit.hit.instID[0], r.ball);
    distances.push_back(hit.ray.tfar);
  }
  EXPECT_EQ(distances[0], distances[1]);
  EXPECT_NEAR(distances[0], 5.0f - std::sqrt(1.0f - 0.09f - 0.04f) - 1.0f, 0.02f) << "the ball's top, near height 2";
  const glm::mat4 before = (*moved)->transform(r.ball).worldFromObject;
  (*moved)->updateTransforms(r.scene, 0.5f, there);
  EXPECT_EQ((*moved)->transform(r.ball).worldFromObject, before);
}

}  // namespace
}  // namespace tandem::rt
