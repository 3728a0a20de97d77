// Google Benchmark micro-benchmarks of tandem-bench (the default mode): the ray pass on a captured frame
// against the raw Embree re-trace of its rays, shadow rays one by one vs streamed, FLIP at 1280×720,
// primary visibility by llvmpipe raster vs by Embree rays. Speed targets live here, never in unit tests.
#include "Micro.h"

#include <map>
#include <memory>

#include <benchmark/benchmark.h>
#include <glm/gtc/matrix_transform.hpp>

#include "BenchCommon.h"
#include "core/Timer.h"
#include "rt/RayCapture.h"
#include "rt/RayReuse.h"
#include "rt/RayTracerBench.h"
#include "rt/RayTracer.h"
#include "tandem/Context.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Renderer.h"

namespace tandem::bench {

namespace {

constexpr int kWidth = 1280, kHeight = 720;

// arg 0: the Whitted scene; arg 1: a 500k-triangle heavy scene (where rays may beat llvmpipe).
std::string sceneSpec(std::int64_t arg) {
  return arg == 0 ? sourceDir() + "/assets/scenes/whitted.json" : std::string("heavy:500000");
}

/// One captured hybrid-full frame per scene, built on first use and kept for the whole run.
struct RtFrame {
  Scene scene;
  std::unique_ptr<rt::RayTracer> tracer;
  rt::VisibilityBuffer visibility;
  FrameSettings settings;
  rt::RayCapture capture;
  RayCounts counts;
  rt::RetraceOptions best;  // the faster API per kind, measured once
  std::string error;
};

RtFrame& rtFrame(std::int64_t arg) {
  static std::map<std::int64_t, std::unique_ptr<RtFrame>> frames;
  auto& slot = frames[arg];
  if (slot) return *slot;
  slot = std::make_unique<RtFrame>();
  RtFrame& f = *slot;
  auto scene = loadBenchScene(sceneSpec(arg));
  if (!scene) {
    f.error = scene.error().message;
    return f;
  }
  f.scene = std::move(*scene);
  auto tracer = rt::RayTracer::create(0);
  if (!tracer) {
    f.error = tracer.error().message;
    return f;
  }
  f.tracer = std::move(*tracer);
  if (auto r = f.tracer->setScene(f.scene); !r) {
    f.error = r.error().message;
    f.tracer.reset();
    return f;
  }
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  f.settings = *presetSettings("hybrid-full", base);
  f.tracer->castVisibility(f.scene.camera, kWidth, kHeight, f.visibility);
  rt::RayOutputs out;
  rt::RayTracerBench::trace(*f.tracer, f.scene, f.scene.camera, f.settings, f.visibility, out, {&f.capture});
  f.counts = out.counts;
  // The floor takes the fastest of Embree's single, stream and packet calls for each kind.
  rt::RetraceStats byApi[rt::kRetraceApis];
  for (int api = 0; api < rt::kRetraceApis; ++api) {
    rt::RetraceOptions o;
    o.api.fill(static_cast<rt::RetraceApi>(api));
    (void)rt::RayTracerBench::retrace(*f.tracer, f.capture, o);  // warm caches
    byApi[api] = rt::RayTracerBench::retrace(*f.tracer, f.capture, o);
  }
  f.best.api.fill(rt::RetraceApi::Single);
  for (std::size_t k = 0; k < rt::kRayKinds; ++k)
    for (int api = 1; api < rt::kRetraceApis; ++api)
      if (byApi[api].ms[k] < byApi[static_cast<int>(f.best.api[k])].ms[k]) f.best.api[k] = static_cast<rt::RetraceApi>(api);
  return f;
}

/// Median over a few runs of the floor with the best API per kind.
double floorMs(RtFrame& f) {
  std::vector<double> v;
  for (int i = 0; i < 5; ++i) v.push_back(rt::RayTracerBench::retrace(*f.tracer, f.capture, f.best).totalMs());
  return summarize(v).median;
}

std::uint64_t embreeRays(const RayCounts& c, bool primaryTraced) {
  return c.shadow + c.reflection + c.refraction + (primaryTraced ? c.primary : 0);
}

void BM_RayPass(benchmark::State& state) {
  RtFrame& f = rtFrame(state.range(0));
  if (!f.tracer) return state.SkipWithError(f.error.c_str());
  rt::RayOutputs out;
  std::vector<double> ms;
  for (auto _ : state) {
    Timer t;
    f.tracer->trace(f.scene, f.scene.camera, f.settings, f.visibility, out);
    ms.push_back(t.ms());
  }
  double floor = floorMs(f);
  double pass = summarize(ms).median;
  state.counters["rays"] = static_cast<double>(embreeRays(f.counts, false));
  state.counters["Mrays/s"] = static_cast<double>(embreeRays(f.counts, false)) / (pass * 1e3);
  state.counters["floor_ms"] = floor;
  state.counters["pass_ms"] = pass;
  // The ceiling: the performance target is the ray pass within 1.3× of this floor (docs/bench.md).
  state.counters["pass/floor"] = floor > 0 ? pass / floor : 0.0;
  state.counters["threads"] = f.tracer->threads();
  state.counters["shadow_rays"] = static_cast<double>(out.counts.shadow);
}

// The same pass with hybrid shadows (hybrid-full, --shadows hybrid; docs/shadows.md): proofs 0, the maps
// alone (--shadow-proofs cpu), built by the first iteration and kept, so this is the per-frame cost of a
// scene where nothing moves; proofs 1, the tile shafts alone (--shadow-proofs shafts: nothing to build);
// proofs 2, the shafts first, then the maps (--shadow-proofs auto without a GPU).
void BM_RayPassHybridShadows(benchmark::State& state) {
  RtFrame& f = rtFrame(state.range(0));
  if (!f.tracer) return state.SkipWithError(f.error.c_str());
  rt::RayOutputs out;
  FrameSettings settings = f.settings;
  settings.hybridShadows = true;
  settings.shadowProofs = state.range(1) == 0 ? ShadowProofs::Cpu : state.range(1) == 1 ? ShadowProofs::Shafts : ShadowProofs::Auto;
  std::vector<double> ms;
  for (auto _ : state) {
    Timer t;
    f.tracer->trace(f.scene, f.scene.camera, settings, f.visibility, out);
    ms.push_back(t.ms());
  }
  state.counters["shadow_rays"] = static_cast<double>(out.counts.shadow);
  state.counters["shadow_by_map"] = static_cast<double>(out.counts.shadowByMap);
  state.counters["shadow_by_shaft"] = static_cast<double>(out.counts.shadowByShaft);
  state.counters["pass_ms"] = summarize(ms).median;
  state.counters["map_MB"] = static_cast<double>(f.tracer->shadowMapBytes()) / 1e6;
}

// Reuse across frames (docs/reuse.md) where it applies: the camera still, one object moving. The
// Whitted scene's box bobs between two places, frame after frame; arg 1 keeps the shadow answers of the
// frame before that pass clear of it, arg 0 traces every ray. Only the ray pass is timed (the ids of both
// places are cast once, outside the loop). Hybrid-full and hybrid-fast (arg 2: 1/2 grid, no refraction).
void BM_RayPassKeptShadows(benchmark::State& state) {
  const bool keep = state.range(0) != 0;
  const bool fast = state.range(1) != 0;
  struct Bob {
    Scene scene;
    std::unique_ptr<rt::RayTracer> tracer;
    glm::mat4 at[2];
    rt::VisibilityBuffer ids[2];
    std::string error;
  };
  static std::map<bool, std::unique_ptr<Bob>> bobs;
  auto& slot = bobs[fast];
  if (!slot) {
    slot = std::make_unique<Bob>();
    RtFrame& f = rtFrame(0);
    if (!f.tracer) {
      slot->error = f.error;
    } else {
      slot->scene = f.scene;
      auto tracer = rt::RayTracer::create(0);
      if (!tracer || !(*tracer)->setScene(slot->scene)) {
        slot->error = "cannot build the ray scene";
      } else {
        slot->tracer = std::move(*tracer);
        const glm::mat4 base = slot->scene.instances.back().worldFromObject;
        for (int k = 0; k < 2; ++k) {
          slot->at[k] = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, k == 0 ? 0.0f : 0.1f, 0.0f)) * base;
          slot->scene.instances.back().worldFromObject = slot->at[k];
          slot->tracer->updateTransforms(slot->scene);
          slot->tracer->castVisibility(slot->scene.camera, kWidth, kHeight, slot->ids[k]);
        }
      }
    }
  }
  Bob& b = *slot;
  if (!b.tracer) return state.SkipWithError(b.error.c_str());
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  const FrameSettings settings = *presetSettings(fast ? "hybrid-fast" : "hybrid-full", base);
  const std::uint32_t box = static_cast<std::uint32_t>(b.scene.instances.size() - 1);
  rt::RayOutputs out[2];
  int k = 0;
  b.scene.instances[box].worldFromObject = b.at[0];
  b.tracer->updateTransforms(b.scene);
  b.tracer->trace(b.scene, b.scene.camera, settings, b.ids[0], out[0]);
  std::vector<double> ms;
  RayCounts counts;
  for (auto _ : state) {
    const int next = 1 - k;
    b.scene.instances[box].worldFromObject = b.at[next];
    b.tracer->updateTransforms(b.scene);
    rt::RayReuse reuse;
    reuse.ids = &b.ids[k];
    reuse.rays = &out[k];
    reuse.moved.emplace_back(box, b.at[k]);
    Timer t;
    b.tracer->trace(b.scene, b.scene.camera, settings, b.ids[next], out[next], keep ? &reuse : nullptr);
    ms.push_back(t.ms());
    counts = out[next].counts;
    k = next;
  }
  state.counters["pass_ms"] = summarize(ms).median;
  state.counters["shadow_rays"] = static_cast<double>(counts.shadow);
  state.counters["shadow_kept"] = static_cast<double>(counts.shadowKept);
}

