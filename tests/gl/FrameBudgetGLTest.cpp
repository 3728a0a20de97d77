// The frame-time budget in the Renderer (FrameSettings::targetMs): it only chooses settings, so a budgeted
// frame must be, bit for bit, the frame those settings draw without a budget — the one FrameStats::budget
// reports. The decisions themselves are tested against a simulated machine (tests/unit/FrameBudgetTest.cpp);
// no test here depends on how fast this machine is, beyond a target no machine can meet.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "GlTestUtil.h"
#include "support/TestSupport.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

FrameSettings small(float targetMs) {
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = 320;
  s.height = 180;
  s.targetMs = targetMs;
  s.reuseRays = false;  // every frame traces, so every frame is measured
  return s;
}

Scene whitted() {
  auto s = loadDefaultScene();
  EXPECT_TRUE(s) << s.error().message;
  return std::move(*s);
}

/// area-lights.json: three area lights, a mirror and a glass ball (the ladder has the filter).
Scene areaLights() {
  auto s = loadSceneFile(test::sourceDir() + "/assets/scenes/area-lights.json");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
  return s.ok() ? *s : Scene{};
}

/// The settings the budget reports it drew, without a budget.
FrameSettings drawnWith(const BudgetStats& b) {
  FrameSettings s = small(0.0f);
  s.rayScale = b.rayScale;
  s.maxDepth = b.maxDepth;
  s.shadows = b.shadows;
  s.hybridShadows = b.hybridShadows;
  s.reflections = b.reflections;
  s.refraction = b.refraction;
  if (b.denoise) {
    s.denoise = true;
    s.lightSamples = s.glossSamples = 1;
  }
  return s;
}

TEST(FrameBudgetGL, AGenerousBudgetDrawsTheRequestedFrame) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = whitted();
  auto plain = gltest::makeRenderer(*glContext_);
  auto budgeted = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(plain && budgeted);
  ASSERT_TRUE(plain->setScene(scene).ok());
  ASSERT_TRUE(budgeted->setScene(scene).ok());
  const FrameStats p = plain->render(scene.camera, small(0.0f));
  EXPECT_FALSE(p.budget.active);
  EXPECT_EQ(describeBudget(p.budget), "");
  FrameStats b;
  for (int i = 0; i < 4; ++i) b = budgeted->render(scene.camera, small(1e4f));  // 10 s a frame: always fits
  EXPECT_TRUE(b.budget.active);
  EXPECT_EQ(b.budget.step, 0);
  EXPECT_GT(b.budget.steps, 10);
  EXPECT_TRUE(b.budget.reachable);
  // The cost model's prediction for the frame it drew is that frame's own cost, within the model's margin.
  EXPECT_GT(b.budget.predictedMs, 0.2 * b.totalMs);
  EXPECT_LT(b.budget.predictedMs, 5.0 * b.totalMs);
  EXPECT_EQ(describeBudget(b.budget), "as requested");
  EXPECT_EQ(plain->readImage().rgba, budgeted->readImage().rgba);
}

// Throughput mode learns a shown frame's cost from its own stages, not from its latency, which holds the next
// frame's raster and the application's time between the calls: an application that sleeps 300 ms between
// render() calls leaves the budget's prediction for its frames near what their stages cost (learnt from the
// latency, every prediction held the 300 ms). The call in PipelinedFrame.cpp, beside the unit test's model.
TEST(FrameBudgetGL, ThroughputModeLearnsNothingOfTheApplicationsTimeBetweenCalls) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = whitted();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r->setScene(scene).ok());
  FrameSettings s = small(1e4f);
  s.width = 96;
  s.height = 54;
  s.pipelined = true;
  constexpr double kSleepMs = 300.0;
  double stages = 0.0;  // the most a shown frame's own stages took
  FrameStats st;
  for (int i = 0; i < 7; ++i) {
    Camera c = scene.camera;
    c.posW.x += 0.01f * static_cast<float>(i);  // (every frame traces)
    st = r->render(c, s);
    ASSERT_TRUE(st.error.empty()) << st.error;
    if (st.samples > 0) stages = std::max(stages, st.stagesMs());
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(kSleepMs)));
  }
  ASSERT_TRUE(st.budget.active);
  ASSERT_GT(stages, 0.0);
  EXPECT_GT(st.totalMs, kSleepMs) << "the shown frame's latency holds the application's time";
  EXPECT_LT(st.budget.predictedMs, stages + 0.5 * kSleepMs)
      << "predicted " << st.budget.predictedMs << " ms; the frames' own stages took at most " << stages << " ms";
}

