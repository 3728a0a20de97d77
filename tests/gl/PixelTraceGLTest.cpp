// Renderer::tracePixel: the ray tree of a pixel of the last frame. Its sum must be the frame's linear
// colour at that pixel (the GL shades the primary hit's local term, the trace its CPU twin: equal within
// the shading parity bound), and it refuses what it cannot trace with a reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "GlTestUtil.h"
#include "tandem/PixelTrace.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

// The glass sphere of the Whitted scene at 320x180 (tests/rt/PixelTraceTest.cpp traces the same pixel).
constexpr int kGlassX = 132, kGlassY = 87;

FrameSettings preset(const char* name) {
  FrameSettings s = *presetSettings(name);
  s.width = 320;
  s.height = 180;
  return s;
}

bool sameColour(const PixelTrace& t, const ImageF& frame, int x, int y, float tolerance) {
  const glm::vec3 c = frame.at(x, y);
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(t.color[k] - c[k]) <= tolerance * (1.0f + c[k]))) return false;
  return true;
}

void expectFrameColour(const PixelTrace& t, const ImageF& frame, int x, int y, float tolerance) {
  const glm::vec3 c = frame.at(x, y);
  EXPECT_TRUE(sameColour(t, frame, x, y, tolerance))
      << "pixel " << x << "," << y << ": trace (" << t.color.x << ", " << t.color.y << ", " << t.color.z << "), frame ("
      << c.x << ", " << c.y << ", " << c.z << ")";
}

TEST(PixelTraceGL, GlassPixelSumIsTheFramesColour) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const Camera camera = scene.camera;
  FrameSettings s = preset("hybrid-full");
  FrameStats stats = renderer->render(camera, s);
  ASSERT_TRUE(stats.error.empty()) << stats.error;
  const ImageF frame = renderer->readLinear();
  auto trace = renderer->tracePixel(kGlassX, kGlassY);
  ASSERT_TRUE(trace) << trace.error().message;
  EXPECT_TRUE(trace->rayPass);
  EXPECT_TRUE(trace->notes.empty()) << trace->notes.front();
  const TraceNode& primary = trace->nodes[static_cast<std::size_t>(trace->roots.at(0))];
  ASSERT_TRUE(primary.hit);
  EXPECT_EQ(renderer->scene().instances[primary.instance].name, "glass-sphere");
  EXPECT_GE(primary.reflectionChild, 0);
  EXPECT_GE(primary.refractionChild, 0);
  // local (GL) + wR·S + wT·T (ray pass) against local (CPU twin) + the same wR·S + wT·T.
  expectFrameColour(*trace, frame, kGlassX, kGlassY, 2e-3f);
  // A pixel of every kind in view: the sky, the floor, the mirror, the box. One may differ: a GPU may round
  // a floor uv onto the other side of a checker edge, where either colour is exact (docs/shading.md).
  int onSurface = 0, differing = 0;
  for (int y = 5; y < 180; y += 17)
    for (int x = 3; x < 320; x += 23) {
      auto t = renderer->tracePixel(x, y);
      ASSERT_TRUE(t) << t.error().message;
      onSurface += t->nodes.front().hit;
      if (!sameColour(*t, frame, x, y, 2e-3f)) {
        ++differing;
        std::fprintf(stderr, "pixel %d,%d: the trace's colour differs from the frame's (one may)\n", x, y);
      }
    }
  EXPECT_GT(onSurface, 20);
  EXPECT_LE(differing, 1);
}

TEST(PixelTraceGL, ReferencePixelIsTheFramesPixel) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const Camera camera = scene.camera;
  FrameSettings s = preset("reference");
  s.toneMap = ToneMap::None;
  ASSERT_TRUE(renderer->render(camera, s).error.empty());
  const ImageF frame = renderer->readLinear();
  auto trace = renderer->tracePixel(kGlassX, kGlassY);
  ASSERT_TRUE(trace) << trace.error().message;
  EXPECT_TRUE(trace->reference);
  EXPECT_TRUE(trace->notes.empty());
  // The reference frame is the tracer's image uploaded as floats: the same numbers.
  expectFrameColour(*trace, frame, kGlassX, kGlassY, 1e-6f);
}

TEST(PixelTraceGL, RasterFrameNamesWhatTheGlMade) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const Camera camera = scene.camera;
  ASSERT_TRUE(renderer->render(camera, preset("raster")).error.empty());
  auto trace = renderer->tracePixel(kGlassX, kGlassY);
  ASSERT_TRUE(trace) << trace.error().message;
  EXPECT_FALSE(trace->rayPass);
  EXPECT_EQ(trace->rays.total(), 1u);  // the primary hit only
  const TraceNode& primary = trace->nodes.front();
  ASSERT_TRUE(primary.hit);
  EXPECT_EQ(renderer->scene().instances[primary.instance].name, "glass-sphere");
  EXPECT_EQ(primary.reflection, SecondaryRay::NotByRays);
  EXPECT_EQ(primary.refraction, SecondaryRay::NotByRays);
  EXPECT_GT(primary.fresnel, 0.0f);  // the weights the probes' sum uses, still shown
  std::string notes;
  for (const std::string& n : trace->notes) notes += n + "\n";
  EXPECT_NE(notes.find("shadow maps"), std::string::npos) << notes;
  EXPECT_NE(notes.find("reflections are raster"), std::string::npos) << notes;
  EXPECT_NE(notes.find("refraction is raster"), std::string::npos) << notes;
}

TEST(PixelTraceGL, RefusesWhatItCannotTrace) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const Camera camera = scene.camera;
  auto none = renderer->tracePixel(0, 0);
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("no frame"), std::string::npos) << none.error().message;
  ASSERT_TRUE(renderer->render(camera, preset("hybrid-full")).error.empty());
  for (glm::ivec2 p : {glm::ivec2(320, 0), glm::ivec2(0, 180), glm::ivec2(-1, 5)}) {
    auto outside = renderer->tracePixel(p.x, p.y);
    ASSERT_FALSE(outside) << p.x << "," << p.y;
    EXPECT_NE(outside.error().message.find("outside the 320x180 frame"), std::string::npos) << outside.error().message;
  }
  EXPECT_TRUE(renderer->tracePixel(319, 179));
  // The frame's ids would not be the scene's any more (a light set to the value it has changes nothing).
  renderer->setLight(1, renderer->scene().lights[1]);
  EXPECT_TRUE(renderer->tracePixel(kGlassX, kGlassY));
  Light dimmer = renderer->scene().lights[1];
  dimmer.intensity *= 0.5f;
  renderer->setLight(1, dimmer);
  auto stale = renderer->tracePixel(kGlassX, kGlassY);
  ASSERT_FALSE(stale);
  EXPECT_NE(stale.error().message.find("changed since the last frame"), std::string::npos) << stale.error().message;
  ASSERT_TRUE(renderer->render(camera, preset("hybrid-full")).error.empty());
  EXPECT_TRUE(renderer->tracePixel(kGlassX, kGlassY));
}

}  // namespace
}  // namespace tandem
