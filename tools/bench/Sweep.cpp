#include "Sweep.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "BenchCommon.h"
#include "Plots.h"
#include "core/Motion.h"
#include "core/Timer.h"
#include "render/FrameBudget.h"
#include "rt/RayCapture.h"
#include "rt/RayTracerBench.h"
#include "rt/RayTracer.h"
#include "tandem/Context.h"
#include "tandem/HeavyScene.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Renderer.h"

namespace fs = std::filesystem;

namespace tandem::bench {

namespace {

// The stages of FrameStats in the order of the frame (kFrameStages, tandem/FrameStats.h): every part of it.
struct StageField {
  const char* name;
  double FrameStats::*field;
};
constexpr std::size_t kStageCount = std::size(kFrameStages);
constexpr std::array<StageField, kStageCount> stageFields() {
  std::array<StageField, kStageCount> f{};
  for (std::size_t i = 0; i < kStageCount; ++i) f[i] = {kFrameStages[i].name, kFrameStages[i].cpu};
  return f;
}
constexpr std::array<StageField, kStageCount> kStages = stageFields();
// Index of a stage by name (for the progress lines).
constexpr std::size_t stageIndex(std::string_view name) {
  for (std::size_t i = 0; i < kStageCount; ++i)
    if (name == kFrameStages[i].name) return i;
  return 0;
}

struct Combo {
  std::string name;
  std::string group;   // "preset", "effect", "budget-knob" (one knob of the budget alone), "aa" or "budget"
  FrameSettings settings;
  /// Drawn with the camera moving (kPanFrames frames of a sideways pan that ends at the scene's camera, the
  /// measured frames the pan's last): the spatiotemporal filter's combinations, measured in motion.
  bool moving = false;
};

std::string modes(const FrameSettings& s) {
  std::string m = std::string(shadowModeName(s)) + "/" + std::string(toString(s.reflections)) + "/" +
                  std::string(toString(s.refraction));
  if (s.reference) m = "primary by rays, " + m;
  m += " d" + std::to_string(s.maxDepth);
  if (s.rayScale > 1) m += " 1/" + std::to_string(s.rayScale);
  if (s.aa == AntiAlias::Ssaa) m += " ssaa " + std::to_string(s.aaSamples);
  if (s.aa == AntiAlias::Adaptive) m += " adaptive " + std::to_string(s.aaSamples);
  if (s.targetMs > 0) m += " within " + std::to_string(static_cast<int>(std::lround(s.targetMs))) + " ms";
  if (s.denoise) m += " denoised, camera moving";
  return m;
}

/// The combinations: every preset (reference at 1 spp: the speed competitor, primary visibility by
/// rays), and per effect the two isolating pairs — only that effect ray traced over the raster preset,
/// and only that effect rasterized under hybrid-full — plus everything off, hybrid-full at half
/// resolution, the budget's other knobs alone (1/4 grid, depth 2 and 1), hybrid shadows and three anti-aliased
/// frames (ssaa 4 over hybrid-fast and hybrid-full, adaptive up to 16 over hybrid-full). 19 in all (3 more
/// with area lights, 2 more with glossy materials, 2 more with either: the spatiotemporal filter), and
/// two budget runs after them (kBudgetFractions): enough to draw a front and measure the budget's error
/// table, few enough for about 15 minutes on two cores. A scene with area lights adds their sample counts
/// over hybrid-full (1 and 16; the presets draw 4) and the raster preset's soft shadows at 16; one with glossy
/// materials, their ray counts over hybrid-full (1 and 16); one whose camera has a lens or moving instances,
/// 16 lens and time samples (ssaa 16) over hybrid-full and raster.
std::vector<Combo> makeCombos(const FrameSettings& base, bool areaLights = false, bool glossy = false,
                              bool lensOrMotion = false) {
  std::vector<Combo> c;
  for (const std::string& p : presetNames()) {
    FrameSettings s = *presetSettings(p, base);
    if (s.reference) s.referenceSpp = 1;
    c.push_back({p, "preset", s});
  }
  FrameSettings raster = *presetSettings("raster", base), full = *presetSettings("hybrid-full", base);
  FrameSettings off = raster;
  off.shadows = off.reflections = off.refraction = EffectMode::Off;
  c.push_back({"all-off", "effect", off});
  struct Effect {
    const char* name;
    EffectMode FrameSettings::*mode;
  };
  const Effect effects[] = {{"shadows", &FrameSettings::shadows},
                            {"reflections", &FrameSettings::reflections},
                            {"refraction", &FrameSettings::refraction}};
  for (const Effect& e : effects) {
    FrameSettings only = raster;
    only.*(e.mode) = EffectMode::Ray;
    only.maxDepth = full.maxDepth;  // the ray-traced effect gets hybrid-full's recursion
    only.minContribution = full.minContribution;
    c.push_back({std::string(e.name) + "-ray-only", "effect", only});
  }
  for (const Effect& e : effects) {
    FrameSettings without = full;
    without.*(e.mode) = EffectMode::Raster;
    c.push_back({std::string(e.name) + "-raster", "effect", without});
  }
  FrameSettings half = full;
  half.rayScale = 2;
  c.push_back({"hybrid-full-half", "effect", half});
  // The frame-time budget's knobs, each alone over hybrid-full (its error table, render/FrameBudget.h).
  FrameSettings quarter = full, d2 = full, d1 = full, hybridShadows = full;
  quarter.rayScale = 4;
  d2.maxDepth = 2;
  d1.maxDepth = 1;
  c.push_back({"hybrid-full-quarter", "budget-knob", quarter});
  c.push_back({"hybrid-full-d2", "budget-knob", d2});
  c.push_back({"hybrid-full-d1", "budget-knob", d1});
  // Hybrid shadows: the same image as hybrid-full, by fewer shadow rays (docs/shadows.md).
  hybridShadows.hybridShadows = true;
  c.push_back({"hybrid-shadows", "effect", hybridShadows});
  // Anti-aliasing: what supersampling buys against the supersampled truth, per sample (docs/antialiasing.md).
  FrameSettings fastSsaa = *presetSettings("hybrid-fast", base), fullSsaa = full, fullAdaptive = full;
  fastSsaa.aa = fullSsaa.aa = AntiAlias::Ssaa;
  fastSsaa.aaSamples = fullSsaa.aaSamples = 4;
  fullAdaptive.aa = AntiAlias::Adaptive;
  fullAdaptive.aaSamples = 16;
  c.push_back({"hybrid-fast-ssaa4", "aa", fastSsaa});
  c.push_back({"hybrid-full-ssaa4", "aa", fullSsaa});
  c.push_back({"hybrid-full-adaptive16", "aa", fullAdaptive});
  if (glossy) {
    // Glossy materials: lobe rays per primary hit (docs/glossy.md).
    FrameSettings one = full, sixteen = full;
    one.glossSamples = 1;
    sixteen.glossSamples = 16;
    c.push_back({"hybrid-full-gloss1", "gloss-samples", one});
    c.push_back({"hybrid-full-gloss16", "gloss-samples", sixteen});
  }
  if (areaLights) {
    // Area lights: samples per light and pixel, each a shadow ray (docs/area-lights.md).
    FrameSettings one = full, sixteen = full, rasterSixteen = raster;
    one.lightSamples = 1;
    sixteen.lightSamples = rasterSixteen.lightSamples = 16;
    c.push_back({"hybrid-full-light1", "light-samples", one});
    c.push_back({"hybrid-full-light16", "light-samples", sixteen});
    c.push_back({"raster-light16", "light-samples", rasterSixteen});
  }
  if (areaLights || glossy) {
    // The spatiotemporal filter (docs/denoise.md), the camera moving: one light and lobe sample a frame, and
    // hybrid-full's own four, each frame reconstructed from the last frames'; and hybrid-fast's half-resolution
    // ray grid with one sample (the filter on the grid's pixels). Against the raw frames above
    // (hybrid-full-light1 / -gloss1, hybrid-full, hybrid-fast), which have no history and are the same still or
    // moving.
    FrameSettings one = full, four = full, fastOne = *presetSettings("hybrid-fast", base);
    one.lightSamples = one.glossSamples = fastOne.lightSamples = fastOne.glossSamples = 1;
    one.denoise = four.denoise = fastOne.denoise = true;
    c.push_back({"hybrid-full-1-denoised", "denoise", one, true});
    c.push_back({"hybrid-full-denoised", "denoise", four, true});
    c.push_back({"hybrid-fast-1-denoised", "denoise", fastOne, true});
  }
  if (lensOrMotion) {
    // Depth of field and motion blur: every anti-aliasing sample sees through a new lens point at a new time
    // of the shutter (docs/depth-of-field.md, docs/motion-blur.md).
    FrameSettings fullSampled = full, rasterSampled = raster;
    fullSampled.aa = rasterSampled.aa = AntiAlias::Ssaa;
    fullSampled.aaSamples = rasterSampled.aaSamples = 16;
    c.push_back({"hybrid-full-ssaa16", "lens-time-samples", fullSampled});
    c.push_back({"raster-ssaa16", "lens-time-samples", rasterSampled});
  }
  return c;
}

/// One point of the error-vs-frames curve: after `frames` accumulated frames of `combo`, their summed time
/// and the error of the converged image so far against the reference.
struct ConvergePoint {
  std::string scene;
  Size size;
  std::string combo;
  int frames = 0;
  double totalMs = 0;
  double flipMean = 0;
};

/// The budget's points: hybrid-full with a target of these fractions of its own measured frame time.
constexpr double kBudgetFractions[] = {0.75, 0.5};
/// The presets whose accumulation the error-vs-frames curve follows.
constexpr const char* kConvergePresets[] = {"hybrid-fast", "hybrid-full"};
/// Frames a budget run gets to settle before it is measured (the model learns from the first ones).
constexpr int kBudgetSettleFrames = 30;

struct Row {
  std::string scene;
  Size size;
  Combo combo;
  int frames = 0;
  Stat total;
  Stat stage[kStageCount];
  RayCounts rays;
  double mraysPerS = 0;
  double rssMiB = 0, peakRssMiB = 0;
  double flipMean = 0, psnrDb = 0, ssim = 0;
  int threads = 0;
  bool pareto = false;
  std::string budgetChoice;  // budget rows: what the last measured frame was drawn with
};

struct Ceiling {
  std::string scene;
  Size size;
  RayCounts rays;
  double passMs = 0;                               // RayTracer::trace, median
  double rendererRaysMs = 0;                       // FrameStats::raysMs of hybrid-full in the sweep
  double floorMs = 0;                              // Σ per kind of the fastest API
  double kindMs[rt::kRetraceApis][rt::kRayKinds]{};  // [api][kind] medians (rt::RetraceApi)
  double rasterMs = 0, readbackMs = 0;             // Renderer, hybrid-full
  double castVisibilityMs = 0;                     // primary visibility by Embree rays
  int threads = 0;
};

/// Marks the non-dominated rows of one scene × size: no other row is at most as slow and at most as
/// wrong, and strictly better in one of the two.
void markPareto(std::vector<Row*>& rows) {
  for (Row* a : rows) {
    a->pareto = true;
    for (Row* b : rows) {
      if (a == b) continue;
      bool noWorse = b->total.median <= a->total.median && b->flipMean <= a->flipMean;
      bool better = b->total.median < a->total.median || b->flipMean < a->flipMean;
      if (noWorse && better) {
        a->pareto = false;
        break;
      }
    }
  }
}

std::string fileSafe(std::string s) {
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
  return s;
}

void printHeader(const Machine& m, const GlContext& ctx, int threads, const SweepOptions& o) {
  std::printf("tandem-bench on %s (%d logical CPUs)\n", m.cpu.c_str(), m.logicalCpus);
  std::printf("  GL: %s\n", ctx.describe().c_str());
  std::printf("  threads: ray pass (TBB arena) %d, TBB default %d, LP_NUM_THREADS %s; Embree %s\n", threads,
              m.tbbThreads, m.lpNumThreads.c_str(), m.embreeVersion.c_str());
  std::printf("  frames: %d warm-up (and at least %.1f s of them) + %d measured per combination; output %s\n", o.warmup,
              o.warmupSeconds, o.frames, o.out.c_str());
  std::fflush(stdout);
}

int truthSppFor(const SweepOptions& o, Size s) {
  if (o.truthSpp > 0) return o.truthSpp;
  return static_cast<long>(s.width) * s.height <= 640L * 360L ? 8 : 4;
}

struct FrameRun {
  std::vector<FrameStats> stats;
  Image image;
};

// Every frame traces: the camera stands still, and reusing the last frame's rays would time a still frame,
// not the frame's cost.
// The warm-up is `warmup` frames and at least `warmupSeconds` of frames: a GPU left idle (between
// combinations, or while the floor is measured) runs at its lowest clock and needs a while to come up (an H100
// drew Whitted's raster frame in 9.8 ms over 2 warm-up frames and 1.8 ms once warm; docs/bench.md).
/// Frames a moving combination's pan takes before its measured frames (the filter's history fills meanwhile).
constexpr int kPanFrames = 16;

/// `camera` moved sideways by `steps` pan steps (0.4 % of its distance to the target each: about 2 pixels a
/// frame on the target at 360 rows and a 42-degree field of view).
Camera panned(const Camera& camera, int steps) {
  const glm::vec3 forward = camera.targetW - camera.posW;
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.upW));
  const glm::vec3 shift = right * (0.004f * glm::length(forward) * static_cast<float>(steps));
  Camera c = camera;
  c.posW += shift;
  c.targetW += shift;
  return c;
}