void BM_RetraceFloor(benchmark::State& state) {
  RtFrame& f = rtFrame(state.range(0));
  if (!f.tracer) return state.SkipWithError(f.error.c_str());
  rt::RetraceStats s;
  for (auto _ : state) s = rt::RayTracerBench::retrace(*f.tracer, f.capture, f.best);
  std::uint64_t n = s.rays[1] + s.rays[2] + s.rays[3] + s.rays[0];
  state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(n) * 1e-6 * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  std::uint64_t mismatches = s.mismatches[0] + s.mismatches[1] + s.mismatches[2] + s.mismatches[3];
  state.counters["mismatches"] = static_cast<double>(mismatches);
  // Which API the floor took per kind: 0 rtc*1, 1 rtc*1M, 2 rtc*8 (rt::RetraceApi).
  for (std::size_t k = 1; k < rt::kRayKinds; ++k)
    state.counters[std::string(rt::toString(static_cast<rt::RayKind>(k))) + "_api"] = static_cast<double>(f.best.api[k]);
}

void shadowRays(benchmark::State& state, rt::RetraceApi api) {
  RtFrame& f = rtFrame(state.range(0));
  if (!f.tracer) return state.SkipWithError(f.error.c_str());
  rt::RetraceOptions o;
  o.kinds = {false, true, false, false};
  o.api.fill(api);
  rt::RetraceStats s;
  for (auto _ : state) s = rt::RayTracerBench::retrace(*f.tracer, f.capture, o);
  state.counters["Mrays/s"] = benchmark::Counter(static_cast<double>(s.rays[1]) * 1e-6 * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}
void BM_ShadowOccluded1(benchmark::State& state) { shadowRays(state, rt::RetraceApi::Single); }
void BM_ShadowOccluded1M(benchmark::State& state) { shadowRays(state, rt::RetraceApi::Stream); }
void BM_ShadowOccluded8(benchmark::State& state) { shadowRays(state, rt::RetraceApi::Packet); }

void BM_Flip1280x720(benchmark::State& state) {
  // Two genuinely different images of the same frame: the reference at 1 and at 2×2 spp (aliased edges
  // vs smoothed ones), so the per-pixel work is the real one.
  static Image a, b;
  static std::string error;
  if (a.rgba.empty() && error.empty()) {
    RtFrame& f = rtFrame(0);
    if (!f.tracer) {
      error = f.error;
    } else {
      FrameSettings s = *presetSettings("reference", f.settings);
      ImageF linear;
      RayCounts c;
      s.referenceSpp = 1;
      f.tracer->renderReference(f.scene, f.scene.camera, s, linear, c);
      a = toDisplay(linear, s);
      s.referenceSpp = 2;
      f.tracer->renderReference(f.scene, f.scene.camera, s, linear, c);
      b = toDisplay(linear, s);
    }
  }
  if (!error.empty()) return state.SkipWithError(error.c_str());
  double mean = 0;
  for (auto _ : state) {
    auto r = flip(a, b);
    mean = r ? r->mean : -1.0;
    benchmark::DoNotOptimize(mean);
  }
  state.counters["flip_mean"] = mean;
  state.counters["Mpixels/s"] = benchmark::Counter(kWidth * kHeight * 1e-6 * static_cast<double>(state.iterations()),
                                                   benchmark::Counter::kIsRate);
}

/// The GL side for the raster benchmark: one context and renderer per scene for the whole run.
struct GlFrame {
  std::unique_ptr<GlContext> context;
  std::unique_ptr<Renderer> renderer;
  Camera camera;
  double readbackMs = 0;  // of a hybrid-full frame: what the ray pass needs read back
  std::string error;
};

GlFrame& glFrame(const std::string& spec) {
  static std::unique_ptr<GlContext> context;
  static std::string contextError;
  static std::map<std::string, std::unique_ptr<GlFrame>> frames;
  auto& slot = frames[spec];
  if (slot) return *slot;
  slot = std::make_unique<GlFrame>();
  if (!context && contextError.empty()) {
    auto c = createGlContext({});
    if (c) context = std::move(*c);
    else contextError = c.error().message;
  }
  if (!context) {
    slot->error = "no GL context: " + contextError;
    return *slot;
  }
  auto scene = loadBenchScene(spec);
  if (!scene) {
    slot->error = scene.error().message;
    return *slot;
  }
  auto r = Renderer::create(*context);
  if (!r) {
    slot->error = r.error().message;
    return *slot;
  }
  slot->renderer = std::move(*r);
  slot->camera = scene->camera;
  if (auto ok = slot->renderer->setScene(std::move(*scene)); !ok) {
    slot->error = ok.error().message;
    slot->renderer.reset();
    return *slot;
  }
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  FrameSettings full = *presetSettings("hybrid-full", base);
  full.reuseRays = false;  // a still camera: every frame must read back and trace
  std::vector<double> rb;
  for (int i = 0; i < 3; ++i) rb.push_back(slot->renderer->render(slot->camera, full).readbackMs);
  slot->readbackMs = summarize(rb).median;
  return *slot;
}

void BM_VisibilityRaster(benchmark::State& state) {
  GlFrame& g = glFrame(sceneSpec(state.range(0)));
  if (!g.renderer) return state.SkipWithError(g.error.c_str());
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  FrameSettings s = *presetSettings("raster", base);
  s.shadows = s.reflections = s.refraction = EffectMode::Off;  // the visibility pass alone is timed
  (void)g.renderer->render(g.camera, s);
  for (auto _ : state) state.SetIterationTime(g.renderer->render(g.camera, s).rasterMs * 1e-3);
  state.counters["readback_ms"] = g.readbackMs;
}

// The raster preset's reflection probes (FrameSettings::probeLimit) on N mirror spheres (arg spheres: 10, 100,
// 1000) under a limit (arg limit) and a per-frame budget (arg perFrame, FrameSettings::probesPerFrame, 0: all):
// each iteration moves one sphere, so every probe is stale; the time is the probes stage's (probesMs). Counters:
// the probes the scene has and those a frame drew. The cost follows the probes drawn (min(N, limit), or the
// budget) times a face's draw, not N² (each probe draws the scene six times, small objects as coarse copies).
void BM_RasterProbes(benchmark::State& state) {
  GlFrame& g = glFrame("mirrors:" + std::to_string(state.range(0)));
  if (!g.renderer) return state.SkipWithError(g.error.c_str());
  FrameSettings base;
  base.width = 320;
  base.height = 180;
  FrameSettings s = *presetSettings("raster", base);
  s.probeLimit = static_cast<int>(state.range(1));
  s.probesPerFrame = static_cast<int>(state.range(2));
  int frame = 0;
  auto next = [&] {
    const float x = 0.1f * static_cast<float>(frame++ % 2);
    g.renderer->setInstanceTransform(1, glm::translate(glm::mat4(1.0f), glm::vec3(x, 1.0f, 0.0f)));
    return g.renderer->render(g.camera, s);
  };
  (void)next();  // the new limit's layout and the shader variants
  FrameStats last;
  for (auto _ : state) {
    last = next();
    state.SetIterationTime(last.probesMs * 1e-3);
  }
  state.counters["probes"] = last.probes;
  state.counters["drawn"] = last.probesDrawn;
}

// The frame interval in latency and in throughput mode (FrameSettings::pipelined, docs/pipeline.md): hybrid-full,
// every frame traced, the camera stepping each frame as a game's does; each iteration's time is the interval
// between render() calls (FrameStats::intervalMs), with the frame's latency and its wait for its rays beside.
void BM_FrameInterval(benchmark::State& state) {
  GlFrame& g = glFrame(sceneSpec(state.range(0)));
  if (!g.renderer) return state.SkipWithError(g.error.c_str());
  FrameSettings base;
  base.width = kWidth;
  base.height = kHeight;
  FrameSettings s = *presetSettings("hybrid-full", base);
  s.reuseRays = false;
  s.pipelined = state.range(1) != 0;
  Camera camera = g.camera;
  int frame = 0;
  auto next = [&] {
    camera.posW.x = g.camera.posW.x + 0.01f * static_cast<float>(frame++ % 8);
    return g.renderer->render(camera, s);
  };
  for (int i = 0; i < 2; ++i) (void)next();  // the shader variants, and the pipeline filled
  std::vector<double> latency, wait;
  for (auto _ : state) {
    const FrameStats st = next();
    state.SetIterationTime(st.intervalMs * 1e-3);
    latency.push_back(st.totalMs);
    wait.push_back(st.raysWaitMs);
  }
  (void)g.renderer->finish();
  state.counters["latency_ms"] = summarize(latency).median;
  state.counters["rays_wait_ms"] = summarize(wait).median;
}

// The spatiotemporal filter's passes alone (FrameStats::denoiseMs, docs/denoise.md) at its two target sizes,
// 640x360 (arg hd 0, 2 cores) and 1920x1080 (hd 1, the GPU class): area-lights.json, one light sample a frame,
// the camera panning ~2 pixels a frame (the history holds, the moved-instance test has nothing to test); arg
// fast 0: hybrid-full (rays at every pixel), 1: hybrid-fast (rays on a half-resolution grid, the upsampling
// stage). Counters: the shade pass with the filter's guides beside it (the composite less the filter), the
// whole frame; medians.
void BM_Denoise(benchmark::State& state) {
  GlFrame& g = glFrame(sourceDir() + "/assets/scenes/area-lights.json");
  if (!g.renderer) return state.SkipWithError(g.error.c_str());
  FrameSettings base;
  base.width = state.range(1) != 0 ? 1920 : 640;
  base.height = state.range(1) != 0 ? 1080 : 360;
  FrameSettings s = *presetSettings(state.range(0) != 0 ? "hybrid-fast" : "hybrid-full", base);
  s.denoise = true;
  s.lightSamples = 1;
  Camera camera = g.camera;
  int frame = 0;
  // (the sweep's pan, tools/bench/Sweep.cpp: 0.004 of the view distance a frame along the camera's right,
  // here back and forth)
  const glm::vec3 forward = g.camera.targetW - g.camera.posW;
  const glm::vec3 right = glm::normalize(glm::cross(forward, g.camera.upW));
  auto next = [&] {
    const int k = frame++ % 480;
    const glm::vec3 shift = right * (0.004f * glm::length(forward) * static_cast<float>(k < 240 ? k : 480 - k));
    camera.posW = g.camera.posW + shift;
    camera.targetW = g.camera.targetW + shift;
    return g.renderer->render(camera, s);
  };
  for (int i = 0; i < 4; ++i) (void)next();  // the variants compiled, a history held
  std::vector<double> shade, total, filter;
  for (auto _ : state) {
    const FrameStats st = next();
    if (!st.denoised) return state.SkipWithError("the frame was not filtered");
    state.SetIterationTime(st.denoiseMs * 1e-3);
    filter.push_back(st.denoiseMs);
    shade.push_back(st.compositeMs - st.denoiseMs);
    total.push_back(st.totalMs);
  }
  state.counters["filter_median_ms"] = summarize(filter).median;
  state.counters["shade_ms"] = summarize(shade).median;
  state.counters["frame_ms"] = summarize(total).median;
}

void BM_VisibilityCastRays(benchmark::State& state) {
  RtFrame& f = rtFrame(state.range(0));
  if (!f.tracer) return state.SkipWithError(f.error.c_str());
  rt::VisibilityBuffer v;
  for (auto _ : state) f.tracer->castVisibility(f.scene.camera, kWidth, kHeight, v);
  state.counters["Mrays/s"] = benchmark::Counter(kWidth * kHeight * 1e-6 * static_cast<double>(state.iterations()),
                                                 benchmark::Counter::kIsRate);
}

}  // namespace

