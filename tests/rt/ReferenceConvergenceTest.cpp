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

TEST(ReferenceConvergence, TheReferenceMeetsClosedFormsNotJustItself) {
  // Convergence compares the reference with itself; this holds it to answers worked out here. A matte floor
  // under a directional light at 30° from its normal and an ambient light, no shadows to cast: every floor pixel
  // is ka·Ia + kd·E·cos 30° at any sample count; a mirror floor (kr 0.5, no kd) under a sky-blue background shows
  // ka·Ia + 0.5·background exactly (its reflected rays all escape).
  for (bool mirror : {false, true}) {
    Scene scene;
    Material m = diffuse(glm::vec3(0.6f, 0.5f, 0.4f));
    m.ka = glm::vec3(0.2f, 0.3f, 0.4f);
    if (mirror) {
      m.kd = glm::vec3(0.0f);
      m.kr = 0.5f;
    }
    addInstance(scene, addMesh(scene, makePlane({40.0f, 40.0f}, 1)), addMaterial(scene, m), glm::mat4(1.0f));
    scene.lights.push_back(ambientLight(0.5f));
    const double theta = 3.14159265358979 / 6;
    scene.lights.push_back(directional({static_cast<float>(std::sin(theta)), static_cast<float>(-std::cos(theta)), 0.0f}, 1.5f));
    scene.background = glm::vec3(0.3f, 0.6f, 0.9f);
    scene.camera.posW = {0.0f, 3.0f, 3.0f};
    scene.camera.targetW = {0.0f, 0.0f, 0.0f};
    auto tracer = makeTracer(scene);
    ASSERT_TRUE(tracer);
    FrameSettings s = *presetSettings("reference", settingsFor(64, 48));
    s.referenceSpp = 2;
    ImageF out;
    RayCounts counts;
    tracer->renderReference(scene, scene.camera, s, out, counts);
    int floorPixels = 0;
    for (const glm::vec3& c : out.rgb) {
      if (c == scene.background) continue;  // the sky above the horizon
      ++floorPixels;
      for (int k = 0; k < 3; ++k) {
        const double want = m.ka[k] * 0.5 + (mirror ? 0.5 * scene.background[k] : m.kd[k] * 1.5 * std::cos(theta));
        ASSERT_NEAR(c[k], want, 1e-5) << (mirror ? "mirror" : "matte") << " channel " << k;
      }
    }
    EXPECT_GT(floorPixels, 64 * 48 / 2);
    EXPECT_EQ(counts.primary, 64u * 48u * 4u);
  }
}

}  // namespace
}  // namespace tandem::rt