FrameRun renderFrames(Renderer& r, const Camera& camera, FrameSettings s, int warmup, double warmupSeconds, int frames,
                      bool moving = false) {
  s.reuseRays = false;
  FrameRun run;
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  // Moving: the warm-up where the pan starts, then the pan, its last `frames` frames measured, the last one at
  // `camera` (the truth's view).
  const int pan = moving ? kPanFrames + frames : 0;
  for (int i = 0; i < warmup || (i < 1000 && seconds() < warmupSeconds); ++i) (void)r.render(panned(camera, -pan), s);
  for (int i = 1; i <= pan - frames; ++i) (void)r.render(panned(camera, i - pan), s);
  for (int i = 0; i < frames; ++i) run.stats.push_back(r.render(panned(camera, moving ? i + 1 - frames : 0), s));
  run.image = r.readImage();
  return run;
}

Stat stageStat(const std::vector<FrameStats>& v, double FrameStats::*field) {
  std::vector<double> x;
  for (const FrameStats& f : v) x.push_back(f.*field);
  return summarize(x);
}

double medianOf(int n, const std::function<double()>& f) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(f());
  return summarize(v).median;
}

/// One combination's row: stage statistics of its measured frames, rays, memory, error against the truth.
Row measuredRow(const std::string& scene, Size size, const Combo& combo, int frames, const FrameRun& run,
                const Image& truth) {
  Row row;
  row.scene = scene;
  row.size = size;
  row.combo = combo;
  row.frames = frames;
  row.total = stageStat(run.stats, &FrameStats::totalMs);
  for (std::size_t i = 0; i < kStageCount; ++i) row.stage[i] = stageStat(run.stats, kStages[i].field);
  row.rays = run.stats.back().rays;
  row.threads = run.stats.back().threads;
  row.mraysPerS =
      row.stage[3].median > 0 ? static_cast<double>(row.rays.total()) / (row.stage[3].median * 1e3) : 0.0;
  row.rssMiB = currentRssMiB();
  row.peakRssMiB = peakRssMiB();
  if (auto e = compare(run.image, truth)) {
    row.flipMean = e->flipMean;
    row.psnrDb = e->psnr;
    row.ssim = e->ssim;
  }
  return row;
}

