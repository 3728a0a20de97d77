// The GL side far from the origin: the Whitted scene moved 1e6 units (along an axis and along the
// diagonal) must render as the same float-rounded scene moved back to the origin, for the raster and the
// hybrid-full presets. Raster, shade, shadow maps and probes work in render space (world − anchor,
// subtracted in double on the CPU), as the ray pass does; world floats lost 0.06 units at 1e6
// (silhouettes, torn refraction, shadow-map acne). 1e7 is measured and printed (docs/numerics.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "GlTestUtil.h"
#include "support/SceneTransform.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 320, kH = 180;
// FLIP between the far render and the render of the same float-rounded scene at the origin; lost shadows,
// acne or torn refraction give 0.02 and more (0.022 hybrid-full, 0.080 raster before render space).
constexpr double kFlipSameScene = 0.005;

Image renderScene(const Scene& scene, const char* preset) {
  std::string error;
  GlContext* context = gltest::sharedContext(error);
  EXPECT_NE(context, nullptr) << error;
  if (!context) return {};
  auto renderer = gltest::makeRenderer(*context);
  EXPECT_TRUE(renderer);
  if (!renderer) return {};
  EXPECT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s = *presetSettings(preset);
  s.width = kW;
  s.height = kH;
  renderer->render(scene.camera, s);
  return renderer->readImage();
}

// FLIP of `preset` at `offset` against the origin copy of the same float-rounded scene.
double flipAtOffset(glm::dvec3 offset, const char* preset, const std::string& name) {
  auto loaded = loadDefaultScene();
  EXPECT_TRUE(loaded);
  Scene far = *loaded;
  transformScene(far, 1.0, offset);
  Scene home = far;
  transformScene(home, 1.0, -offset);
  const Image a = renderScene(far, preset), b = renderScene(home, preset);
  gltest::savePng("far-" + name + "-" + preset + ".png", a);
  gltest::savePng("far-" + name + "-" + preset + "-home.png", b);
  auto f = flip(a, b);
  EXPECT_TRUE(f) << (f ? "" : f.error().message);
  return f ? f->mean : 1.0;
}

struct Case {
  const char* name;
  glm::dvec3 offset;
  const char* preset;
};

class FarFromOrigin : public ::testing::TestWithParam<Case> {};

TEST_P(FarFromOrigin, RendersAsTheSameSceneAtTheOrigin) {
  TD_REQUIRE_GL_CONTEXT();
  const Case c = GetParam();
  const double f = flipAtOffset(c.offset, c.preset, c.name);
  std::printf("[far] %s %s: FLIP %.5f against the origin copy\n", c.name, c.preset, f);
  EXPECT_LT(f, kFlipSameScene) << c.name << " " << c.preset;
}

const double kDiag = 1e6 / std::sqrt(3.0);
INSTANTIATE_TEST_SUITE_P(Presets, FarFromOrigin,
                         ::testing::Values(Case{"x1e6", {1e6, 0, 0}, "raster"}, Case{"x1e6", {1e6, 0, 0}, "hybrid-full"},
                                           Case{"diag1e6", {kDiag, kDiag, kDiag}, "raster"},
                                           Case{"diag1e6", {kDiag, kDiag, kDiag}, "hybrid-full"}),
                         [](const ::testing::TestParamInfo<Case>& p) {
                           return std::string(p.param.name) + "_" +
                                  (std::string(p.param.preset) == "raster" ? "raster" : "hybridFull");
                         });

TEST(FarFromOrigin, TenMillionIsMeasured) {
  // The documented limit: at 1e7 a float places the input only to 1 unit, but what is placed renders as at
  // the origin. Printed for docs/numerics.md; held to the same bound.
  TD_REQUIRE_GL_CONTEXT();
  const double d = 1e7 / std::sqrt(3.0);
  for (const char* preset : {"raster", "hybrid-full"}) {
    const double f = flipAtOffset({d, d, d}, preset, "diag1e7");
    std::printf("[far] diag1e7 %s: FLIP %.5f against the origin copy\n", preset, f);
    EXPECT_LT(f, kFlipSameScene) << preset;
  }
}

}  // namespace
}  // namespace tandem
