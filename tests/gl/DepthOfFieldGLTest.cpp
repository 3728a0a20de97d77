// Depth of field (Camera::aperture, focusDistance; docs/depth-of-field.md): the hybrid frame draws one lens
// point per sample as that point's pinhole, exact at its samples as any frame; its accumulation and the
// reference's lens rays converge to the same image; the lens centre is the pinhole; any thread count gives
// the same image.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "gl/GlTestUtil.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 90;

gltest::SceneFrame load(GlContext& context, int threads = 0) {
  gltest::SceneFrame f =
      gltest::sceneFrame(context, loadSceneFile(test::sourceDir() + "/assets/scenes/whitted.json"), kW, kH, threads);
  // Focused on the mirror sphere's front (the target is its centre), the glass sphere and the floor's far
  // rows well out of focus.
  f.camera.aperture = 0.35f;
  f.camera.focusDistance = 6.0f;
  return f;
}

TEST(DepthOfField, TheLensCentreIsThePinhole) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera pinhole = f.camera;
  pinhole.aperture = 0.0f;
  for (const char* name : {"hybrid-full", "raster", "reference"}) {
    // One frame without samples sees through the lens centre: the pinhole's image, bit for bit.
    EXPECT_TRUE(gltest::sameImage(gltest::drawFrame(f, gltest::presetFor(f, name)), gltest::drawFrame(f, pinhole, gltest::presetFor(f, name)))) << name;
  }
}

TEST(DepthOfField, ALensPointsFrameIsTheReferenceThroughThatPoint) {
  // The ray pass starts from each sample's exact hit: a hybrid frame through one lens point agrees with the
  // reference's lens rays from that point as closely as at the pinhole, and clearly not with the pinhole.
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera lens = f.camera;
  lens.lensUv = glm::vec2(0.92f, 0.15f);
  const Image hybrid = gltest::drawFrame(f, lens, gltest::presetFor(f, "hybrid-full"));
  const Image reference = gltest::drawFrame(f, lens, gltest::presetFor(f, "reference"));
  const Image pinholeReference = gltest::drawFrame(f, f.camera, gltest::presetFor(f, "reference"));
  const double same = gltest::flipMean(hybrid, reference), other = gltest::flipMean(hybrid, pinholeReference);
  std::printf("FLIP hybrid-full through lens point vs reference: same point %.5f, lens centre %.5f\n", same, other);
  EXPECT_LT(same, 0.004);
  EXPECT_GT(other, 3.0 * same);
}

TEST(DepthOfField, HybridAndReferenceConvergeToTheSameImage) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera pinhole = f.camera;
  pinhole.aperture = 0.0f;
  const gltest::Convergence c = gltest::converge(f, pinhole, "lens");
  const double hybrid64 = c.error64, referenceNoise = c.reference64;
  const Image& image64 = c.hybrid64;
  EXPECT_LT(hybrid64, 0.5 * c.withoutEffect) << "the lens must blur what the pinhole shows sharp";
  // The two estimators at 64 samples: equally near the converged image (raster vs ray primary hits apart).
  EXPECT_LT(hybrid64, referenceNoise + 0.006);
  // An accumulation over frames is the same supersampling spread out: 16 frames of 4 samples draw the very
  // lens points and sub-pixel offsets of 64 in one frame, in the same order.
  EXPECT_TRUE(gltest::sameImage(gltest::accumulateFrames(f, gltest::presetFor(f, "hybrid-full", 4), 16), image64));
}

TEST(DepthOfField, TheSameSamplesGiveTheSameImageOnAnyThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame one = load(*glContext_, 1), two = load(*glContext_, 2);
  gltest::expectSameOnAnyThreadCount(one, two);
}

}  // namespace
}  // namespace tandem