TEST(FrameBudgetGL, AnOutOfReachTargetDrawsExactlyTheChoiceItReports) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = whitted();
  auto budgeted = gltest::makeRenderer(*glContext_);
  auto plain = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(budgeted && plain);
  ASSERT_TRUE(budgeted->setScene(scene).ok());
  ASSERT_TRUE(plain->setScene(scene).ok());
  // 0.01 ms: no frame fits, so the budget walks down to its cheapest choice and says the target is out of reach.
  FrameStats b;
  int changes = 0, lastStep = 0;
  for (int i = 0; i < 8; ++i) {
    b = budgeted->render(scene.camera, small(0.01f));
    ASSERT_TRUE(b.error.empty()) << b.error;
    changes += b.budget.step != lastStep;
    lastStep = b.budget.step;
  }
  EXPECT_GT(b.budget.step, 0);
  EXPECT_FALSE(b.budget.reachable);
  EXPECT_LE(changes, 3) << "the cheapest choice is found in a few moves";
  // The reported choice, drawn without a budget by another renderer: the same frame to the bit.
  const FrameStats p = plain->render(scene.camera, drawnWith(b.budget));
  EXPECT_EQ(p.rays.total(), b.rays.total());
  EXPECT_EQ(plain->readImage().rgba, budgeted->readImage().rgba) << describeBudget(b.budget);
  // And it is not the requested frame: something was given up.
  const FrameStats full = plain->render(scene.camera, small(0.0f));
  EXPECT_GT(full.rays.total(), b.rays.total());
}

TEST(FrameBudgetGL, StillFramesReuseTheChoicesRaysAndPixelTracesSeeTheChoice) {
  // With reuse on and a still camera, a frame traces when the budget changed its choice and reuses the rays
  // otherwise; tracePixel re-runs the frame that was drawn, with the choice's settings.
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = whitted();
  auto r = gltest::makeRenderer(*glContext_);
  auto plain = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r && plain);
  ASSERT_TRUE(r->setScene(scene).ok());
  ASSERT_TRUE(plain->setScene(scene).ok());
  FrameSettings s = small(0.01f);
  s.reuseRays = true;
  // The camera moves for 8 frames (every frame traces: the budget learns and walks down), then stands still.
  FrameStats prev, b;
  int reused = 0, stillWithRays = 0;
  Camera camera = scene.camera;
  for (int i = 0; i < 14; ++i) {
    if (i < 8) camera.posW.x = scene.camera.posW.x + 1e-3f * static_cast<float>(i);
    b = r->render(camera, s);
    if (i < 8) {
      EXPECT_FALSE(b.raysReused) << "frame " << i << ": the camera moved";
    } else if (b.budget.step != prev.budget.step) {
      EXPECT_FALSE(b.raysReused) << "frame " << i << " changed choice";
    } else if (i > 8) {
      // Still camera, same choice: nothing is traced; a choice with a ray pass reuses its rays (one with
      // every effect by raster has none to reuse).
      EXPECT_EQ(b.rays.total(), 0u) << "frame " << i;
      const bool choiceTraces = prev.raysReused || prev.rays.total() > 0;
      EXPECT_EQ(b.raysReused, choiceTraces) << "frame " << i;
      reused += b.raysReused ? 1 : 0;
      stillWithRays += choiceTraces ? 1 : 0;
    }
    prev = b;
  }
  if (stillWithRays > 0) {
    EXPECT_GT(reused, 0);
  }
  ASSERT_GT(b.budget.step, 0);
  auto trace = r->tracePixel(160, 90);
  ASSERT_TRUE(trace) << trace.error().message;
  EXPECT_EQ(trace->settings.rayScale, b.budget.rayScale);
  EXPECT_EQ(trace->settings.maxDepth, b.budget.maxDepth);
  EXPECT_EQ(trace->settings.reflections, b.budget.reflections);
  (void)plain->render(camera, drawnWith(b.budget));
  EXPECT_EQ(plain->readImage().rgba, r->readImage().rgba) << describeBudget(b.budget);
}

