// Motion blur (Instance::velocity, angularVelocity, Camera::shutter, timeU; docs/motion-blur.md): each hybrid
// sample draws the scene at one time of the shutter, the rasterizer and the rays agreeing on where moving
// instances are; its accumulation and the reference's rays with a time each converge to the same image; the
// middle of the shutter is the frame without motion; any thread count gives the same image.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "core/Motion.h"
#include "gl/GlTestUtil.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 90;
constexpr float kShutter = 0.25f;

// whitted.json with the box sliding and turning and the mirror sphere rising, during a quarter second.
Result<Scene> movingWhitted() {
  auto scene = loadSceneFile(test::sourceDir() + "/assets/scenes/whitted.json");
  if (!scene) return scene;
  for (Instance& inst : scene->instances) {
    if (inst.name == "matte-box") inst.velocity = glm::vec3(3.0f, 0.0f, 1.0f), inst.angularVelocity = glm::vec3(0.0f, 4.0f, 0.0f);
    if (inst.name == "mirror-sphere") inst.velocity = glm::vec3(0.0f, 2.0f, 0.0f);
  }
  scene->camera.shutter = kShutter;
  return scene;
}

gltest::SceneFrame load(GlContext& context, int threads = 0) {
  return gltest::sceneFrame(context, movingWhitted(), kW, kH, threads);
}

TEST(MotionBlur, ASampleShowsTheSceneWhereItsTimePutsIt) {
  // A frame at time 0.15 of the shutter against the scene with each moving instance placed where the exact
  // motion has it then (the steps' blend strays from it by under 1.6e-4 of the radius), shutter closed: the
  // GL copy, the raster shadows and the rays all moved it. (Raster reflections and refraction come from probes,
  // which show the middle of the shutter: the raster frame here has shadows only.)
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera at = f.camera;
  at.timeU = 0.15f;
  auto placed = movingWhitted();
  ASSERT_TRUE(placed.ok());
  for (Instance& inst : placed->instances) {
    inst.worldFromObject = glm::mat4(rigidMotionAt(inst, kShutter, 0.15));
    inst.velocity = inst.angularVelocity = glm::vec3(0.0f);
  }
  placed->camera.shutter = 0.0f;
  gltest::SceneFrame moved = gltest::sceneFrame(*glContext_, std::move(placed), kW, kH);
  for (const char* name : {"raster", "hybrid-full", "reference"}) {
    FrameSettings s = gltest::presetFor(f, name);
    if (s.shadows == EffectMode::Raster) s.reflections = s.refraction = EffectMode::Off;
    const Image sample = gltest::drawFrame(f, at, s);
    const double e = gltest::flipMean(sample, gltest::drawFrame(moved, s));
    const double still = gltest::flipMean(sample, gltest::drawFrame(f, s));
    std::printf("%s at time 0.15: FLIP vs the scene moved there %.6f, vs the middle of the shutter %.5f\n", name, e, still);
    EXPECT_LT(e, 0.001) << name;
    EXPECT_GT(still, 20.0 * e + 0.005) << name;
  }
}

TEST(MotionBlur, ASamplesHybridFrameIsTheReferenceAtThatTime) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera at = f.camera;
  at.timeU = 0.9f;
  const double same = gltest::flipMean(gltest::drawFrame(f, at, gltest::presetFor(f, "hybrid-full")), gltest::drawFrame(f, at, gltest::presetFor(f, "reference")));
  std::printf("FLIP hybrid-full vs reference, both at time 0.9: %.5f\n", same);
  EXPECT_LT(same, 0.004);
}