Ceiling measureCeiling(const Scene& scene, Size size, const FrameSettings& full, int threads, int frames) {
  Ceiling c;
  auto tracer = rt::RayTracer::create(threads);
  if (!tracer) return c;
  if (!(*tracer)->setScene(scene)) return c;
  rt::RayTracer& t = **tracer;
  c.threads = t.threads();
  rt::VisibilityBuffer vis;
  t.castVisibility(scene.camera, size.width, size.height, vis);  // warm
  c.castVisibilityMs = medianOf(frames, [&] {
    Timer timer;
    t.castVisibility(scene.camera, size.width, size.height, vis);
    return timer.ms();
  });
  rt::RayOutputs out;
  t.trace(scene, scene.camera, full, vis, out);  // warm
  c.passMs = medianOf(frames, [&] {
    Timer timer;
    t.trace(scene, scene.camera, full, vis, out);
    return timer.ms();
  });
  rt::RayCapture capture;
  rt::RayTracerBench::trace(t, scene, scene.camera, full, vis, out, {&capture});
  c.rays = capture.counts();
  for (int api = 0; api < rt::kRetraceApis; ++api) {
    rt::RetraceOptions opt;
    opt.api.fill(static_cast<rt::RetraceApi>(api));
    (void)rt::RayTracerBench::retrace(t, capture, opt);  // warm
    std::vector<rt::RetraceStats> runs;
    for (int i = 0; i < frames; ++i) runs.push_back(rt::RayTracerBench::retrace(t, capture, opt));
    for (std::size_t k = 0; k < rt::kRayKinds; ++k) {
      std::vector<double> v;
      for (const auto& r : runs) v.push_back(r.ms[k]);
      c.kindMs[api][k] = summarize(v).median;
    }
  }
  for (std::size_t k = 0; k < rt::kRayKinds; ++k)
    c.floorMs += std::min({c.kindMs[0][k], c.kindMs[1][k], c.kindMs[2][k]});
  return c;
}

