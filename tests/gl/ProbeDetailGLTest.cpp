// The reflection probes' cost by what the frame can show (docs/shading.md, "Reflection probes"): objects that
// span few texels of a probe's face are drawn there with coarse copies of their meshes (GpuScene::ensureProbeLod),
// a mirror small on screen asks for less of its probe's detail than a large or flat one (gl::probeDetail), a
// probe drawn for less than a nearer camera needs is drawn again, and FrameSettings::probesPerFrame bounds the
// probes a new scene draws in one frame (the rest show the environment until their turn).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "GlTestUtil.h"
#include "gl/GpuScene.h"
#include "gl/RasterEffects.h"
#include "gl/ReflectionProbes.h"

namespace tandem {
namespace {

// A 3x3 grid of finely tessellated mirror balls among coloured ones on a floor, under a point light.
Scene mirrorsAmongColours() {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(40.0f), 1), makeSphere(1.0f, 64, 32)};
  Material mirror = gltest::plainMaterial(glm::vec3(0.05f));
  mirror.kr = 0.9f;
  s.materials = {gltest::plainMaterial(glm::vec3(0.7f)), mirror, gltest::plainMaterial({0.9f, 0.2f, 0.1f}),
                 gltest::plainMaterial({0.1f, 0.8f, 0.2f}), gltest::plainMaterial({0.2f, 0.3f, 0.9f})};
  s.instances = {Instance{}};
  for (int k = 0; k < 16; ++k) {
    Instance ball;
    ball.mesh = 1;
    const int x = k % 4, z = k / 4;
    ball.material = (x + z) % 2 == 0 ? 1u : static_cast<std::uint32_t>(2 + k % 3);
    ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(2.5f * float(x), 1.0f, 2.5f * float(z)));
    s.instances.push_back(ball);
  }
  s.lights[1].posW = {3.0f, 8.0f, 6.0f};
  // The render-space anchor where the tests' cameras stay within its reach (core/RenderSpace.h): a move of
  // the anchor would draw every probe again.
  s.camera.posW = {3.75f, 6.0f, 12.0f};
  s.camera.targetW = {3.75f, 1.0f, 3.75f};
  return s;
}

Camera looking(glm::vec3 from) {
  Camera c;
  c.posW = from;
  c.targetW = {3.75f, 1.0f, 3.75f};
  c.yFovDeg = 45.0f;
  return c;
}

FrameSettings rasterAt(int width, int height) {
  FrameSettings s = *presetSettings("raster");
  s.width = width;
  s.height = height;
  s.probeSize = 64;
  return s;
}

TEST(ProbeDetail, AMirrorSmallOnScreenAsksForLessThanAFlatOneOrGlass) {
  Scene s = mirrorsAmongColours();
  s.meshes.push_back(makePlane(glm::vec2(2.0f), 1));  // a flat mirror
  Instance flat;
  flat.mesh = 2;
  flat.material = 1;
  flat.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-4.0f, 0.5f, 0.0f));
  s.instances.push_back(flat);
  const std::vector<float> spread = gl::meshNormalSpread(s);
  EXPECT_NEAR(spread[1], glm::pi<float>(), 0.05f) << "a sphere's normals point every way";
  EXPECT_NEAR(spread[2], 0.0f, 1e-3f) << "a plane's one way";
  const gl::ProbeLayout layout = gl::probeLayout(s, 64);
  const std::vector<gl::Bounds> bounds = gl::instanceBounds(s, gl::meshBounds(s), glm::vec3(0.0f));
  auto detailOf = [&](const Scene& scene, const Camera& c, std::uint32_t instance, int height) {
    const std::vector<float> d = gl::probeDetail(scene, layout, bounds, spread, c, height, 64);
    return d[static_cast<std::size_t>(layout.slotOf[instance])];
  };
  const Camera far = looking({3.75f, 30.0f, 32.0f}), near = looking({3.75f, 3.0f, -3.0f});
  const float small = detailOf(s, far, 1, 180);
  EXPECT_LT(small, 0.15f) << "a mirror ball a few pixels wide";
  EXPECT_GT(detailOf(s, near, 1, 180), 2.0f * small) << "nearer, larger on screen";
  EXPECT_GT(detailOf(s, far, 1, 720), 2.0f * small) << "a larger frame";
  EXPECT_EQ(detailOf(s, far, static_cast<std::uint32_t>(s.instances.size() - 1), 180), 1.0f)
      << "a flat mirror shows its probe at the view's own scale";
  Scene glass = s;
  glass.materials[1].kt = 0.8f;
  EXPECT_EQ(detailOf(glass, far, 1, 180), 1.0f) << "what is seen through glass keeps the view's scale";
  Camera inside = far;
  inside.posW = glm::vec3(0.0f, 1.0f, 0.0f);  // within ball 1's bounds
  EXPECT_EQ(detailOf(s, inside, 1, 180), 1.0f);
  Camera ortho = far;
  ortho.orthographic = true;
  EXPECT_EQ(detailOf(s, ortho, 1, 180), 1.0f);
}

