// The bench's ray capture (RayTracerBench::trace) and raw re-trace (RayTracerBench::retrace): the capture
// holds exactly the rays the pass counted, tile by tile, and Embree alone gives the same answers.
#include <array>

#include <gtest/gtest.h>

#include "rt/RayCapture.h"
#include "rt/RayTracerBench.h"
#include "rt/RtTestScenes.h"
#include "tandem/SceneFile.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

Scene whittedScene() {
  auto scene = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/whitted.json");
  EXPECT_TRUE(scene.ok()) << (scene ? std::string() : scene.error().message);
  return scene ? std::move(*scene) : Scene{};
}

void expectCounts(const RayCounts& captured, const RayCounts& counted) {
  EXPECT_EQ(captured.primary, counted.primary);
  EXPECT_EQ(captured.shadow, counted.shadow);
  EXPECT_EQ(captured.reflection, counted.reflection);
  EXPECT_EQ(captured.refraction, counted.refraction);
}

struct Frame {
  Scene scene = whittedScene();
  std::unique_ptr<RayTracer> tracer;
  VisibilityBuffer visibility;
  FrameSettings settings;
  explicit Frame(int threads = 2, int w = 160, int h = 90) {
    tracer = makeTracer(scene, threads);
    settings = *presetSettings("hybrid-full", settingsFor(w, h));
    if (tracer) tracer->castVisibility(scene.camera, w, h, visibility);
  }
  RayCounts trace(RayCapture* capture, bool batchedShadowRays = true) {
    RayOutputs out;
    RayTracerBench::trace(*tracer, scene, scene.camera, settings, visibility, out, {capture, batchedShadowRays});
    return out.counts;
  }
};

TEST(RayCapture, HybridCaptureHoldsExactlyTheCountedRays) {
  for (bool batched : {true, false}) {
    SCOPED_TRACE(batched ? "batched shadow rays" : "one rtcOccluded1 per shadow ray");
    Frame f;
    ASSERT_TRUE(f.tracer);
    RayCapture capture;
    RayCounts counted = f.trace(&capture, batched);
    // Whitted's scene exercises every kind; a zero here would make the comparison vacuous.
    ASSERT_GT(counted.shadow, 0u);
    ASSERT_GT(counted.reflection, 0u);
    ASSERT_GT(counted.refraction, 0u);
    expectCounts(capture.counts(), counted);
    EXPECT_FALSE(capture.primaryTraced);
    EXPECT_EQ(capture.width, 160);
    EXPECT_EQ(capture.height, 90);
    // Each shadow ray names the light it heads for (the floor's packets group by it): the Whitted scene's
    // two direct lights (a point and a spot), both present. Rays of one group end at one point, the light
    // (in the tracer's render space, and just short of it), and the two groups' points are far apart.
    const std::size_t lights = f.scene.directLights().size();
    ASSERT_EQ(lights, 2u);
    std::array<std::uint64_t, 2> perLight{};
    std::array<glm::vec3, 2> end{};
    for (const auto& tile : capture.tiles)
      for (const CapturedRay& r : tile.rays[static_cast<std::size_t>(RayKind::Shadow)]) {
        ASSERT_LT(r.group, lights);
        const glm::vec3 e = r.origin + r.dir * r.tfar;
        if (perLight[r.group]++ == 0) end[r.group] = e;
        EXPECT_LT(glm::distance(e, end[r.group]), 2e-2f) << "light " << int(r.group);
      }
    EXPECT_GT(perLight[0], 0u);
    EXPECT_GT(perLight[1], 0u);
    EXPECT_GT(glm::distance(end[0], end[1]), 1.0f);
  }
}

TEST(RayCapture, TilesAreRowMajorSixteenPixelTiles) {
  Frame f;
  ASSERT_TRUE(f.tracer);
  RayCapture capture;
  f.trace(&capture);
  const int tilesX = (160 + 15) / 16, tilesY = (90 + 15) / 16;
  ASSERT_EQ(capture.tiles.size(), static_cast<std::size_t>(tilesX * tilesY));
  // One primary record per non-background pixel of the tile it lies in.
  for (int t = 0; t < tilesX * tilesY; ++t) {
    int x0 = (t % tilesX) * 16, y0 = (t / tilesX) * 16;
    std::size_t covered = 0;
    for (int y = y0; y < std::min(y0 + 16, 90); ++y)
      for (int x = x0; x < std::min(x0 + 16, 160); ++x)
        covered += f.visibility.ids[static_cast<std::size_t>(y * 160 + x)].x != 0;
    EXPECT_EQ(capture.tiles[static_cast<std::size_t>(t)].rays[0].size(), covered) << "tile " << t;
  }
}