void writeSweepCsv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream f(path);
  f << "scene,width,height,combination,group,shadows,reflections,refraction,max_depth,ray_scale,reference,frames,"
       "total_ms_median,total_ms_min,total_ms_max";
  for (const StageField& s : kStages) f << "," << s.name << "_ms_median," << s.name << "_ms_min," << s.name << "_ms_max";
  f << ",rays_primary,rays_shadow,rays_reflection,rays_refraction,rays_resolved,mrays_per_s,rss_mib,peak_rss_mib,"
       "threads,flip_mean,psnr_db,ssim,pareto\n";
  for (const Row& r : rows) {
    const FrameSettings& s = r.combo.settings;
    f << r.scene << "," << r.size.width << "," << r.size.height << "," << r.combo.name << "," << r.combo.group << ","
      << toString(s.shadows) << "," << toString(s.reflections) << "," << toString(s.refraction) << "," << s.maxDepth
      << "," << s.rayScale << "," << (s.reference ? 1 : 0) << "," << r.frames << "," << r.total.median << ","
      << r.total.min << "," << r.total.max;
    for (const Stat& st : r.stage) f << "," << st.median << "," << st.min << "," << st.max;
    f << "," << r.rays.primary << "," << r.rays.shadow << "," << r.rays.reflection << "," << r.rays.refraction << ","
      << r.rays.resolved << "," << r.mraysPerS << "," << r.rssMiB << "," << r.peakRssMiB << "," << r.threads << "," << r.flipMean << ","
      << r.psnrDb << "," << r.ssim << "," << (r.pareto ? 1 : 0) << "\n";
  }
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void writeSweepMarkdown(const std::string& path, const std::vector<Row>& rows, const std::vector<Ceiling>& ceilings,
                        const Machine& m, const std::string& gl, int threads, const SweepOptions& o) {
  std::ofstream f(path);
  f << "# tandem-bench sweep\n\n";
  f << "Machine: " << m.cpu << ", " << m.logicalCpus << " logical CPUs; GL: " << gl << "; ray-pass threads "
    << threads << "; LP_NUM_THREADS " << m.lpNumThreads << "; Embree " << m.embreeVersion << ". "
    << o.warmup << " warm-up (at least " << o.warmupSeconds << " s) + " << o.frames << " measured frames per combination; times in ms are "
    << "median [min–max]. Error against the reference at N×N spp (N in the section title). ★ = on the "
    << "Pareto front (frame time vs FLIP).\n";
  std::string section;
  for (const Row& r : rows) {
    std::string key = r.scene + " " + r.size.label();
    if (key != section) {
      section = key;
      f << "\n## " << r.scene << " " << r.size.label() << " (reference " << truthSppFor(o, r.size) << "×"
        << truthSppFor(o, r.size) << " spp)\n\n";
      f << "| combination | shadows/reflections/refraction | frame ms | prepare | raster | readback | rays | upload "
           "| composite | rays/frame P/S/R/T (+X resolved) | Mrays/s | peak RSS MiB | FLIP | PSNR dB | SSIM | front |\n";
      f << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    }
    f << "| " << r.combo.name << " | " << modes(r.combo.settings)
      << (r.budgetChoice.empty() ? std::string() : " → " + r.budgetChoice) << " | " << fmt("%.1f", r.total.median) << " ["
      << fmt("%.1f", r.total.min) << "–" << fmt("%.1f", r.total.max) << "]";
    for (const Stat& st : r.stage) f << " | " << fmt("%.1f", st.median);
    f << " | " << r.rays.primary << "/" << r.rays.shadow << "/" << r.rays.reflection << "/" << r.rays.refraction
      << (r.rays.resolved > 0 ? " +" + std::to_string(r.rays.resolved) : std::string()) << " | " << fmt("%.2f", r.mraysPerS) << " | " << fmt("%.0f", r.peakRssMiB) << " | " << fmt("%.4f", r.flipMean)
      << " | " << (std::isinf(r.psnrDb) ? std::string("inf") : fmt("%.2f", r.psnrDb)) << " | "
      << fmt("%.4f", r.ssim) << " | " << (r.pareto ? "★" : "") << " |\n";
  }
  if (!ceilings.empty()) {
    f << "\n## The ceiling (hybrid-full): ray pass vs raw Embree re-trace of the same captured rays\n\n";
    f << "| scene | size | rays S/R/T | ray pass ms | floor ms | pass ÷ floor | shadow 1 / 1M / 8 ms | reflection 1 / 1M "
         "/ 8 ms | refraction 1 / 1M / 8 ms | raster+readback ms (llvmpipe) | castVisibility ms (Embree) |\n";
    f << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto apis = [&](const Ceiling& c, int k) {
      return fmt("%.1f", c.kindMs[0][k]) + " / " + fmt("%.1f", c.kindMs[1][k]) + " / " + fmt("%.1f", c.kindMs[2][k]);
    };
    for (const Ceiling& c : ceilings)
      f << "| " << c.scene << " | " << c.size.label() << " | " << c.rays.shadow << "/" << c.rays.reflection << "/"
        << c.rays.refraction << " | " << fmt("%.1f", c.passMs) << " | " << fmt("%.1f", c.floorMs) << " | "
        << (c.floorMs > 0 ? fmt("%.2f×", c.passMs / c.floorMs) : std::string("–")) << " | " << apis(c, 1) << " | "
        << apis(c, 2) << " | " << apis(c, 3) << " | " << fmt("%.1f", c.rasterMs + c.readbackMs) << " | "
        << fmt("%.1f", c.castVisibilityMs) << " |\n";
  }
}

/// convergence.csv and convergence.md: the error-vs-frames curves.
void writeConvergence(const SweepOptions& o, const std::vector<ConvergePoint>& points) {
  if (points.empty()) return;
  std::ofstream csv(fs::path(o.out) / "convergence.csv");
  csv << "scene,width,height,combination,frames,total_ms,flip_mean\n";
  for (const ConvergePoint& p : points)
    csv << p.scene << "," << p.size.width << "," << p.size.height << "," << p.combo << "," << p.frames << ","
        << p.totalMs << "," << p.flipMean << "\n";
  std::ofstream md(fs::path(o.out) / "convergence.md");
  md << "# Error against the reference vs accumulated frames\n\nEach frame of an accumulation adds new pixel, "
        "area-light, gloss and lens samples (FrameSettings::accumulate); FLIP mean against the reference after "
        "N frames, and the N frames' summed time in ms.\n\n| scene | size | combination | frames | total ms | FLIP |\n"
        "|---|---|---|---|---|---|\n";
  for (const ConvergePoint& p : points)
    md << "| " << p.scene << " | " << p.size.label() << " | " << p.combo << " | " << p.frames << " | "
       << fmt("%.0f", p.totalMs) << " | " << fmt("%.4f", p.flipMean) << " |\n";
}

void writeCeilingCsv(const std::string& path, const std::vector<Ceiling>& ceilings) {
  std::ofstream f(path);
  f << "scene,width,height,threads,rays_shadow,rays_reflection,rays_refraction,pass_ms,renderer_rays_ms,floor_ms,"
       "ratio,shadow_1_ms,shadow_1m_ms,shadow_8_ms,reflection_1_ms,reflection_1m_ms,reflection_8_ms,refraction_1_ms,"
       "refraction_1m_ms,refraction_8_ms,raster_ms,readback_ms,cast_visibility_ms\n";
  for (const Ceiling& c : ceilings) {
    f << c.scene << "," << c.size.width << "," << c.size.height << "," << c.threads << "," << c.rays.shadow << ","
      << c.rays.reflection << "," << c.rays.refraction << "," << c.passMs << "," << c.rendererRaysMs << ","
      << c.floorMs << "," << (c.floorMs > 0 ? c.passMs / c.floorMs : 0.0);
    for (int k = 1; k < static_cast<int>(rt::kRayKinds); ++k)
      for (int api = 0; api < rt::kRetraceApis; ++api) f << "," << c.kindMs[api][k];
    f << "," << c.rasterMs << "," << c.readbackMs << "," << c.castVisibilityMs << "\n";
  }
}

