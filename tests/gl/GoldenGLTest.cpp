// Golden images of the default (Whitted) scene: one per shading model with every effect off, and one per
// preset; and of assets/scenes/area-lights.json and glossy.json (soft shadows and glossy rays at the default
// 4 samples, first sample of the sequence: the same seed gives the same image), and distribution.json (all of
// them with depth of field and motion blur, 8 anti-aliasing, lens and time samples in one frame), the
// Cornell box (hybrid-full, and the path-traced reference at 2×2 spp), and csg.json (raster and hybrid-full).
// Every golden is compared alike (tests/support/Goldens.h, tests/golden/README.md): at most 0.1 % of pixels more
// than 2 levels off and each channel's mean within 0.25 of a level — what a GPU driver's rounding stays within
// and what flat shading, Schlick's Fresnel, one bounce less or a shifted tone map each break (tested below).
// Regenerate (and look at every changed image): cmake --build build --target update-goldens.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "gl/GlTestUtil.h"
#include "support/Goldens.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 180;

// The frame `settings` draws of the default scene or of assets/scenes/<sceneFile>.
Image renderFrame(GlContext& context, const FrameSettings& settings, const std::string& sceneFile) {
  auto scene = sceneFile.empty() ? loadDefaultScene() : loadSceneFile(test::sourceDir() + "/assets/scenes/" + sceneFile);
  EXPECT_TRUE(scene.ok()) << scene.error().message;
  if (!scene.ok()) return {};
  Camera camera = scene->camera;
  auto renderer = gltest::makeRenderer(context);
  EXPECT_NE(renderer, nullptr);
  if (!renderer || !renderer->setScene(std::move(*scene)).ok()) return {};
  const FrameStats stats = renderer->render(camera, settings);
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  return renderer->readImage();
}

Result<Image> readGolden(const std::string& name) {
  return readPng(test::sourceDir() + "/tests/golden/" + name + ".png");
}

void checkGolden(const std::string& name, const FrameSettings& settings, bool rayTraced,
                 const std::string& sceneFile = "") {
  TD_REQUIRE_GL_CONTEXT();
  (void)rayTraced;  // every golden is judged alike; the flag names what the frame holds
  Image image = renderFrame(*glContext_, settings, sceneFile);
  ASSERT_GT(image.width, 0);
  gltest::savePng("golden-" + name + ".png", image);

  std::string path = test::sourceDir() + "/tests/golden/" + name + ".png";
  ASSERT_EQ(test::strayGoldenUpdate(), "");
  if (test::updatingGoldens()) {
    ASSERT_TRUE(writePng(path, image).ok());
    GTEST_SKIP() << "golden updated: " << path;
  }
  auto golden = readPng(path);
  ASSERT_TRUE(golden.ok()) << golden.error().message << " (regenerate: cmake --build build --target update-goldens)";
  ASSERT_EQ(golden->width, image.width);
  ASSERT_EQ(golden->height, image.height);

  const test::GoldenDiff diff = test::compareToGolden(image, *golden);
  auto f = flip(image, *golden);
  ASSERT_TRUE(f.ok());
  std::printf("%s: %.3f %% of pixels over 2 levels (largest %d), mean shift %.3f %.3f %.3f levels, FLIP %.5f\n",
              name.c_str(), 100.0 * diff.fractionOver, diff.maxDiff, diff.meanSigned.x, diff.meanSigned.y,
              diff.meanSigned.z, f->mean);
  EXPECT_EQ(test::goldenMismatch(diff), "") << name << " against its golden";
}

FrameSettings effectsOff(ShadingModel model) {
  FrameSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.shadows = s.reflections = s.refraction = EffectMode::Off;
  s.shadingOverride = model;
  return s;
}

FrameSettings preset(const char* name) {
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  return *presetSettings(name, base);
}

TEST(Golden, WhittedFlat) { checkGolden("whitted-flat", effectsOff(ShadingModel::Flat), false); }
TEST(Golden, WhittedGouraud) { checkGolden("whitted-gouraud", effectsOff(ShadingModel::Gouraud), false); }
TEST(Golden, WhittedPhong) { checkGolden("whitted-phong", effectsOff(ShadingModel::Phong), false); }
TEST(Golden, WhittedToon) { checkGolden("whitted-toon", effectsOff(ShadingModel::Toon), false); }
TEST(Golden, WhittedPresetRaster) { checkGolden("whitted-preset-raster", preset("raster"), false); }
TEST(Golden, WhittedPresetHybridFast) { checkGolden("whitted-preset-hybrid-fast", preset("hybrid-fast"), true); }
TEST(Golden, WhittedPresetHybridFull) { checkGolden("whitted-preset-hybrid-full", preset("hybrid-full"), true); }
TEST(Golden, AreaLightsRaster) { checkGolden("area-lights-raster", preset("raster"), false, "area-lights.json"); }
TEST(Golden, AreaLightsHybridFull) {
  checkGolden("area-lights-hybrid-full", preset("hybrid-full"), true, "area-lights.json");
}
TEST(Golden, GlossyRaster) { checkGolden("glossy-raster", preset("raster"), false, "glossy.json"); }
TEST(Golden, GlossyHybridFull) { checkGolden("glossy-hybrid-full", preset("hybrid-full"), true, "glossy.json"); }