TEST(ProbeDetail, TheLevelOfDetailFollowsTheTexelsAnObjectSpans) {
  EXPECT_EQ(gl::probeLodLevel(1000.0f), 0);
  EXPECT_EQ(gl::probeLodLevel(2.0f * gl::kProbeLodCells[0] + 0.5f), 0);
  EXPECT_EQ(gl::probeLodLevel(2.0f * gl::kProbeLodCells[0]), 1);
  EXPECT_EQ(gl::probeLodLevel(2.0f * gl::kProbeLodCells[1] + 0.5f), 1);
  EXPECT_EQ(gl::probeLodLevel(2.0f * gl::kProbeLodCells[1]), 2);
  EXPECT_EQ(gl::probeLodLevel(0.0f), 2);
}

// Two renderers end at the far camera: one drew its probes for a near camera first (the detail a near view
// needs, kept when the camera backs away), the other for the far one (coarse copies for nearly everything). The
// two frames differ (the coarse copies were drawn) by little; brought near, the second draws its probes again
// and its frame is the first's near frame to the bit.
TEST(ProbeDetailGLTest, SmallMirrorsProbesAreDrawnCoarseAndAgainWhenTheCameraComesNear) {
  TD_REQUIRE_GL_CONTEXT();
  const FrameSettings s = rasterAt(320, 180);
  const Camera far = looking({3.75f, 30.0f, 32.0f}), near = looking({3.75f, 3.0f, -3.0f});
  gltest::SceneFrame fine = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), s.width, s.height);
  gltest::SceneFrame coarse = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), s.width, s.height);
  FrameStats st;
  const Image nearFine = gltest::drawFrame(fine, near, s, &st);
  EXPECT_EQ(st.probesDrawn, 8);
  const Image farFine = gltest::drawFrame(fine, far, s, &st);
  EXPECT_EQ(st.probesDrawn, 0) << "backing away needs no new probes";
  const Image farCoarse = gltest::drawFrame(coarse, far, s, &st);
  EXPECT_EQ(st.probesDrawn, 8);
  int differing = 0;
  for (std::size_t i = 0; i < farFine.rgba.size(); ++i) differing += farFine.rgba[i] != farCoarse.rgba[i] ? 1 : 0;
  EXPECT_GT(differing, 0) << "no coarse copy drawn";
  const double flip = gltest::flipMean(farCoarse, farFine);
  EXPECT_LT(flip, 5e-4) << "coarse copies where the mirrors show them a few pixels wide";
  gltest::savePng("probe-detail-far-coarse.png", farCoarse);
  gltest::savePng("probe-detail-far-fine.png", farFine);
  const Image nearAgain = gltest::drawFrame(coarse, near, s, &st);
  EXPECT_EQ(st.probesDrawn, 8) << "every mirror is now larger on screen than its probe was drawn for";
  EXPECT_EQ(nearAgain.rgba, nearFine.rgba);
  gltest::drawFrame(coarse, near, s, &st);
  EXPECT_EQ(st.probesDrawn, 0);
}