TEST(RayCapture, CaptureDoesNotDependOnTheThreadCount) {
  Frame one(1), two(2);
  ASSERT_TRUE(one.tracer && two.tracer);
  RayCapture a, b;
  one.trace(&a);
  two.trace(&b);
  ASSERT_EQ(a.tiles.size(), b.tiles.size());
  for (std::size_t t = 0; t < a.tiles.size(); ++t)
    for (std::size_t k = 0; k < kRayKinds; ++k) {
      const auto& ra = a.tiles[t].rays[k];
      const auto& rb = b.tiles[t].rays[k];
      ASSERT_EQ(ra.size(), rb.size()) << "tile " << t << " kind " << k;
      for (std::size_t i = 0; i < ra.size(); ++i) {
        EXPECT_EQ(ra[i].origin, rb[i].origin);
        EXPECT_EQ(ra[i].dir, rb[i].dir);
        EXPECT_EQ(ra[i].hit, rb[i].hit);
      }
    }
}

TEST(RayCapture, WithoutACaptureNothingIsRecorded) {
  Frame f;
  ASSERT_TRUE(f.tracer);
  RayCapture capture;
  f.trace(&capture);
  RayCounts before = capture.counts();
  RayOutputs out;
  f.tracer->trace(f.scene, f.scene.camera, f.settings, f.visibility, out);
  expectCounts(capture.counts(), before);  // the previous capture is left as it was
}

TEST(RayCapture, RetraceGivesTheSameAnswersWithEveryApi) {
  Frame f;
  ASSERT_TRUE(f.tracer);
  RayCapture capture;
  RayCounts counted = f.trace(&capture);
  // Occluded shadow rays and escaping reflection rays both occur: a re-trace that answered everything
  // the same way could not pass.
  std::size_t occluded = 0, escaped = 0;
  for (const auto& tile : capture.tiles) {
    for (const auto& r : tile.rays[1]) occluded += r.hit;
    for (const auto& r : tile.rays[2]) escaped += !r.hit;
  }
  EXPECT_GT(occluded, 0u);
  EXPECT_GT(escaped, 0u);
  for (RetraceApi api : {RetraceApi::Single, RetraceApi::Stream, RetraceApi::Packet}) {
    SCOPED_TRACE(std::string("rtc*") + toString(api));
    RetraceOptions options;
    options.api.fill(api);
    RetraceStats s = RayTracerBench::retrace(*f.tracer, capture, options);
    EXPECT_EQ(s.rays[0], 0u) << "hybrid primary hits are not Embree rays";
    EXPECT_EQ(s.rays[1], counted.shadow);
    EXPECT_EQ(s.rays[2], counted.reflection);
    EXPECT_EQ(s.rays[3], counted.refraction);
    for (std::size_t k = 0; k < kRayKinds; ++k) EXPECT_EQ(s.mismatches[k], 0u) << toString(static_cast<RayKind>(k));
  }
}

TEST(RayCapture, ReferenceCaptureIncludesTracedCameraRays) {
  Scene scene = whittedScene();
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  FrameSettings s = *presetSettings("reference", settingsFor(64, 36));
  s.referenceSpp = 2;
  RayCapture capture;
  ImageF image;
  RayCounts counts;
  RayTracerBench::renderReference(*tracer, scene, scene.camera, s, image, counts, capture);
  EXPECT_TRUE(capture.primaryTraced);
  EXPECT_EQ(counts.primary, 64u * 36u * 4u);
  expectCounts(capture.counts(), counts);
  RetraceStats r = RayTracerBench::retrace(*tracer, capture);
  EXPECT_EQ(r.rays[0], counts.primary);
  for (std::size_t k = 0; k < kRayKinds; ++k) EXPECT_EQ(r.mismatches[k], 0u) << toString(static_cast<RayKind>(k));
}

// The capture is a second instantiation of the passes (rt/TileCapture.h): it must compute what the
// frame's computes, to the bit, or the bench would measure other rays than the frame traces.
TEST(RayCapture, CapturingPassesComputeTheFramesResultsBitForBit) {
  Frame f;
  ASSERT_TRUE(f.tracer);
  for (bool batched : {true, false}) {
    SCOPED_TRACE(batched ? "batched shadow rays" : "one rtcOccluded1 per shadow ray");
    RayOutputs frame, captured;
    f.tracer->trace(f.scene, f.scene.camera, f.settings, f.visibility, frame);
    RayCapture capture;
    RayTracerBench::trace(*f.tracer, f.scene, f.scene.camera, f.settings, f.visibility, captured, {&capture, batched});
    expectCounts(captured.counts, frame.counts);
    ASSERT_FALSE(frame.lightMask.empty());
    ASSERT_FALSE(frame.reflected.empty());
    ASSERT_FALSE(frame.transmitted.empty());
    EXPECT_EQ(captured.lightMask, frame.lightMask);
    EXPECT_EQ(captured.reflected, frame.reflected);
    EXPECT_EQ(captured.transmitted, frame.transmitted);
  }
  FrameSettings s = *presetSettings("reference", settingsFor(48, 27));
  ImageF plain, recorded;
  RayCounts plainCounts, recordedCounts;
  f.tracer->renderReference(f.scene, f.scene.camera, s, plain, plainCounts);
  RayCapture capture;
  RayTracerBench::renderReference(*f.tracer, f.scene, f.scene.camera, s, recorded, recordedCounts, capture);
  expectCounts(recordedCounts, plainCounts);
  EXPECT_EQ(recorded.rgb, plain.rgb);
}

}  // namespace
}  // namespace tandem::rt