FrameSettings supersampled(const char* name, int samples) {
  FrameSettings s = preset(name);
  s.aa = AntiAlias::Ssaa;
  s.aaSamples = samples;
  return s;
}
TEST(Golden, DistributionRaster) {
  checkGolden("distribution-raster", supersampled("raster", 8), false, "distribution.json");
}
TEST(Golden, DistributionHybridFull) {
  checkGolden("distribution-hybrid-full", supersampled("hybrid-full", 8), true, "distribution.json");
}
TEST(Golden, CornellBoxPathTraced) {
  FrameSettings s = preset("reference");
  s.gi = GlobalIllumination::Path;
  s.referenceSpp = 2;
  checkGolden("cornell-box-path", s, true, "cornell-box.json");
}
TEST(Golden, CornellBoxHybridFull) { checkGolden("cornell-box-hybrid-full", preset("hybrid-full"), true, "cornell-box.json"); }
TEST(Golden, CornellBoxRadiosity) {
  // The two-pass frame: the radiosity solution (1024 patches, to 1 % unshot) in place of the ambient term.
  FrameSettings s = preset("hybrid-full");
  s.radiosity = true;
  s.radiosityPatches = 1024;
  checkGolden("cornell-box-radiosity", s, true, "cornell-box.json");
}

// Exact solids, CSG and procedural textures (docs/csg.md, docs/procedural.md): the proxies' pixels resolved by
// ray in both; raster shadows and probes from the proxies, the rest exact.
TEST(Golden, CsgRaster) { checkGolden("csg-raster", preset("raster"), false, "csg.json"); }
TEST(Golden, CsgHybridFull) { checkGolden("csg-hybrid-full", preset("hybrid-full"), true, "csg.json"); }

// ---- the comparison itself: it must pass a GPU driver's rounding and catch what tests/golden/README.md says ----

// The golden with one level taken off or added to a share of its values (deterministic), as a GPU driver's
// rounding does: NVIDIA's H100 frame of 2026-11-27 had 1.9 % of values one level lower, none further.
Image roundedElsewhere(Image im, double share, int sign) {
  std::uint32_t s = 0x9e3779b9u;
  for (std::size_t i = 0; i < im.rgba.size(); ++i) {
    if (i % 4 == 3) continue;
    s = s * 1664525u + 1013904223u;
    if (static_cast<double>(s >> 8) / 16777216.0 >= share) continue;
    const int v = int(im.rgba[i]) + (sign != 0 ? sign : ((s >> 3) & 1u ? 1 : -1));
    im.rgba[i] = static_cast<std::uint8_t>(std::clamp(v, 0, 255));
  }
  return im;
}

TEST(GoldenComparison, PassesADriversRoundingAndCatchesWhatAGoldenMust) {
  TD_REQUIRE_GL_CONTEXT();
  auto full = readGolden("whitted-preset-hybrid-full"), fast = readGolden("whitted-preset-hybrid-fast");
  ASSERT_TRUE(full.ok() && fast.ok());
  // A driver's rounding: one level either way on 10 % of the values, or down on 5 % (over twice what the H100
  // showed), passes; so does the H100's own frame where ../shared has it.
  EXPECT_EQ(test::goldenMismatch(test::compareToGolden(roundedElsewhere(*full, 0.10, 0), *full)), "");
  EXPECT_EQ(test::goldenMismatch(test::compareToGolden(roundedElsewhere(*full, 0.05, -1), *full)), "");
  const std::string h100 = test::sourceDir() + "/../shared/docs/gpu-runs/2026-11-27/whitted-hybrid-full-320x180-nvidia.png";
  if (std::filesystem::exists(h100)) {
    auto nvidia = readPng(h100);
    ASSERT_TRUE(nvidia.ok());
    EXPECT_EQ(test::goldenMismatch(test::compareToGolden(*nvidia, *full)), "") << "the H100's frame of 2026-11-27";
  }
  // Every value a level brighter (an exposure or tone-map constant a little off) fails.
  EXPECT_NE(test::goldenMismatch(test::compareToGolden(roundedElsewhere(*full, 1.0, +1), *full)), "");
  // What tests/golden/README.md says the goldens must catch, drawn for real: each fails.
  FrameSettings flat = preset("hybrid-full");
  flat.shadingOverride = ShadingModel::Flat;
  const std::string flatWhy = test::goldenMismatch(test::compareToGolden(renderFrame(*glContext_, flat, ""), *full));
  EXPECT_NE(flatWhy, "") << "flat shading forced passed the hybrid-full golden";
  FrameSettings schlick = preset("hybrid-full");
  schlick.fresnel = FresnelMode::Schlick;
  const std::string schlickWhy = test::goldenMismatch(test::compareToGolden(renderFrame(*glContext_, schlick, ""), *full));
  EXPECT_NE(schlickWhy, "") << "Schlick's Fresnel passed the hybrid-full golden";
  FrameSettings shallow = preset("hybrid-fast");
  shallow.maxDepth -= 1;
  const std::string shallowWhy = test::goldenMismatch(test::compareToGolden(renderFrame(*glContext_, shallow, ""), *fast));
  EXPECT_NE(shallowWhy, "") << "one bounce less passed the hybrid-fast golden";
  std::printf("caught: flat shading: %s\nSchlick: %s\none bounce less: %s\n", flatWhy.c_str(), schlickWhy.c_str(),
              shallowWhy.c_str());
}

}  // namespace
}  // namespace tandem