TEST(MotionBlur, HybridAndReferenceConvergeToTheSameImage) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera closed = f.camera;
  closed.shutter = 0.0f;
  const gltest::Convergence c = gltest::converge(f, closed, "time");
  const Image& truth = c.truth;
  EXPECT_LT(c.error64, 0.5 * c.withoutEffect) << "the motion must blur";
  EXPECT_LT(c.error64, c.reference64 + 0.006);
  // Raster frames (shadow maps drawn at each sample's time) converge near it too.
  const double raster = gltest::flipMean(gltest::drawFrame(f, gltest::presetFor(f, "raster", 64)), truth);
  const double rasterSharp = gltest::flipMean(gltest::drawFrame(f, closed, gltest::presetFor(f, "raster", 64)), truth);
  std::printf("raster, 64 samples: %.5f (without motion %.5f)\n", raster, rasterSharp);
  EXPECT_LT(raster, rasterSharp);
}

TEST(MotionBlur, TheSameSamplesGiveTheSameImageOnAnyThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame one = load(*glContext_, 1), two = load(*glContext_, 2);
  gltest::expectSameOnAnyThreadCount(one, two);
}

TEST(MotionBlur, TheProbesShowTheMiddleOfTheShutterWhicheverSampleDrewThem) {
  // Raster reflections and refraction come from probes drawn once: at the middle of the shutter, lit by shadow
  // maps of that time, so a frame does not depend on which time the probes happened to be drawn at.
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame earlier = load(*glContext_), fresh = load(*glContext_);
  Camera first = earlier.camera, second = earlier.camera;
  first.timeU = 0.2f;
  second.timeU = 0.7f;
  for (const char* name : {"raster", "hybrid-fast"}) {
    (void)gltest::drawFrame(earlier, first, gltest::presetFor(earlier, name));
    const Image after = gltest::drawFrame(earlier, second, gltest::presetFor(earlier, name));
    EXPECT_TRUE(gltest::sameImage(after, gltest::drawFrame(fresh, second, gltest::presetFor(fresh, name)))) << name;
  }
}

TEST(MotionBlur, NoRayIsKeptFromAFrameWhereSomethingMoved) {
  // Reuse across frames bounds instances at their transforms; a frame drawn at time 0.15 saw the box elsewhere.
  // Once it stops (its transform unchanged), the next frame must be the one traced whole.
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  auto stopped = movingWhitted();
  ASSERT_TRUE(stopped.ok());
  stopped->instances[3].velocity = stopped->instances[3].angularVelocity = glm::vec3(0.0f);
  gltest::SceneFrame still = gltest::sceneFrame(*glContext_, std::move(stopped), kW, kH);
  Camera at = f.camera;
  at.timeU = 0.15f;
  FrameSettings s = gltest::presetFor(f, "hybrid-fast");
  s.reuseRays = true;
  (void)gltest::drawFrame(f, at, s);
  f.renderer->setInstanceMotion(3, glm::vec3(0.0f), glm::vec3(0.0f));
  (void)gltest::drawFrame(f, at, s);
  (void)gltest::drawFrame(still, at, s);
  const ImageF a = f.renderer->readLinear(), b = still.renderer->readLinear();
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0);
}

TEST(MotionBlur, SetInstanceMotionStartsTheAccumulationAgain) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  FrameSettings acc = gltest::presetFor(f, "hybrid-fast");
  acc.accumulate = 8;
  FrameStats st;
  for (int i = 0; i < 3; ++i) st = f.renderer->render(f.camera, acc);
  EXPECT_EQ(st.accumulated, 3);
  const Image blurred = f.renderer->readImage();
  f.renderer->setInstanceMotion(3, glm::vec3(0.0f), glm::vec3(0.0f));  // the box stops
  st = f.renderer->render(f.camera, acc);
  EXPECT_EQ(st.accumulated, 1);
  for (int i = 0; i < 2; ++i) st = f.renderer->render(f.camera, acc);
  EXPECT_GT(gltest::flipMean(f.renderer->readImage(), blurred), 0.002);
  // A non-finite motion is refused: nothing changes, the accumulation goes on.
  f.renderer->setInstanceMotion(3, glm::vec3(std::nanf(""), 0.0f, 0.0f), glm::vec3(0.0f));
  st = f.renderer->render(f.camera, acc);
  EXPECT_EQ(st.accumulated, 4);
}

}  // namespace
}  // namespace tandem
