// At 1 sample per pixel the reference tracer's camera ray goes through the pixel centre, the point the
// rasterizer samples: hybrid-full (raster visibility + ray pass) and the reference (camera rays) see the
// same surfaces and must agree to a FLIP mean under 0.01 on whitted.json (the reference is only a
// yardstick for the other presets, docs/bench.md, if it sees what they see).
#include <gtest/gtest.h>

#include "gl/GlTestUtil.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

TEST(HybridVsReference, OneSppReferenceMatchesHybridFullOnWhitted) {
  TD_REQUIRE_GL_CONTEXT();
  auto scene = loadSceneFile(test::sourceDir() + "/assets/scenes/whitted.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto renderer = Renderer::create(*glContext_);
  ASSERT_TRUE(renderer.ok()) << renderer.error().message;
  Camera camera = scene->camera;
  int maxDepth = scene->render.maxDepth;
  ASSERT_TRUE((*renderer)->setScene(std::move(*scene)).ok());

  FrameSettings base;
  base.width = 320;
  base.height = 180;
  if (maxDepth >= 0) base.maxDepth = maxDepth;
  FrameSettings hybrid = *presetSettings("hybrid-full", base);
  FrameSettings reference = *presetSettings("reference", base);
  reference.referenceSpp = 1;

  FrameStats hs = (*renderer)->render(camera, hybrid);
  Image hybridImage = (*renderer)->readImage();
  FrameStats rs = (*renderer)->render(camera, reference);
  Image referenceImage = (*renderer)->readImage();
  EXPECT_EQ(rs.rays.primary, 320u * 180u) << "one camera ray per pixel";
  EXPECT_GT(hs.rays.reflection, 0u);
  EXPECT_GT(hs.rays.refraction, 0u);

  auto f = flip(hybridImage, referenceImage);
  ASSERT_TRUE(f.ok()) << f.error().message;
  std::printf("FLIP mean hybrid-full vs reference 1 spp: %.5f\n", f->mean);
  (void)writePng(test::outputDir() + "/hybrid-vs-reference-hybrid.png", hybridImage);
  (void)writePng(test::outputDir() + "/hybrid-vs-reference-reference.png", referenceImage);
  (void)writePng(test::outputDir() + "/hybrid-vs-reference-flip.png", heatmap(*f));
  EXPECT_LT(f->mean, 0.01);
}

}  // namespace
}  // namespace tandem
