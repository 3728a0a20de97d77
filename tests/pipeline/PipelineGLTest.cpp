// Throughput mode (FrameSettings::pipelined, docs/pipeline.md): each render() call shows the frame before its
// own, whose rays ran while the call rasterized; every frame it shows is the frame latency mode draws for the
// same camera, scene and settings, to the bit, whether it overlapped, had to drain, or fell back to latency
// mode. Run under ThreadSanitizer by tools/test.sh --tsan with the rest of the GL tests.
#include <algorithm>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "gl/GlTestUtil.h"

using namespace tandem;

namespace {

// What one frame showed: its linear and display images and its stats.
struct Shown {
  ImageF linear;
  Image display;
  FrameStats stats;
};

Shown capture(Renderer& r, const FrameStats& st) { return {r.readLinear(), r.readImage(), st}; }

// Where two linear frames differ: how many pixels, their bounds and the largest difference (a failure's report).
std::string describeDifference(const ImageF& a, const ImageF& b) {
  if (a.width != b.width || a.height != b.height) return "sizes differ";
  int count = 0, x0 = a.width, y0 = a.height, x1 = -1, y1 = -1;
  float largest = 0.0f;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const glm::vec3 d = glm::abs(a.at(x, y) - b.at(x, y));
      const float m = std::max(d.x, std::max(d.y, d.z));
      if (!(a.at(x, y) == b.at(x, y))) {
        ++count;
        x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        largest = std::max(largest, m);
      }
    }
  return std::to_string(count) + " pixels in x " + std::to_string(x0) + ".." + std::to_string(x1) + ", y " +
         std::to_string(y0) + ".." + std::to_string(y1) + ", largest difference " + std::to_string(largest);
}

// Scene, camera and settings changes applied to both renderers before a frame (the same calls).
struct Step {
  const char* what;
  std::function<void(Renderer&)> scene;  // the scene's mutators, called on each renderer
  std::function<void()> view;            // the camera or the settings, shared
  bool drains = false;                   // throughput mode must complete the frame in flight first
  bool latencyOnly = false;              // a frame the pipeline does not take (drawn in latency mode)
};

