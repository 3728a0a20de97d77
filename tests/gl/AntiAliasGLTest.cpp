// Anti-aliasing and progressive accumulation (FrameSettings::aa, accumulate; docs/antialiasing.md): a
// jittered frame is exact at its sample points, supersampling converges to the supersampled reference,
// accumulation is supersampling spread over frames and starts again on any change, adaptive rounds refine
// only where samples disagree, and none of it depends on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/GlTestUtil.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Primitives.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 90;

struct Whitted {
  std::unique_ptr<Renderer> renderer;
  Camera camera;
  FrameSettings base;
};

Whitted whitted(GlContext& context, int threads = 0) {
  Whitted w;
  auto scene = loadSceneFile(test::sourceDir() + "/assets/scenes/whitted.json");
  if (!scene.ok()) gltest::endTest("whitted.json: " + scene.error().message);
  RendererDesc desc;
  desc.threads = threads;
  w.renderer = gltest::madeOrEnd(Renderer::create(context, desc));
  w.camera = scene->camera;
  w.base.width = kW;
  w.base.height = kH;
  if (scene->render.maxDepth >= 0) w.base.maxDepth = scene->render.maxDepth;
  EXPECT_TRUE(w.renderer->setScene(std::move(*scene)).ok());
  return w;
}

FrameSettings preset(const Whitted& w, const char* name, AntiAlias aa = AntiAlias::Off, int samples = 1) {
  FrameSettings s = *presetSettings(name, w.base);
  s.aa = aa;
  s.aaSamples = samples;
  s.referenceSpp = 1;
  return s;
}

Image draw(Whitted& w, const FrameSettings& s, const Camera& camera, FrameStats* stats = nullptr) {
  FrameStats st = w.renderer->render(camera, s);
  EXPECT_TRUE(st.error.empty()) << st.error;
  if (stats != nullptr) *stats = st;
  return w.renderer->readImage();
}

using gltest::flipMean;

bool sameLinear(const ImageF& a, const ImageF& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)) == 0;
}

TEST(AntiAlias, AJitteredFrameSeesWhatItsCameraRaysSee) {
  // The rasterizer, the shade pass and the ray pass all move by the jitter: the hybrid frame then agrees
  // with reference camera rays through the jittered points (as at the centres, HybridVsReferenceGLTest),
  // and clearly better than with rays through the centres.
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  Camera jittered = w.camera;
  jittered.jitterPx = glm::vec2(0.45f, -0.4f);
  const Image hybrid = draw(w, preset(w, "hybrid-full"), jittered);
  const Image referenceJittered = draw(w, preset(w, "reference"), jittered);
  const Image referenceCentred = draw(w, preset(w, "reference"), w.camera);
  const double same = flipMean(hybrid, referenceJittered), shifted = flipMean(hybrid, referenceCentred);
  std::printf("FLIP jittered hybrid-full vs reference: same jitter %.5f, no jitter %.5f\n", same, shifted);
  EXPECT_LT(same, 0.003);
  EXPECT_LT(same * 1.5, shifted) << "the jitter must move the frame as it moves the rays";
  // An orthographic camera moves its ray origins instead of their directions.
  Camera ortho = jittered;
  ortho.orthographic = true;
  ortho.orthoHeight = 6.0f;
  ortho.posW = ortho.targetW + 4.0f * (ortho.posW - ortho.targetW);  // back, clear of everything
  Camera orthoCentred = ortho;
  orthoCentred.jitterPx = glm::vec2(0.0f);
  const double orthoSame = flipMean(draw(w, preset(w, "hybrid-full"), ortho), draw(w, preset(w, "reference"), ortho));
  const double orthoShifted =
      flipMean(draw(w, preset(w, "hybrid-full"), ortho), draw(w, preset(w, "reference"), orthoCentred));
  const double orthoCentres = flipMean(draw(w, preset(w, "hybrid-full"), orthoCentred),
                                       draw(w, preset(w, "reference"), orthoCentred));
  std::printf("orthographic: same jitter %.5f, no jitter %.5f, both centred %.5f\n", orthoSame, orthoShifted,
              orthoCentres);
  // (Orthographic hybrid and reference frames differ by ~0.007 even at the centres: its finite depth range.)
  EXPECT_LT(orthoSame, 0.02);
  EXPECT_LT(orthoSame * 4.0, orthoShifted);
}