/// The budget's error table as this sweep measured it: per knob, the mean over scenes × sizes of the FLIP
/// it adds to hybrid-full, next to the table the engine uses (render/FrameBudget.h).
void writeBudgetTable(const std::string& path, const std::vector<Row>& rows) {
  const BudgetErrorTable& engine = budgetErrorTable();
  struct Knob {
    const char* combo;
    const char* field;
    double engine;
  } knobs[] = {{"hybrid-full-half", "rayScale2", engine.rayScale2},
               {"hybrid-full-quarter", "rayScale4", engine.rayScale4},
               {"hybrid-full-d2", "depth2", engine.depth2},
               {"hybrid-full-d1", "depth1", engine.depth1},
               {"refraction-raster", "refractionRaster", engine.refractionRaster},
               {"reflections-raster", "reflectionsRaster", engine.reflectionsRaster},
               {"shadows-raster", "shadowsRaster", engine.shadowsRaster},
               {"hybrid-full-1-denoised", "filtered", engine.filtered}};
  std::ofstream f(path);
  f << "# The budget's error table\n\nFLIP each knob adds to hybrid-full against the reference, mean [min–max] "
       "over the sweep's scenes × sizes, and the value the engine uses (render/FrameBudget.cpp).\n\n"
       "| knob | sweep combination | measured mean | min | max | engine |\n|---|---|---|---|---|---|\n";
  std::printf("budget error table (FLIP added to hybrid-full; measured mean vs the engine's):\n");
  for (const Knob& k : knobs) {
    std::vector<double> d;
    for (const Row& full : rows) {
      if (full.combo.name != "hybrid-full") continue;
      // The budget offers the filter only where the camera is a pinhole with a closed shutter: not on a scene
      // whose camera has a lens or whose instances move under its shutter (those have the ssaa16 rows).
      const bool lensOrMotion = std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
        return r.combo.name == "hybrid-full-ssaa16" && r.scene == full.scene && r.size.label() == full.size.label();
      });
      if (lensOrMotion && std::string(k.field) == "filtered") continue;
      for (const Row& r : rows)
        if (r.combo.name == k.combo && r.scene == full.scene && r.size.label() == full.size.label())
          d.push_back(r.flipMean - full.flipMean);
    }
    if (d.empty()) continue;
    double sum = 0;
    for (double x : d) sum += x;
    const double mean = sum / static_cast<double>(d.size());
    f << "| " << k.field << " | " << k.combo << " | " << fmt("%.4f", mean) << " | "
      << fmt("%.4f", *std::min_element(d.begin(), d.end())) << " | " << fmt("%.4f", *std::max_element(d.begin(), d.end()))
      << " | " << fmt("%.4f", k.engine) << " |\n";
    std::printf("  %-18s measured %+.4f  engine %+.4f\n", k.field, mean, k.engine);
  }
}

struct Setup {
  Machine machine;
  std::unique_ptr<GlContext> context;
  std::unique_ptr<Renderer> renderer;
  int threads = 0;
};

int makeSetup(const SweepOptions& o, Setup& s) {
  s.machine = describeMachine();
  auto ctx = createGlContext({});
  if (!ctx) {
    std::fprintf(stderr, "tandem-bench: no GL context: %s\n", ctx.error().message.c_str());
    return 1;
  }
  s.context = std::move(*ctx);
  RendererDesc desc;
  desc.threads = o.threads;
  auto r = Renderer::create(*s.context, desc);
  if (!r) {
    std::fprintf(stderr, "tandem-bench: %s\n", r.error().message.c_str());
    return 1;
  }
  s.renderer = std::move(*r);
  s.threads = o.threads > 0 ? o.threads : s.machine.logicalCpus;
  std::error_code ec;
  fs::create_directories(fs::path(o.out) / "images", ec);
  fs::create_directories(fs::path(o.out) / "data", ec);
  if (ec) {
    std::fprintf(stderr, "tandem-bench: cannot create %s: %s\n", o.out.c_str(), ec.message().c_str());
    return 1;
  }
  printHeader(s.machine, *s.context, s.threads, o);
  return 0;
}

}  // namespace