void registerMicroBenchmarks() {
  auto scenes = [](benchmark::internal::Benchmark* b) { b->ArgName("heavy")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond); };
  scenes(benchmark::RegisterBenchmark("BM_RayPass", BM_RayPass)->MinTime(2.0));
  benchmark::RegisterBenchmark("BM_RayPassHybridShadows", BM_RayPassHybridShadows)
      ->ArgNames({"heavy", "proofs"})
      ->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})->Args({0, 2})->Args({1, 2})
      ->Unit(benchmark::kMillisecond)
      ->MinTime(2.0);
  benchmark::RegisterBenchmark("BM_RayPassKeptShadows", BM_RayPassKeptShadows)
      ->ArgNames({"keep", "fast"})
      ->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})
      ->MinTime(2.0)
      ->Unit(benchmark::kMillisecond);
  scenes(benchmark::RegisterBenchmark("BM_RetraceFloor", BM_RetraceFloor));
  scenes(benchmark::RegisterBenchmark("BM_ShadowOccluded1", BM_ShadowOccluded1));
  scenes(benchmark::RegisterBenchmark("BM_ShadowOccluded1M", BM_ShadowOccluded1M));
  scenes(benchmark::RegisterBenchmark("BM_ShadowOccluded8", BM_ShadowOccluded8));
  benchmark::RegisterBenchmark("BM_Flip1280x720", BM_Flip1280x720)->Unit(benchmark::kMillisecond);
  scenes(benchmark::RegisterBenchmark("BM_VisibilityRaster", BM_VisibilityRaster)->UseManualTime());
  scenes(benchmark::RegisterBenchmark("BM_VisibilityCastRays", BM_VisibilityCastRays));
  benchmark::RegisterBenchmark("BM_Denoise", BM_Denoise)
      ->ArgNames({"fast", "hd"})
      ->Args({0, 0})->Args({1, 0})->Args({0, 1})->Args({1, 1})
      ->UseManualTime()
      ->MinTime(3.0)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_RasterProbes", BM_RasterProbes)
      ->ArgNames({"spheres", "limit", "perFrame"})
      ->Args({10, 8, 0})->Args({100, 8, 0})->Args({1000, 8, 0})->Args({10, 32, 0})->Args({100, 32, 0})
      ->Args({1000, 32, 0})->Args({10, 32, 4})->Args({100, 32, 4})->Args({1000, 32, 4})
      ->UseManualTime()
      ->Iterations(3)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_FrameInterval", BM_FrameInterval)
      ->ArgNames({"heavy", "pipelined"})
      ->Args({0, 0})->Args({0, 1})
      ->UseManualTime()
      ->MinTime(3.0)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace tandem::bench