TEST(AntiAlias, AReferenceAccumulationKeepsEachSampleInItsPixel) {
  // Accumulated reference frames with spp × spp strata each: the jitter moves the strata within the pixel
  // (wrapped), so 4 frames of 2×2 are as sharp as one frame of 4×4 — a jitter added on top of the strata
  // would spread each pixel's samples over its neighbours (a blur a hybrid frame never has).
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  FrameSettings sixteen = preset(w, "reference");
  sixteen.referenceSpp = 4;
  const Image one = draw(w, sixteen, w.camera);
  FrameSettings four = preset(w, "reference");
  four.referenceSpp = 2;
  four.accumulate = 4;
  Image accumulated;
  for (int i = 0; i < 4; ++i) accumulated = draw(w, four, w.camera);
  FrameSettings truthSettings = preset(w, "reference");
  truthSettings.referenceSpp = 8;
  const Image truth = draw(w, truthSettings, w.camera);
  // Both are 16-sample estimates of the same box-filtered image: equally far from the 8×8 one.
  const double eAccumulated = flipMean(accumulated, truth), eOne = flipMean(one, truth);
  std::printf("FLIP vs reference 8x8: 4 frames of 2x2 %.5f, one frame of 4x4 %.5f\n", eAccumulated, eOne);
  EXPECT_LT(eAccumulated, 1.25 * eOne);
}

TEST(AntiAlias, AccumulationStartsAgainAfterALightChangeOrAResize) {
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  FrameSettings acc = preset(w, "hybrid-fast");
  acc.accumulate = 4;
  FrameStats st;
  for (int i = 0; i < 3; ++i) (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 3);
  std::uint32_t light = 0;
  while (w.renderer->scene().lights[light].type == LightType::Ambient) ++light;
  Light l = w.renderer->scene().lights[light];
  l.intensity *= 0.5f;
  w.renderer->setLight(light, l);
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 1) << "after a light changed";
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 2);
  ASSERT_TRUE(w.renderer->resize(kW * 2, kH * 2).ok());
  ASSERT_TRUE(w.renderer->resize(kW, kH).ok());
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 1) << "the targets its samples were in were made again";
  // tracePixel after an adaptive frame sees the frame's surfaces, not the pixels its last round skipped.
  FrameSettings adaptive = preset(w, "hybrid-full", AntiAlias::Adaptive, 8);
  (void)draw(w, adaptive, w.camera, &st);
  ASSERT_GT(st.refinedPixels, 0u);
  int surfaces = 0, pixels = 0;
  for (int y = kH / 2; y < kH; y += 7)
    for (int x = 0; x < kW; x += 7) {
      auto trace = w.renderer->tracePixel(x, y);
      ASSERT_TRUE(trace.ok()) << trace.error().message;
      ++pixels;
      surfaces += !trace->roots.empty() && trace->nodes[static_cast<std::size_t>(trace->roots.front())].hit ? 1 : 0;
    }
  EXPECT_EQ(surfaces, pixels) << "the floor fills the lower half";
}

TEST(AntiAlias, SupersamplingConvergesToTheSupersampledReference) {
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  FrameSettings truthSettings = preset(w, "reference");
  truthSettings.referenceSpp = 8;
  const Image truth = draw(w, truthSettings, w.camera);
  const double off = flipMean(draw(w, preset(w, "hybrid-full"), w.camera), truth);
  const Image four = draw(w, preset(w, "hybrid-full", AntiAlias::Ssaa, 4), w.camera);
  FrameStats st;
  const Image sixteen = draw(w, preset(w, "hybrid-full", AntiAlias::Ssaa, 16), w.camera, &st);
  const double e4 = flipMean(four, truth), e16 = flipMean(sixteen, truth);
  std::printf("FLIP hybrid-full vs reference 8x8 spp: off %.5f, ssaa 4 %.5f, ssaa 16 %.5f\n", off, e4, e16);
  EXPECT_EQ(st.samples, 16);
  EXPECT_EQ(st.accumulated, 16);
  EXPECT_LT(e4, 0.85 * off);
  EXPECT_LT(e16, e4);
  // The reference accumulated over the same 16 sub-pixel points sees the same samples.
  FrameSettings sameSamples = preset(w, "reference");
  sameSamples.accumulate = 16;
  Image referenceSixteen;
  for (int i = 0; i < 16; ++i) referenceSixteen = draw(w, sameSamples, w.camera);
  const double paired = flipMean(sixteen, referenceSixteen);
  std::printf("FLIP hybrid-full ssaa 16 vs reference over the same 16 points: %.5f\n", paired);
  EXPECT_LT(paired, 0.01);
  (void)writePng(test::outputDir() + "/antialias-off.png", draw(w, preset(w, "hybrid-full"), w.camera));
  (void)writePng(test::outputDir() + "/antialias-ssaa16.png", sixteen);
  (void)writePng(test::outputDir() + "/antialias-truth.png", truth);
}