// Runs `steps` on a latency renderer and a throughput one, and checks that each frame the throughput one
// shows (a call later, or on finish()) is the latency frame of the same step, to the bit, with its rays.
// `strict`: each step overlaps, drains or falls back to latency mode as it says; else (accumulation, whose
// frames pipeline only when it starts again) the frames are checked whichever way each was drawn.
void checkSequence(GlContext& ctx, const Scene& scene, FrameSettings& s, Camera& camera, std::vector<Step>& steps,
                   bool strict = true) {
  auto latency = gltest::makeRenderer(ctx);
  auto throughput = gltest::makeRenderer(ctx);
  ASSERT_TRUE(latency && throughput);
  ASSERT_TRUE(latency->setScene(scene).ok());
  ASSERT_TRUE(throughput->setScene(scene).ok());
  EXPECT_FALSE(throughput->finish().has_value()) << "nothing in flight yet";
  std::vector<Shown> want;             // latency mode, frame i
  // The throughput renderer's frame in flight, kNone when none (an index, not an optional: GCC 12 takes an
  // engaged optional's value for uninitialized).
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::size_t pending = kNone;
  int overlapped = 0, drained = 0, keeping = 0;
  auto compare = [&](std::size_t frame, const Shown& got) {
    SCOPED_TRACE(std::string("frame of step ") + steps[frame].what);
    const Shown& w = want[frame];
    EXPECT_TRUE(got.linear.rgb == w.linear.rgb) << "linear frame differs: " << describeDifference(got.linear, w.linear);
    EXPECT_TRUE(got.display.rgba == w.display.rgba) << "display frame differs";
    if (got.display.rgba != w.display.rgba) {
      gltest::savePng(std::string("pipeline-differs-") + std::to_string(frame) + "-throughput.png", got.display);
      gltest::savePng(std::string("pipeline-differs-") + std::to_string(frame) + "-latency.png", w.display);
    }
    EXPECT_EQ(got.stats.rays.total(), w.stats.rays.total());
    EXPECT_EQ(got.stats.rays.shadow, w.stats.rays.shadow);
    EXPECT_EQ(got.stats.rays.shadowKept, w.stats.rays.shadowKept);
    EXPECT_EQ(got.stats.rays.shadowByMap, w.stats.rays.shadowByMap);
    EXPECT_EQ(got.stats.rays.shadowByShaft, w.stats.rays.shadowByShaft);
    EXPECT_EQ(got.stats.rays.resolved, w.stats.rays.resolved);
    EXPECT_EQ(got.stats.raysReused, w.stats.raysReused);
    keeping += got.stats.rays.shadowKept > 0 ? 1 : 0;
  };
  for (std::size_t i = 0; i < steps.size(); ++i) {
    SCOPED_TRACE(std::string("step ") + steps[i].what);
    if (steps[i].scene) {
      steps[i].scene(*latency);
      steps[i].scene(*throughput);
    }
    if (steps[i].view) steps[i].view();
    FrameSettings off = s;
    off.pipelined = false;
    const FrameStats l = latency->render(camera, off);
    ASSERT_TRUE(l.error.empty()) << l.error;
    EXPECT_FALSE(l.pipelined);
    want.push_back(capture(*latency, l));

    FrameSettings on = s;
    on.pipelined = true;
    const FrameStats t = throughput->render(camera, on);
    ASSERT_TRUE(t.error.empty()) << t.error;
    if (strict ? steps[i].latencyOnly : !t.pipelined) {
      // Drawn whole in latency mode, the frame in flight completed (and drawn over) first.
      EXPECT_FALSE(t.pipelined);
      compare(i, capture(*throughput, t));
      pending = kNone;
      continue;
    }
    EXPECT_TRUE(t.pipelined);
    EXPECT_EQ(t.pipelineFilling, pending == kNone);
    if (pending != kNone) {
      if (strict) {
        EXPECT_EQ(t.pipelineDrained, steps[i].drains) << "drained the frame in flight, or overlapped it";
      }
      (t.pipelineDrained ? drained : overlapped) += 1;
      compare(pending, capture(*throughput, t));
    } else {
      EXPECT_EQ(t.samples, 0) << "a filling call shows no frame";
    }
    if (i > 0) {
      EXPECT_GT(t.intervalMs, 0.0);
    }
    pending = i;
  }
  const std::optional<FrameStats> last = throughput->finish();
  ASSERT_EQ(last.has_value(), pending != kNone);
  if (last) {
    EXPECT_TRUE(last->error.empty()) << last->error;
    compare(pending, capture(*throughput, *last));
  }
  EXPECT_FALSE(throughput->finish().has_value()) << "finish() left nothing in flight";
  const bool overlaps = std::any_of(steps.begin(), steps.end(), [](const Step& st) { return !st.drains && !st.latencyOnly; });
  if (overlaps) {
    EXPECT_GT(overlapped, 0) << "the sequence never overlapped a frame's rays with the next raster";
  } else {
    EXPECT_EQ(overlapped, 0) << "a sequence that should always drain overlapped";
  }
  if (strict) {
    EXPECT_GT(drained, 0) << "the sequence never drained";
  }
  // (The filter's frames each draw new samples at a new sub-pixel offset: the camera never stands still for them.)
  if (s.reuseRays && s.shadows == EffectMode::Ray && !s.denoise) {
    EXPECT_GT(keeping, 0) << "no frame kept shadow answers (the camera still while an instance moved)";
  }
}