int runSweep(const SweepOptions& o) {
  Setup setup;
  if (int rc = makeSetup(o, setup)) return rc;
  Renderer& renderer = *setup.renderer;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  struct Loaded {
    std::string spec, label;
    Scene scene;
  };
  std::vector<Loaded> scenes;
  for (const std::string& spec : o.scenes) {
    auto s = loadBenchScene(spec);
    if (!s) {
      std::printf("  skipping %s: %s\n", spec.c_str(), s.error().message.c_str());
      continue;
    }
    scenes.push_back({spec, sceneLabel(spec), std::move(*s)});
  }
  if (scenes.empty()) {
    std::fprintf(stderr, "tandem-bench: no scene could be loaded\n");
    return 1;
  }
  auto hasAreaLights = [](const Scene& scene) {
    for (const Light* l : scene.directLights())
      if (isAreaLight(l->type)) return true;
    return false;
  };
  auto hasGloss = [](const Scene& scene) {
    for (const Material& m : scene.materials)
      if (m.roughness > 0.0f && (m.kr > 0.0f || m.kt > 0.0f)) return true;
    return false;
  };
  auto hasLensOrMotion = [](const Scene& scene) {
    if (scene.camera.aperture > 0.0f && !scene.camera.orthographic) return true;
    for (const Instance& inst : scene.instances)
      if (isMoving(inst, scene.camera.shutter)) return true;
    return false;
  };
  auto combosFor = [&](const Scene& scene) {
    return makeCombos(FrameSettings{}, hasAreaLights(scene), hasGloss(scene), hasLensOrMotion(scene)).size() +
           std::size(kBudgetFractions) + (o.convergeFrames > 0 ? std::size(kConvergePresets) : 0);
  };
  std::size_t totalSteps = 0;
  for (const Loaded& l : scenes) totalSteps += o.sizes.size() * (combosFor(l.scene) + 2);  // + truth + ceiling
  std::size_t done = 0;
  auto progress = [&](const std::string& what) {
    ++done;
    double t = elapsed();
    double eta = t / static_cast<double>(done) * static_cast<double>(totalSteps - done);
    std::printf("[%3zu/%zu %s, ETA %s] %s\n", done, totalSteps, formatDuration(t).c_str(), formatDuration(eta).c_str(),
                what.c_str());
    std::fflush(stdout);
  };

  std::vector<Row> rows;
  std::vector<ConvergePoint> converge;
  std::vector<Ceiling> ceilings;
  std::vector<HeatPanel> heat;
  for (Loaded& l : scenes) {
    std::printf("scene %s: %zu triangles, %zu instances, %zu lights\n", l.label.c_str(), l.scene.triangleCount(),
                l.scene.instances.size(), l.scene.directLights().size());
    if (auto r = renderer.setScene(l.scene); !r) {
      std::printf("  skipping %s: %s\n", l.label.c_str(), r.error().message.c_str());
      done += o.sizes.size() * (combosFor(l.scene) + 2);
      continue;
    }
    const Camera camera = l.scene.camera;
    for (Size size : o.sizes) {
      FrameSettings base;
      base.width = size.width;
      base.height = size.height;
      // Ground truth: the reference preset, N×N jittered spp, rendered once.
      FrameSettings truthSettings = *presetSettings("reference", base);
      truthSettings.referenceSpp = truthSppFor(o, size);
      // Area lights and glossy rays: 16 samples in each of the N×N pixel samples (the presets draw 4).
      if (hasAreaLights(l.scene)) truthSettings.lightSamples = 16;
      if (hasGloss(l.scene)) truthSettings.glossSamples = 16;
      Timer truthTimer;
      FrameRun truth = renderFrames(renderer, camera, truthSettings, 0, 0.0, 1);
      std::string prefix = fileSafe(l.label) + "-" + size.label();
      (void)writePng((fs::path(o.out) / "images" / (prefix + "-truth.png")).string(), truth.image);
      progress(l.label + " " + size.label() + " reference " + std::to_string(truthSettings.referenceSpp) + "x" +
               std::to_string(truthSettings.referenceSpp) + " spp (ground truth): " + fmt("%.0f ms", truthTimer.ms()));

      std::map<std::string, Image> images;
      std::vector<std::size_t> mine;
      for (const Combo& combo : makeCombos(base, hasAreaLights(l.scene), hasGloss(l.scene), hasLensOrMotion(l.scene))) {
        FrameRun run = renderFrames(renderer, camera, combo.settings, o.warmup, o.warmupSeconds, o.frames, combo.moving);
        Row row = measuredRow(l.label, size, combo, o.frames, run, truth.image);
        (void)writePng((fs::path(o.out) / "images" / (prefix + "-" + combo.name + ".png")).string(), run.image);
        images[combo.name] = std::move(run.image);
        progress(l.label + " " + size.label() + " " + combo.name + ": " + fmt("%.1f ms", row.total.median) +
                 fmt(", FLIP %.4f", row.flipMean) + fmt(", %.2f Mrays/s", row.mraysPerS));
        mine.push_back(rows.size());
        rows.push_back(std::move(row));
      }
      // The budget at fractions of hybrid-full's frame time: where its choices land on the front.
      double fullMs = 0;
      for (std::size_t i : mine)
        if (rows[i].combo.name == "hybrid-full") fullMs = rows[i].total.median;
      for (double fraction : kBudgetFractions) {
        Combo combo{"budget-" + std::to_string(static_cast<int>(fraction * 100)) + "pct", "budget",
                    *presetSettings("hybrid-full", base)};
        combo.settings.targetMs = static_cast<float>(fraction * fullMs);
        FrameRun run = renderFrames(renderer, camera, combo.settings, o.warmup + kBudgetSettleFrames, o.warmupSeconds, o.frames);
        Row row = measuredRow(l.label, size, combo, o.frames, run, truth.image);
        row.budgetChoice = describeBudget(run.stats.back().budget);
        (void)writePng((fs::path(o.out) / "images" / (prefix + "-" + combo.name + ".png")).string(), run.image);
        progress(l.label + " " + size.label() + " " + combo.name + fmt(" (target %.1f ms)", combo.settings.targetMs) +
                 ": " + fmt("%.1f ms", row.total.median) + fmt(", FLIP %.4f", row.flipMean) + ", drew " +
                 row.budgetChoice);
        mine.push_back(rows.size());
        rows.push_back(std::move(row));
      }
      std::vector<Row*> group;
      for (std::size_t i : mine) group.push_back(&rows[i]);
      markPareto(group);

      // The error-vs-frames curve: each frame of an accumulation adds new pixel, light, gloss and lens
      // samples (FrameSettings::accumulate); FLIP against the reference after 1, 2, 4, ... frames.
      for (const char* name : kConvergePresets) {
        if (o.convergeFrames <= 0) break;
        FrameSettings s = *presetSettings(name, base);
        s.accumulate = o.convergeFrames;
        s.reuseRays = false;
        double totalMs = 0;
        std::string line;
        for (int frame = 1; frame <= o.convergeFrames; ++frame) {
          totalMs += renderer.render(camera, s).totalMs;
          if ((frame & (frame - 1)) != 0 && frame != o.convergeFrames) continue;  // powers of two and the last
          ConvergePoint p{l.label, size, name, frame, totalMs, 1.0};
          if (auto e = compare(renderer.readImage(), truth.image)) p.flipMean = e->flipMean;
          line += ' ';
          line += std::to_string(frame);
          line += ':';
          line += fmt("%.4f", p.flipMean);
          converge.push_back(p);
        }
        progress(l.label + " " + size.label() + " " + name + " accumulated, FLIP after N frames:" + line);
      }

      // Per effect: where raster and ray traced disagree, the effect alone over the raster preset.
      for (const char* effect : {"shadows", "reflections", "refraction"}) {
        auto f = flip(images[std::string(effect) + "-ray-only"], images["raster"]);
        if (!f) continue;
        HeatPanel p;
        p.effect = effect;
        p.scene = l.label;
        p.size = size.label();
        p.width = f->width;
        p.height = f->height;
        p.mean = f->mean;
        p.dataPath = (fs::path(o.out) / "data" / ("heat-" + prefix + "-" + effect + ".f32")).string();
        std::ofstream bin(p.dataPath, std::ios::binary);
        bin.write(reinterpret_cast<const char*>(f->map.data()),
                  static_cast<std::streamsize>(f->map.size() * sizeof(float)));
        (void)writePng((fs::path(o.out) / "images" / (prefix + "-heat-" + effect + ".png")).string(), heatmap(*f));
        heat.push_back(p);
      }

      Timer ceilingTimer;
      Ceiling c = measureCeiling(l.scene, size, *presetSettings("hybrid-full", base), o.threads, o.frames);
      c.scene = l.label;
      c.size = size;
      for (const Row& r : rows)
        if (r.scene == l.label && r.size.label() == size.label() && r.combo.name == "hybrid-full") {
          c.rasterMs = r.stage[1].median;
          c.readbackMs = r.stage[2].median;
          c.rendererRaysMs = r.stage[3].median;
        }
      progress(l.label + " " + size.label() + " ceiling: ray pass " + fmt("%.1f ms", c.passMs) + ", floor " +
               fmt("%.1f ms", c.floorMs) + fmt(" (%.2fx)", c.floorMs > 0 ? c.passMs / c.floorMs : 0.0) +
               ", castVisibility " + fmt("%.1f ms", c.castVisibilityMs) + " vs raster+readback " +
               fmt("%.1f ms", c.rasterMs + c.readbackMs));
      ceilings.push_back(c);
    }
  }

  const std::string gl = setup.context->describe();
  writeSweepCsv((fs::path(o.out) / "sweep.csv").string(), rows);
  writeCeilingCsv((fs::path(o.out) / "ceiling.csv").string(), ceilings);
  writeSweepMarkdown((fs::path(o.out) / "sweep.md").string(), rows, ceilings, setup.machine, gl, setup.threads, o);
  writeBudgetTable((fs::path(o.out) / "budget-table.md").string(), rows);
  writeConvergence(o, converge);

  if (o.plots) {
    std::vector<ParetoPanel> pareto;
    std::vector<StagePanel> stages;
    std::map<std::string, std::size_t> panelOf;
    for (const Row& r : rows) {
      std::string key = r.scene + " " + r.size.label();
      if (!panelOf.count(key)) {
        panelOf[key] = pareto.size();
        pareto.push_back({r.scene, r.size.label(), {}});
        stages.push_back({r.scene, r.size.label(), {}});
      }
      std::size_t i = panelOf[key];
      pareto[i].points.push_back({r.combo.name, r.combo.group == "preset", r.pareto, r.total.median, r.flipMean});
      if (r.combo.group == "preset") {
        StageBar bar;
        bar.name = r.combo.name;
        for (std::size_t k = 0; k < kStageCount; ++k) bar.ms.push_back(r.stage[k].median);
        stages[i].bars.push_back(bar);
      }
    }
    std::vector<std::string> stageNames;
    for (const StageField& s : kStages) stageNames.push_back(s.name);
    PlotContext pc{o.out, static_cast<int>(o.sizes.size()), gl, setup.machine.cpu, setup.threads};
    plotPareto(pc, pareto);
    plotStages(pc, stages, stageNames);
    plotHeat(pc, heat);
    std::vector<ConvergeCurve> curves;
    for (const ConvergePoint& p : converge) {
      const std::string panel = p.scene + " " + p.size.label();
      if (curves.empty() || curves.back().panel != panel || curves.back().name != p.combo)
        curves.push_back({panel, p.combo, {}});
      curves.back().points.push_back({p.frames, p.totalMs, p.flipMean});
    }
    plotConvergence(pc, curves);
  }
  const bool curves = !converge.empty();
  std::printf("wrote %s/sweep.csv, sweep.md, ceiling.csv%s%s in %s\n", o.out.c_str(), curves ? ", convergence.csv/.md" : "",
              o.plots ? (curves ? ", pareto.png, stages.png, heat-*.png, convergence.png" : ", pareto.png, stages.png, heat-*.png")
                      : "",
              formatDuration(elapsed()).c_str());
  return 0;
}