TEST(AntiAlias, AccumulationIsSupersamplingSpreadOverFramesAndStartsAgainOnAnyChange) {
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  (void)draw(w, preset(w, "hybrid-fast", AntiAlias::Ssaa, 8), w.camera);
  const ImageF ssaa = w.renderer->readLinear();
  FrameSettings acc = preset(w, "hybrid-fast");
  acc.accumulate = 8;
  FrameStats st;
  for (int i = 0; i < 8; ++i) {
    (void)draw(w, acc, w.camera, &st);
    EXPECT_EQ(st.samples, 1) << "frame " << i;
    EXPECT_EQ(st.accumulated, i + 1) << "frame " << i;
  }
  const ImageF accumulated = w.renderer->readLinear();
  EXPECT_TRUE(sameLinear(accumulated, ssaa)) << "8 frames of 1 sample are ssaa 8, bit for bit";
  // Converged: the frame is shown again and draws nothing.
  const Image converged = w.renderer->readImage();
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.samples, 0);
  EXPECT_EQ(st.rays.total(), 0u);
  EXPECT_EQ(st.accumulated, 8);
  EXPECT_TRUE(w.renderer->readImage().rgba == converged.rgba);
  // Any change starts again: an instance moved, the camera moved, a setting changed.
  const Instance first = w.renderer->scene().instances.front();
  w.renderer->setInstanceTransform(0, glm::translate(first.worldFromObject, glm::vec3(0.01f, 0.0f, 0.0f)));
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 1) << "after a move";
  (void)draw(w, acc, w.camera, &st);
  EXPECT_EQ(st.accumulated, 2);
  Camera moved = w.camera;
  moved.posW.x += 0.01f;
  (void)draw(w, acc, moved, &st);
  EXPECT_EQ(st.accumulated, 1) << "after the camera moved";
  FrameSettings other = acc;
  other.exposure = 1.5f;
  (void)draw(w, other, moved, &st);
  EXPECT_EQ(st.accumulated, 1) << "after a setting changed";
}

TEST(AntiAlias, AdaptiveRefinesOnlyWhereSamplesDisagree) {
  TD_REQUIRE_GL_CONTEXT();
  Whitted w = whitted(*glContext_);
  const Image sixteen = draw(w, preset(w, "hybrid-full", AntiAlias::Ssaa, 16), w.camera);
  const Image four = draw(w, preset(w, "hybrid-full", AntiAlias::Ssaa, 4), w.camera);
  FrameStats st;
  const Image adaptive = draw(w, preset(w, "hybrid-full", AntiAlias::Adaptive, 16), w.camera, &st);
  const double eFour = flipMean(four, sixteen), eAdaptive = flipMean(adaptive, sixteen);
  const double share = static_cast<double>(st.refinedPixels) / (12.0 * kW * kH);
  std::printf("adaptive 16: refined %.1f%% of the pixel-samples ssaa 16 adds to ssaa 4; FLIP vs ssaa 16: "
              "adaptive %.5f, ssaa 4 %.5f\n", 100.0 * share, eAdaptive, eFour);
  EXPECT_EQ(st.accumulated, 16) << "edge pixels get every sample";
  EXPECT_GT(st.refinedPixels, 0u);
  EXPECT_LT(share, 0.6);
  EXPECT_LT(eAdaptive, 0.6 * eFour);
  // Rays go only to the refined pixels: fewer primary hits than a pixel per sample.
  EXPECT_LT(st.rays.primary, 4ull * kW * kH + st.refinedPixels + 1);
  // Where nothing disagrees (only sky in view) nothing is refined.
  Camera sky = w.camera;
  sky.targetW = sky.posW + glm::vec3(0.0f, 1.0f, -0.5f);
  (void)draw(w, preset(w, "hybrid-full", AntiAlias::Adaptive, 16), sky, &st);
  ASSERT_EQ(st.rays.primary, 0u) << "the view must hold only sky";
  EXPECT_EQ(st.samples, 4);
  EXPECT_EQ(st.refinedPixels, 0u);
}