// FrameSettings::probesPerFrame on a new scene: each frame draws that many probes, the others show the
// environment (the background here) until then; once each has had its turn the frame is the one drawing them
// all at once gives, to the bit.
TEST(ProbeDetailGLTest, ANewScenesProbesArriveAFewAFrame) {
  TD_REQUIRE_GL_CONTEXT();
  FrameSettings all = rasterAt(320, 180), three = all;
  three.probesPerFrame = 3;
  const Camera c = looking({3.75f, 9.0f, 16.0f});
  gltest::SceneFrame exact = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), all.width, all.height);
  gltest::SceneFrame budgeted = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), all.width, all.height);
  FrameStats st;
  const Image truth = gltest::drawFrame(exact, c, all, &st);
  EXPECT_EQ(st.probesDrawn, 8);
  int drawn = 0;
  for (int frame = 0; frame < 3; ++frame) {
    SCOPED_TRACE("frame " + std::to_string(frame));
    const Image image = gltest::drawFrame(budgeted, c, three, &st);
    EXPECT_EQ(st.probes, 8);
    EXPECT_EQ(st.probesDrawn, std::min(3, 8 - drawn));
    drawn += st.probesDrawn;
    if (drawn < 8) {
      int differing = 0;
      for (std::size_t i = 0; i < truth.rgba.size(); ++i) differing += truth.rgba[i] != image.rgba[i] ? 1 : 0;
      EXPECT_GT(differing, 50) << "mirrors still showing the environment";
      if (frame == 0) gltest::savePng("probes-arriving-first-frame.png", image);
    } else {
      EXPECT_EQ(image.rgba, truth.rgba);
    }
  }
  gltest::drawFrame(budgeted, c, three, &st);
  EXPECT_EQ(st.probesDrawn, 0);
}

// The samples of an anti-aliased frame all see the same probes: a new scene's first sample draws every probe,
// whatever the budget, so the frame is the one a renderer without a budget draws, to the bit.
TEST(ProbeDetailGLTest, AnAntiAliasedFrameOfANewSceneDrawsEveryProbeInItsFirstSample) {
  TD_REQUIRE_GL_CONTEXT();
  FrameSettings all = rasterAt(160, 90), three = all;
  all.aa = three.aa = AntiAlias::Ssaa;
  all.aaSamples = three.aaSamples = 4;
  three.probesPerFrame = 3;
  const Camera c = looking({3.75f, 9.0f, 16.0f});
  gltest::SceneFrame exact = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), all.width, all.height);
  gltest::SceneFrame budgeted = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), all.width, all.height);
  FrameStats st;
  const Image truth = gltest::drawFrame(exact, c, all);
  const Image image = gltest::drawFrame(budgeted, c, three, &st);
  EXPECT_EQ(st.probesDrawn, 8);
  EXPECT_EQ(image.rgba, truth.rgba);
}

// A new shading override changes what every probe shows; under a budget they are drawn again a few a frame,
// the others keeping what they showed (not the environment a new scene's waiting probes show), and once each
// has had its turn the frame is the exact one.
TEST(ProbeDetailGLTest, AfterANewShadingOverrideTheProbesKeepWhatTheyShowedUntilTheirTurn) {
  TD_REQUIRE_GL_CONTEXT();
  FrameSettings three = rasterAt(320, 180);
  three.probesPerFrame = 3;
  const Camera c = looking({3.75f, 9.0f, 16.0f});
  gltest::SceneFrame f = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), three.width, three.height);
  for (int frame = 0; frame < 3; ++frame) gltest::drawFrame(f, c, three);
  FrameSettings flat = three;
  flat.shadingOverride = ShadingModel::Flat;
  // What the budget's first frame of a new scene shows under the override: three probes, the rest environment.
  gltest::SceneFrame fresh = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), three.width, three.height);
  const Image waiting = gltest::drawFrame(fresh, c, flat);
  FrameStats st;
  const Image kept = gltest::drawFrame(f, c, flat, &st);
  EXPECT_EQ(st.probesDrawn, 3);
  EXPECT_NE(kept.rgba, waiting.rgba) << "the other probes went to the environment";
  FrameSettings flatAll = flat;
  flatAll.probesPerFrame = 0;
  gltest::SceneFrame exact = gltest::sceneFrame(*glContext_, mirrorsAmongColours(), three.width, three.height);
  const Image truth = gltest::drawFrame(exact, c, flatAll);
  gltest::drawFrame(f, c, flat);
  const Image caught = gltest::drawFrame(f, c, flat, &st);
  EXPECT_EQ(st.probesDrawn, 2);
  EXPECT_EQ(caught.rgba, truth.rgba);
}

}  // namespace
}  // namespace tandem