int runHeavy(const SweepOptions& o) {
  Setup setup;
  if (int rc = makeSetup(o, setup)) return rc;
  Renderer& renderer = *setup.renderer;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  std::vector<HeavyRow> rows;
  const std::size_t steps = o.heavyCounts.size() * o.heavySizes.size();
  std::size_t done = 0;
  for (std::size_t count : o.heavyCounts) {
    Timer genTimer;
    Scene scene = makeHeavyScene(count);
    double genMs = genTimer.ms();
    Timer setTimer;
    if (auto r = renderer.setScene(scene); !r) {
      std::printf("  heavy %zu: %s\n", count, r.error().message.c_str());
      continue;
    }
    double setMs = setTimer.ms();
    auto tracer = rt::RayTracer::create(o.threads);
    Timer buildTimer;
    bool rtOk = tracer && (*tracer)->setScene(scene).ok();
    double buildMs = buildTimer.ms();
    for (Size size : o.heavySizes) {
      FrameSettings base;
      base.width = size.width;
      base.height = size.height;
      HeavyRow h;
      h.triangles = scene.triangleCount();
      h.size = size.label();
      h.generateMs = genMs;
      h.setSceneMs = setMs;
      h.embreeBuildMs = buildMs;
      FrameRun run = renderFrames(renderer, scene.camera, *presetSettings("hybrid-full", base), o.warmup, o.warmupSeconds, o.frames);
      for (std::size_t i = 0; i < kStageCount; ++i) h.stageMs.push_back(stageStat(run.stats, kStages[i].field).median);
      h.totalMs = stageStat(run.stats, &FrameStats::totalMs).median;
      h.rays = run.stats.back().rays;
      FrameRun rasterRun = renderFrames(renderer, scene.camera, *presetSettings("raster", base), o.warmup, o.warmupSeconds, o.frames);
      h.rasterPresetMs = stageStat(rasterRun.stats, &FrameStats::totalMs).median;
      if (rtOk) {
        rt::VisibilityBuffer vis;
        (*tracer)->castVisibility(scene.camera, size.width, size.height, vis);
        h.castVisibilityMs = medianOf(o.frames, [&] {
          Timer t;
          (*tracer)->castVisibility(scene.camera, size.width, size.height, vis);
          return t.ms();
        });
      }
      h.peakRssMiB = peakRssMiB();
      ++done;
      double t = elapsed();
      std::printf("[%zu/%zu %s, ETA %s] heavy %zu triangles %s: hybrid-full %.1f ms (raster %.1f, rays %.1f), "
                  "raster preset %.1f ms, castVisibility %.1f ms\n",
                  done, steps, formatDuration(t).c_str(),
                  formatDuration(t / static_cast<double>(done) * static_cast<double>(steps - done)).c_str(),
                  h.triangles, h.size.c_str(), h.totalMs, h.stageMs[stageIndex("raster")], h.stageMs[stageIndex("rays")],
                  h.rasterPresetMs,
                  h.castVisibilityMs);
      std::fflush(stdout);
      rows.push_back(std::move(h));
    }
  }
  std::vector<std::string> stageNames;
  for (const StageField& s : kStages) stageNames.push_back(s.name);
  writeHeavyTables(o.out, rows, stageNames, setup.machine.cpu, setup.context->describe(), setup.threads);
  PlotContext pc{o.out, static_cast<int>(o.heavySizes.size()), setup.context->describe(), setup.machine.cpu,
                 setup.threads};
  if (o.plots) plotHeavy(pc, rows, stageNames);
  std::printf("wrote %s/heavy.csv, heavy.md%s in %s\n", o.out.c_str(), o.plots ? ", heavy.png" : "",
              formatDuration(elapsed()).c_str());
  return 0;
}

