// The reference tracer converges (docs/measuring.md): on whitted.json the error between 8×8 and 16×16
// samples per pixel is smaller than between 4×4 and 8×8. Images are tone-mapped on the CPU exactly as the
// GL tone-map pass does (exposure, tone map, sRGB encode), so FLIP sees what a user would.
#include <cmath>

#include <gtest/gtest.h>

#include "core/Shading.h"
#include "rt/RtTestScenes.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

Image toDisplay(const ImageF& linear, const FrameSettings& s) {
  Image out;
  out.width = linear.width;
  out.height = linear.height;
  out.rgba.resize(static_cast<std::size_t>(linear.width) * static_cast<std::size_t>(linear.height) * 4);
  for (std::size_t i = 0; i < linear.rgb.size(); ++i) {
    glm::vec3 c = shading::tdSrgbEncode(shading::tdToneMap(s.exposure * linear.rgb[i], shading::toneMapOp(s.toneMap)));
    for (int k = 0; k < 3; ++k)
      out.rgba[i * 4 + static_cast<std::size_t>(k)] =
          static_cast<std::uint8_t>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    out.rgba[i * 4 + 3] = 255;
  }
  return out;
}

TEST(ReferenceConvergence, ErrorShrinksFromFourToEightToSixteenSpp) {
  auto scene = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/whitted.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto tracer = makeTracer(*scene);
  ASSERT_TRUE(tracer);
  FrameSettings s = *presetSettings("reference", settingsFor(160, 90));
  if (scene->render.maxDepth >= 0) s.maxDepth = scene->render.maxDepth;
  Image images[3];
  const int spps[3] = {4, 8, 16};
  for (int i = 0; i < 3; ++i) {
    s.referenceSpp = spps[i];
    ImageF linear;
    RayCounts counts;
    tracer->renderReference(*scene, scene->camera, s, linear, counts);
    ASSERT_EQ(counts.primary, 160u * 90u * static_cast<std::uint64_t>(spps[i] * spps[i]));
    images[i] = toDisplay(linear, s);
  }
  auto coarse = flip(images[0], images[1]);  // 4×4 vs 8×8
  auto fine = flip(images[1], images[2]);    // 8×8 vs 16×16
  ASSERT_TRUE(coarse.ok() && fine.ok());
  std::printf("FLIP mean: 4x4 vs 8x8 %.5f, 8x8 vs 16x16 %.5f\n", coarse->mean, fine->mean);
  EXPECT_GT(coarse->mean, 0.0) << "supersampling changed nothing: the jitter is not reaching the image";
  EXPECT_LT(fine->mean, coarse->mean);
  auto p1 = psnr(images[0], images[1]), p2 = psnr(images[1], images[2]);
  ASSERT_TRUE(p1.ok() && p2.ok());
  EXPECT_GT(*p2, *p1);
}

}  // namespace
}  // namespace tandem::rt