TEST(AntiAlias, SamplesDoNotDependOnTheThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  Whitted one = whitted(*glContext_, 1);
  Whitted two = whitted(*glContext_, 2);
  for (AntiAlias aa : {AntiAlias::Ssaa, AntiAlias::Adaptive}) {
    (void)draw(one, preset(one, "hybrid-full", aa, 8), one.camera);
    (void)draw(two, preset(two, "hybrid-full", aa, 8), two.camera);
    EXPECT_TRUE(sameLinear(one.renderer->readLinear(), two.renderer->readLinear())) << toString(aa);
  }
}

TEST(AntiAlias, AdaptiveFindsAThinLineThatAPixelsFirstSamplesMiss) {
  // A white line a tenth of a pixel wide across a black frame, at a slant: the first four samples of a pixel
  // (a 4-rooks pattern) catch it in some pixels along it and miss it in others. Those that missed it agree
  // (all black), but a neighbour's samples disagree, so adaptive rounds sample them too: there they are the
  // 16-sample supersampled image, sample for sample.
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  const float pixel = 2.0f * 10.0f * std::tan(glm::radians(15.0f)) / static_cast<float>(kH);  // at the line's distance
  scene.meshes.push_back(makeBox({40.0f, 0.1f * pixel, 0.1f * pixel}));
  Material white;
  white.unlit = true;
  white.kd = glm::vec3(1.0f);
  scene.materials.push_back(white);
  Instance line;
  line.mesh = 0;
  line.material = 0;
  line.worldFromObject = glm::rotate(glm::mat4(1.0f), std::atan(0.3f), glm::vec3(0.0f, 0.0f, 1.0f));
  scene.instances.push_back(line);
  scene.background = glm::vec3(0.0f);
  scene.camera.posW = {0.0f, 0.0f, 10.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  scene.camera.yFovDeg = 30.0f;
  Whitted w;
  w.camera = scene.camera;
  w.base.width = kW;
  w.base.height = kH;
  auto renderer = Renderer::create(*glContext_, RendererDesc{});
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  w.renderer = std::move(*renderer);
  ASSERT_TRUE(w.renderer->setScene(std::move(scene)).ok());
  const Image four = draw(w, preset(w, "raster", AntiAlias::Ssaa, 4), w.camera);
  const Image sixteen = draw(w, preset(w, "raster", AntiAlias::Ssaa, 16), w.camera);
  FrameStats st;
  const Image adaptive = draw(w, preset(w, "raster", AntiAlias::Adaptive, 16), w.camera, &st);
  auto at = [&](const Image& im, int x, int y) { return im.rgba[(static_cast<std::size_t>(y) * kW + x) * 4]; };
  int missed = 0, besideACatch = 0, seen = 0, differ = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      seen += at(sixteen, x, y) > 0;
      if (at(four, x, y) > 0 || at(sixteen, x, y) == 0) continue;
      ++missed;  // the line crosses this pixel; its first four samples all missed it
      bool neighbourCaught = false;  // a neighbour's first four samples caught it (and so disagree)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (x + dx >= 0 && x + dx < kW && y + dy >= 0 && y + dy < kH) neighbourCaught |= at(four, x + dx, y + dy) > 0;
      if (!neighbourCaught) continue;
      ++besideACatch;
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * 4 + static_cast<std::size_t>(c);
        differ += std::abs(int(adaptive.rgba[i]) - int(sixteen.rgba[i])) > 1 ? 1 : 0;
      }
    }
  std::printf("thin line: %d pixels show it with 16 samples, %d missed by their first 4, %d of those beside a pixel "
              "whose first 4 caught it; adaptive refined %llu pixel-samples\n",
              seen, missed, besideACatch, static_cast<unsigned long long>(st.refinedPixels));
  ASSERT_GT(besideACatch, 20) << "the scene must have pixels whose first samples miss the line beside some that catch it";
  EXPECT_EQ(differ, 0) << "a pixel whose first four samples missed the line, beside one whose caught it, is not the "
                          "16-sample image";
  EXPECT_LT(st.refinedPixels, 12ull * kW * kH / 4) << "refined far beyond the line";
}

}  // namespace
}  // namespace tandem