// The steps every sequence runs: the camera moving, standing still (reuse), the scene changing under it (a
// light, an instance: the next frame drawn while the rays of the last see the scene as it was, keeping some
// answers), all of it overlapped; the camera moving the render anchor, the settings changing and the scene set
// again (drains); a new size and a frame of two samples (latency mode).
std::vector<Step> movingSteps(Scene& scene, FrameSettings& s, Camera& camera) {
  const auto lastInstance = static_cast<std::uint32_t>(scene.instances.size() - 1);
  const std::uint32_t light = scene.lights[0].type == LightType::Ambient ? 1u : 0u;
  return {
      {"first frame", {}, {}, false},
      {"camera moves", {}, [&] { camera.posW.x += 0.2f; }, false},
      {"camera moves again", {}, [&] { camera.posW.y += 0.1f; }, false},
      {"nothing", {}, {}, false},
      {"an instance moves",
       [&, lastInstance](Renderer& r) {
         r.setInstanceTransform(lastInstance, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.15f, 0.0f)) *
                                                  scene.instances[lastInstance].worldFromObject);
       },
       {}, false},
      {"a light dims",
       [&, light](Renderer& r) {
         Light l = scene.lights[light];
         l.intensity *= 0.6f;
         r.setLight(light, l);
       },
       {}, false},
      {"an instance and the camera move",
       [&, lastInstance](Renderer& r) {
         r.setInstanceTransform(lastInstance, glm::translate(glm::mat4(1.0f), glm::vec3(0.1f, 0.0f, 0.05f)) *
                                                  scene.instances[lastInstance].worldFromObject);
       },
       [&] { camera.posW.x += 0.05f; }, false},
      {"camera moves after the changes", {}, [&] { camera.posW.x -= 0.1f; }, false},
      // The floating origin (core/RenderSpace.h): a camera past the anchor's reach moves it, the frame in flight
      // first completed with the old one.
      {"the camera travels past the anchor's reach", {}, [&] {
         camera.posW.x += 60.0f;
         camera.targetW.x += 60.0f;
       }, true},
      {"and back, past it again", {}, [&] {
         camera.posW.x -= 60.0f;
         camera.targetW.x -= 60.0f;
       }, true},
      {"tone map", {}, [&] { s.toneMap = ToneMap::Reinhard; }, true},
      {"two samples", {}, [&] { s.aa = AntiAlias::Ssaa, s.aaSamples = 2; }, false, true},
      {"one sample again", {}, [&] { s.aa = AntiAlias::Off; }, false},
      {"camera moves once more", {}, [&] { camera.posW.z -= 0.2f; }, false},
      {"an instance moves back, the camera still (the frame keeps answers)",
       [&, lastInstance](Renderer& r) {
         r.setInstanceTransform(lastInstance, scene.instances[lastInstance].worldFromObject);
       },
       {}, false},
      // Replaced while that frame's rays, reading the answers it keeps, are in flight.
      {"the scene set again", [&](Renderer& r) { ASSERT_TRUE(r.setScene(scene).ok()); }, {}, true},
      {"size", {}, [&] { s.width -= 16; }, false, true},
      {"camera moves at the end", {}, [&] { camera.posW.y -= 0.1f; }, false},
  };
}

}  // namespace

// The Whitted scene in each hybrid preset, with reuse on (still frames reuse their rays, moved instances keep
// answers), hybrid shadows by maps and by shafts, proofs in the GL (which never overlap: their maps are the
// tracer's), and a coarser ray grid.
TEST(Pipeline, ThroughputFramesEqualLatencyFramesToTheBit) {
  TD_REQUIRE_GL_CONTEXT();
  struct Variant {
    const char* name;
    const char* preset;
    std::function<void(FrameSettings&)> tweak;
    bool overlaps;
  } variants[] = {
      {"hybrid-full", "hybrid-full", [](FrameSettings&) {}, true},
      {"hybrid-fast (ray grid 1/2, raster refraction: probes)", "hybrid-fast", [](FrameSettings&) {}, true},
      {"raster shadows (maps drawn after the frame before is shown)", "hybrid-full",
       [](FrameSettings& f) { f.shadows = EffectMode::Raster; }, true},
      {"probes a few a frame", "hybrid-fast", [](FrameSettings& f) { f.probesPerFrame = 1; }, true},
      {"hybrid shadows, maps", "hybrid-full",
       [](FrameSettings& f) { f.hybridShadows = true, f.shadowProofs = ShadowProofs::Cpu; }, true},
      {"hybrid shadows, shafts", "hybrid-full",
       [](FrameSettings& f) { f.hybridShadows = true, f.shadowProofs = ShadowProofs::Shafts; }, true},
      {"the motion view (each frame against the one composited before it)", "hybrid-full",
       [](FrameSettings& f) { f.debugView = DebugView::Motion; }, true},
      {"the spatiotemporal filter (its history: the frame composited before)", "hybrid-full",
       [](FrameSettings& f) { f.denoise = true; }, true},
      {"hybrid shadows, proofs in the GL", "hybrid-full",
       [](FrameSettings& f) { f.hybridShadows = true, f.shadowProofs = ShadowProofs::Gl; }, false},
  };
  for (const Variant& v : variants) {
    SCOPED_TRACE(v.name);
    auto loaded = loadDefaultScene();
    ASSERT_TRUE(loaded.ok());
    Scene scene = std::move(*loaded);
    FrameSettings s = *presetSettings(v.preset);
    s.width = 128;
    s.height = 72;
    v.tweak(s);
    Camera camera = scene.camera;
    std::vector<Step> steps = movingSteps(scene, s, camera);
    // Proofs in the GL: every frame drains (the full sequence, instance moves included, checks that the maps
    // are made from the Embree scene of the frame they prove).
    if (!v.overlaps)
      for (Step& step : steps) step.drains = !step.latencyOnly;
    checkSequence(*glContext_, scene, s, camera, steps);
  }
}