// With area lights the ladder has the filter in place of the request's four samples: each frame says whether
// it was filtered, and the run, filtered frames and their history included, is the run its reported choices
// draw without a budget, to the bit. (Which choices an out-of-reach target walks through depends on this
// machine's costs; tests/unit/FrameBudgetTest.cpp checks that one that fits is taken.)
TEST(FrameBudgetGL, WithAreaLightsTheFilterIsAChoiceAndARunIsTheRunOfItsChoices) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = areaLights();
  ASSERT_FALSE(scene.lights.empty());
  auto budgeted = gltest::makeRenderer(*glContext_);
  auto plain = gltest::makeRenderer(*glContext_);
  auto noFilter = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(budgeted && plain && noFilter);
  ASSERT_TRUE(budgeted->setScene(scene).ok());
  ASSERT_TRUE(plain->setScene(scene).ok());
  ASSERT_TRUE(noFilter->setScene(scene).ok());
  // With one sample asked for, the filter would replace nothing: half the choices (but the filtered frames
  // with every effect by raster at 1/2 and 1/4, whose filter runs on the grid's pixels).
  FrameSettings one = small(1e4f);
  one.lightSamples = one.glossSamples = 1;
  const int withoutFilter = noFilter->render(scene.camera, one).budget.steps;
  std::vector<BudgetStats> drawn;
  Camera camera = scene.camera;
  FrameStats b;
  for (int i = 0; i < 10; ++i) {
    camera.posW.x = scene.camera.posW.x + 0.01f * static_cast<float>(i);  // in motion: the filter's history
    b = budgeted->render(camera, small(0.01f));
    ASSERT_TRUE(b.error.empty()) << b.error;
    EXPECT_EQ(b.denoised, b.budget.denoise) << "frame " << i << ": " << describeBudget(b.budget);
    drawn.push_back(b.budget);
  }
  EXPECT_EQ(b.budget.steps, 2 * withoutFilter + 2);
  EXPECT_GT(b.budget.step, 0);
  // (on the way down, the filtered frame with every effect by raster: it and its raw twin are predicted alike
  // before either is drawn, and the filtered one is expected nearer the truth)
  EXPECT_TRUE(std::any_of(drawn.begin(), drawn.end(), [](const BudgetStats& x) { return x.denoise; }));
  camera = scene.camera;
  FrameStats p;
  for (int i = 0; i < 10; ++i) {
    camera.posW.x = scene.camera.posW.x + 0.01f * static_cast<float>(i);
    p = plain->render(camera, drawnWith(drawn[static_cast<std::size_t>(i)]));
  }
  EXPECT_EQ(p.denoised, b.denoised);
  EXPECT_EQ(plain->readImage().rgba, budgeted->readImage().rgba) << describeBudget(b.budget);
}

// A frame without the filter releases it; under a budget that may take it again (the ladder has filtered
// choices) only its targets go and its programs stay, so going back costs no compile.
TEST(FrameBudgetGL, LeavingTheFilterUnderABudgetKeepsItsPrograms) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = areaLights();
  ASSERT_FALSE(scene.lights.empty());
  auto budgeted = gltest::makeRenderer(*glContext_);
  auto plain = gltest::makeRenderer(*glContext_);
  auto other = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(budgeted && plain && other);
  FrameSettings filtered = small(0.0f);
  filtered.denoise = true;
  filtered.lightSamples = filtered.glossSamples = 1;
  for (Renderer* r : {budgeted.get(), plain.get()}) {
    ASSERT_TRUE(r->setScene(scene).ok());
    EXPECT_TRUE(r->render(scene.camera, filtered).denoised);
  }
  // Then a raw frame each: the budget's first (its request; 10 s a frame always fits), and one without a budget.
  const FrameStats b = budgeted->render(scene.camera, small(1e4f));
  EXPECT_EQ(b.budget.step, 0);
  EXPECT_FALSE(b.denoised);
  EXPECT_FALSE(plain->render(scene.camera, small(0.0f)).denoised);
  // (the count is the process's: each renderer's own objects are what its destruction takes away)
  const std::size_t all = other->resources().glObjects;
  budgeted.reset();
  const std::size_t kept = all - other->resources().glObjects;
  plain.reset();
  const std::size_t released = all - kept - other->resources().glObjects;
  EXPECT_GT(kept, released);
  EXPECT_LT(kept, released + 12) << "its programs only, not its 14 targets and their framebuffers";
}

TEST(FrameBudgetGL, ANewSceneStartsFromTheRequest) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = whitted();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r);
  ASSERT_TRUE(r->setScene(scene).ok());
  FrameStats b;
  for (int i = 0; i < 6; ++i) b = r->render(scene.camera, small(0.01f));
  ASSERT_GT(b.budget.step, 0);
  ASSERT_TRUE(r->setScene(scene).ok());  // what was learned belonged to the old scene
  b = r->render(scene.camera, small(0.01f));
  EXPECT_EQ(b.budget.step, 0);
  EXPECT_EQ(b.budget.predictedMs, 0.0);
}

}  // namespace
}  // namespace tandem