namespace {

/// One preset × scene × size of the summary table.
struct SummaryRow {
  std::string scene, preset;
  Size size;
  Stat total;
  double stageMs[kStageCount]{};
  double worstMs = 0;   // the slowest measured frame: what a player feels as a hitch
  int compiles = 0;     // shader programs compiled in the measured frames (after the warm-up)
  double mraysPerS = 0;
  double passOverFloor = 0;  // 0: no ray pass
};

void printSummary(std::FILE* out, const std::vector<SummaryRow>& rows, bool markdown) {
  const char* sep = markdown ? " | " : "  ";
  if (markdown) std::fprintf(out, "| ");
  std::fprintf(out, "%-16s%s%-9s%s%-11s%s%7s%s%6s%s%7s", "scene", sep, "size", sep, "preset", sep, "frame", sep, "fps", sep,
               "worst");
  for (const StageField& f : kStages) std::fprintf(out, "%s%9s", sep, f.name);
  std::fprintf(out, "%s%7s%s%10s%s%8s%s\n", sep, "Mrays/s", sep, "pass/floor", sep, "compiles", markdown ? " |" : "");
  if (markdown) {
    std::fprintf(out, "|");
    for (std::size_t k = 0; k < 9 + kStageCount; ++k) std::fprintf(out, "---|");
    std::fprintf(out, "\n");
  }
  for (const SummaryRow& r : rows) {
    if (markdown) std::fprintf(out, "| ");
    std::fprintf(out, "%-16s%s%-9s%s%-11s%s%7.1f%s%6.1f%s%7.1f", r.scene.c_str(), sep, r.size.label().c_str(), sep,
                 r.preset.c_str(), sep, r.total.median, sep, r.total.median > 0 ? 1000.0 / r.total.median : 0.0, sep,
                 r.worstMs);
    for (std::size_t k = 0; k < kStageCount; ++k) std::fprintf(out, "%s%9.1f", sep, r.stageMs[k]);
    if (r.passOverFloor > 0)
      std::fprintf(out, "%s%7.2f%s%10.2f", sep, r.mraysPerS, sep, r.passOverFloor);
    else
      std::fprintf(out, "%s%7s%s%10s", sep, "-", sep, "-");
    std::fprintf(out, "%s%8d%s\n", sep, r.compiles, markdown ? " |" : "");
  }
}

}  // namespace

int runSummary(const SweepOptions& o) {
  Setup setup;
  if (int rc = makeSetup(o, setup)) return rc;
  Renderer& renderer = *setup.renderer;
  std::vector<SummaryRow> rows;
  for (const std::string& spec : o.scenes) {
    auto loaded = loadBenchScene(spec);
    if (!loaded) {
      std::printf("  skipping %s: %s\n", spec.c_str(), loaded.error().message.c_str());
      continue;
    }
    const Scene& scene = *loaded;
    if (auto r = renderer.setScene(scene); !r) {
      std::printf("  skipping %s: %s\n", spec.c_str(), r.error().message.c_str());
      continue;
    }
    for (Size size : o.sizes) {
      FrameSettings base;
      base.width = size.width;
      base.height = size.height;
      for (const char* preset : {"raster", "hybrid-fast", "hybrid-full"}) {
        const FrameSettings s = *presetSettings(preset, base);
        FrameRun run = renderFrames(renderer, scene.camera, s, o.warmup, o.warmupSeconds, o.frames);
        SummaryRow row;
        row.scene = sceneLabel(spec);
        row.preset = preset;
        row.size = size;
        row.total = stageStat(run.stats, &FrameStats::totalMs);
        for (std::size_t k = 0; k < kStageCount; ++k) row.stageMs[k] = stageStat(run.stats, kStages[k].field).median;
        for (const FrameStats& f : run.stats) {
          row.worstMs = std::max(row.worstMs, f.totalMs);
          row.compiles += f.shaderCompiles;
        }
        const FrameStats& last = run.stats.back();
        const double raysMs = stageStat(run.stats, &FrameStats::raysMs).median;
        if (last.rays.total() > 0 && raysMs > 0) {
          row.mraysPerS = static_cast<double>(last.rays.total()) / (raysMs * 1e3);
          // The floor of this preset's own rays: captured and re-traced through raw Embree.
          const Ceiling c = measureCeiling(scene, size, s, o.threads, o.frames);
          if (c.floorMs > 0) row.passOverFloor = c.passMs / c.floorMs;
        }
        rows.push_back(row);
        std::printf("  %s %s %s: %.1f ms\n", row.scene.c_str(), size.label().c_str(), preset, row.total.median);
        std::fflush(stdout);
      }
    }
  }
  if (rows.empty()) {
    std::fprintf(stderr, "tandem-bench: no scene could be rendered\n");
    return 1;
  }
  std::printf("\nframe, worst and stages in ms (medians of %d frames after %d warm-up, at least %.1f s; worst = "
              "slowest measured frame); compiles = shader programs compiled in the measured frames\n",
              o.frames, o.warmup, o.warmupSeconds);
  printSummary(stdout, rows, false);
  const std::string path = (fs::path(o.out) / "summary.md").string();
  if (std::FILE* f = std::fopen(path.c_str(), "w")) {
    std::fprintf(f, "tandem-bench --summary on %s (%d logical CPUs); GL: %s\n\n", setup.machine.cpu.c_str(),
                 setup.machine.logicalCpus, setup.context->describe().c_str());
    printSummary(f, rows, true);
    std::fclose(f);
    std::printf("\nwritten: %s\n", path.c_str());
  }
  return 0;
}

}  // namespace tandem::bench