// Accumulation (the game's default: 16 frames at rest): while things move each frame starts it again and shows
// its one sample, pipelined; at rest the frames that add samples are drawn in latency mode, the first reading
// the last pipelined frame's linear image, and the mean is the latency renderer's to the bit.
TEST(Pipeline, AccumulationStartsPipelinedAndConvergesAsInLatencyMode) {
  TD_REQUIRE_GL_CONTEXT();
  auto loaded = loadDefaultScene();
  ASSERT_TRUE(loaded.ok());
  Scene scene = std::move(*loaded);
  FrameSettings s = *presetSettings("hybrid-fast");
  s.width = 128;
  s.height = 72;
  s.accumulate = 4;
  s.probesPerFrame = 2;
  Camera camera = scene.camera;
  std::vector<Step> steps = movingSteps(scene, s, camera);
  // Rest at the end: the accumulation goes on and converges.
  for (const char* rest : {"at rest 1", "at rest 2", "at rest 3", "at rest 4 (converged)", "at rest 5 (shown again)"})
    steps.push_back({rest, {}, {}, false});
  checkSequence(*glContext_, scene, s, camera, steps, false);
}

// Exact solids (their proxies' pixels resolved by the ray pass and patched into the frame's own visibility
// buffer, the spare one while the next frame is drawn), procedural textures and glass: csg.json.
TEST(Pipeline, ExactSolidsArePatchedIntoTheirOwnFramesBuffer) {
  TD_REQUIRE_GL_CONTEXT();
  auto loaded = loadSceneFile(test::sourceDir() + "/assets/scenes/csg.json");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  Scene scene = std::move(*loaded);
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = 128;
  s.height = 72;
  Camera camera = scene.camera;
  std::vector<Step> steps = movingSteps(scene, s, camera);
  checkSequence(*glContext_, scene, s, camera, steps);
}

// What completes the frame in flight: tracePixel traces it (shown first), resize composites it at its own
// size, a latency frame completes it; and a renderer destroyed with one in flight joins its rays.
TEST(Pipeline, TracePixelResizeAndDestructionCompleteTheFrameInFlight) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto latency = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(latency);
  auto throughput = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(throughput && throughput->setScene(scene).ok());
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = 96;
  s.height = 54;
  FrameSettings on = s;
  on.pipelined = true;
  Camera camera = scene.camera;
  ASSERT_TRUE(latency->render(camera, s).error.empty());
  const FrameStats first = throughput->render(camera, on);
  ASSERT_TRUE(first.pipelineFilling);
  auto want = latency->tracePixel(48, 27);
  auto got = throughput->tracePixel(48, 27);
  ASSERT_TRUE(want.ok() && got.ok()) << (got.ok() ? "" : got.error().message);
  EXPECT_EQ(toText(*got, throughput->scene()), toText(*want, latency->scene()));
  EXPECT_TRUE(throughput->readImage().rgba == latency->readImage().rgba) << "tracePixel showed the frame it traced";
  EXPECT_FALSE(throughput->finish().has_value());

  // resize() with a frame in flight: the frame is shown at its size, then the targets change (as in latency
  // mode, readImage() then holds no frame until the next is drawn).
  camera.posW.x += 0.2f;
  ASSERT_TRUE(throughput->render(camera, on).pipelineFilling);
  ASSERT_TRUE(throughput->resize(80, 45).ok());
  EXPECT_FALSE(throughput->finish().has_value());

  // A latency-mode frame with one in flight: completed first, then this frame drawn.
  camera.posW.y += 0.1f;
  ASSERT_TRUE(throughput->render(camera, on).pipelineFilling);
  const FrameStats l = throughput->render(camera, s);
  EXPECT_FALSE(l.pipelined);
  ASSERT_TRUE(latency->render(camera, s).error.empty());
  EXPECT_TRUE(throughput->readImage().rgba == latency->readImage().rgba);

  // Destroyed with rays running, the scene changed under them first (they see their own copy of it).
  ASSERT_TRUE(throughput->render(camera, on).pipelineFilling);
  throughput->setInstanceTransform(0, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.05f, 0.0f)) *
                                          scene.instances[0].worldFromObject);
  const FrameStats overlapped = throughput->render(camera, on);
  EXPECT_TRUE(overlapped.pipelined && !overlapped.pipelineDrained && !overlapped.pipelineFilling);
  throughput.reset();
}
