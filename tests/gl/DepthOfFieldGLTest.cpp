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

FrameSettings preset(const gltest::SceneFrame& f, const char* name, int samples = 1) {
  FrameSettings s = *presetSettings(name, f.base);
  if (samples > 1) {
    s.aa = AntiAlias::Ssaa;
    s.aaSamples = samples;
  }
  s.referenceSpp = 1;
  return s;
}

Image drawWith(gltest::SceneFrame& f, const Camera& camera, const FrameSettings& s) {
  FrameStats st = f.renderer->render(camera, s);
  EXPECT_TRUE(st.error.empty()) << st.error;
  return f.renderer->readImage();
}

bool sameImage(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba == b.rgba;
}

TEST(DepthOfField, TheLensCentreIsThePinhole) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera pinhole = f.camera;
  pinhole.aperture = 0.0f;
  for (const char* name : {"hybrid-full", "raster", "reference"}) {
    // One frame without samples sees through the lens centre: the pinhole's image, bit for bit.
    EXPECT_TRUE(sameImage(gltest::drawFrame(f, preset(f, name)), drawWith(f, pinhole, preset(f, name)))) << name;
  }
}

TEST(DepthOfField, ALensPointsFrameIsTheReferenceThroughThatPoint) {
  // The ray pass starts from each sample's exact hit: a hybrid frame through one lens point agrees with the
  // reference's lens rays from that point as closely as at the pinhole, and clearly not with the pinhole.
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  Camera lens = f.camera;
  lens.lensUv = glm::vec2(0.92f, 0.15f);
  const Image hybrid = drawWith(f, lens, preset(f, "hybrid-full"));
  const Image reference = drawWith(f, lens, preset(f, "reference"));
  const Image pinholeReference = drawWith(f, f.camera, preset(f, "reference"));
  const double same = gltest::flipMean(hybrid, reference), other = gltest::flipMean(hybrid, pinholeReference);
  std::printf("FLIP hybrid-full through lens point vs reference: same point %.5f, lens centre %.5f\n", same, other);
  EXPECT_LT(same, 0.004);
  EXPECT_GT(other, 3.0 * same);
}

TEST(DepthOfField, HybridAndReferenceConvergeToTheSameImage) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame f = load(*glContext_);
  FrameSettings truthSettings = preset(f, "reference");
  truthSettings.referenceSpp = 8;
  const Image truth = gltest::accumulateFrames(f, truthSettings, 4);  // 256 lens and pixel samples
  Camera pinhole = f.camera;
  pinhole.aperture = 0.0f;
  const double sharp = gltest::flipMean(drawWith(f, pinhole, preset(f, "hybrid-full", 16)), truth);
  double previous = 1.0;
  double hybrid64 = 1.0;
  Image image64;
  for (int samples : {4, 16, 64}) {
    image64 = gltest::drawFrame(f, preset(f, "hybrid-full", samples));
    const double e = gltest::flipMean(image64, truth);
    std::printf("hybrid-full, %d lens samples: FLIP vs reference %.5f\n", samples, e);
    EXPECT_LT(e, previous) << samples << " samples";
    previous = e;
    hybrid64 = e;
  }
  FrameSettings reference64 = preset(f, "reference");
  reference64.referenceSpp = 8;
  const double referenceNoise = gltest::flipMean(gltest::drawFrame(f, reference64), truth);
  std::printf("pinhole %.5f, reference 64 samples %.5f\n", sharp, referenceNoise);
  EXPECT_LT(hybrid64, 0.5 * sharp) << "the lens must blur what the pinhole shows sharp";
  // The two estimators at 64 samples: equally near the converged image (raster vs ray primary hits apart).
  EXPECT_LT(hybrid64, referenceNoise + 0.006);
  // An accumulation over frames is the same supersampling spread out: 16 frames of 4 samples draw the very
  // lens points and sub-pixel offsets of 64 in one frame, in the same order.
  EXPECT_TRUE(sameImage(gltest::accumulateFrames(f, preset(f, "hybrid-full", 4), 16), image64));
}

TEST(DepthOfField, TheSameSamplesGiveTheSameImageOnAnyThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  gltest::SceneFrame one = load(*glContext_, 1), two = load(*glContext_, 2);
  for (const char* name : {"hybrid-full", "hybrid-fast"}) {
    gltest::drawFrame(one, preset(one, name, 8));
    gltest::drawFrame(two, preset(two, name, 8));
    const ImageF a = one.renderer->readLinear(), b = two.renderer->readLinear();
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0) << name;
  }
  FrameSettings reference = preset(one, "reference");
  reference.referenceSpp = 3;
  gltest::drawFrame(one, reference);
  gltest::drawFrame(two, reference);
  const ImageF a = one.renderer->readLinear(), b = two.renderer->readLinear();
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0) << "reference";
}

}  // namespace
}  // namespace tandem
