// tandem-bench: what each render setting costs and buys (docs/bench.md).
//   tandem-bench --sweep [--scenes a.json,b.gltf] [--sizes 640x360,1280x720] [--frames N] [--warmup W] [--out DIR]
//                        [--converge-frames N]
//   tandem-bench --summary [--scenes ...] [--sizes 640x360,1280x720,1920x1080] [--frames N] [--warmup W]
//   tandem-bench --budget [--targets 100,85,75] [--budget-preset hybrid-full] [--budget-size 640x360]
//   tandem-bench --radiosity [--radiosity-patches 512,2048] [--truth-spp N] [--frames N]
//   tandem-bench --heavy [--heavy-counts 10000,100000,500000,2000000] [--heavy-sizes 640x360,1280x720]
//   tandem-bench [--benchmark_filter=REGEX ...]     (Google Benchmark micro-benchmarks, the default)
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <benchmark/benchmark.h>

#include "BenchCommon.h"
#include "Budget.h"
#include "ExactBench.h"
#include "Micro.h"
#include "RadiosityBench.h"
#include "Sweep.h"

using namespace tandem::bench;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) v.push_back(item);
  return v;
}

bool parseSizes(const std::string& s, std::vector<Size>& out, std::string& error) {
  out.clear();
  for (const std::string& item : split(s)) {
    Size z;
    char x = 0;
    std::istringstream in(item);
    if (!(in >> z.width >> x >> z.height) || x != 'x' || z.width < 1 || z.height < 1 || !in.eof()) {
      error = "bad size '" + item + "' (WxH)";
      return false;
    }
    out.push_back(z);
  }
  if (out.empty()) error = "no size given";
  return !out.empty();
}

int sweepMain(int argc, char** argv) {
  CLI::App app{"tandem-bench: the speed-for-accuracy sweep, the ceiling and the heavy-scene table"};
  bool sweep = false, heavy = false, summary = false, budget = false, radiosity = false, noPlots = false;
  std::string radiosityPatches = "512,2048";
  std::string targets;
  BudgetOptions b;
  std::string scenes, sizes = "640x360,1280x720", heavyCounts = "10000,100000,500000,2000000",
                      heavySizes = "640x360,1280x720";
  SweepOptions o;
  const std::string shared = sourceDir() + "/../shared/assets/gltf-sample-assets/";
  scenes = sourceDir() + "/assets/scenes/whitted.json," + shared + "LightsPunctualLamp/glTF/LightsPunctualLamp.gltf," +
           shared + "TransmissionTest/glTF/TransmissionTest.gltf";
  app.add_flag("--sweep", sweep, "Every preset and effect combination on each scene × size");
  app.add_flag("--heavy", heavy, "The heavy-scene table: stage cost against triangle count");
  app.add_flag("--summary", summary,
               "One screen for this machine: each preset x scene x size -> frame ms, fps, worst frame, stages, "
               "Mrays/s, pass/floor, shader compiles (defaults: whitted.json; 640x360,1280x720,1920x1080; 10 frames)");
  app.add_flag("--budget", budget,
               "The game's scripted run at several frame-time targets (tandem-game --target-fps): frame time and "
               "FLIP per frame, budget.md / budget.png");
  app.add_option("--targets", targets, "--budget: comma-separated targets in ms (default: 80 %, 60 % and 45 % of "
                                       "the requested preset's median frame)");
  app.add_option("--budget-preset", b.preset, "--budget: the requested settings")->capture_default_str();
  app.add_option("--budget-size", b.size, "--budget: the game's frame size")->capture_default_str();
  app.add_option("--budget-frames", b.frames, "--budget: frames per run")->check(CLI::Range(2, 100000))->capture_default_str();
  app.add_option("--error-every", b.errorEvery, "--budget: FLIP every Nth frame")
      ->check(CLI::Range(1, 100000))->capture_default_str();
  bool exact = false;
  app.add_flag("--exact", exact,
               "Exact solids: the Whitted scene with tessellated and exact spheres against the exact truth, and the "
               "CSG scene's resolved pixels, per preset (exact.md)");
  app.add_flag("--radiosity", radiosity,
               "Radiosity on the Cornell box: solve time and error against the path-traced truth per patch count, "
               "the per-frame cost of showing it, the box three ways (docs/radiosity.md)");
  app.add_option("--radiosity-patches", radiosityPatches, "--radiosity: comma-separated patch counts")
      ->capture_default_str();
  app.add_option("--scenes", scenes, "Comma-separated scenes (.json, .gltf, .glb, heavy:N); missing ones are skipped")
      ->capture_default_str();
  app.add_option("--sizes", sizes, "Comma-separated WxH")->capture_default_str();
  app.add_option("--frames", o.frames, "Measured frames per combination")->check(CLI::Range(1, 1000))->capture_default_str();
  app.add_option("--warmup", o.warmup, "Warm-up frames per combination")->check(CLI::Range(0, 1000))->capture_default_str();
  app.add_option("--warmup-seconds", o.warmupSeconds,
                 "Warm up for at least this long too (a GPU left idle needs a while to raise its clock)")
      ->check(CLI::Range(0.0, 60.0))
      ->capture_default_str();
  app.add_option("--truth-spp", o.truthSpp, "Reference N (N×N spp); 0 = 8 up to 640×360, else 4")
      ->check(CLI::Range(0, 64))->capture_default_str();
  app.add_option("--converge-frames", o.convergeFrames,
                 "--sweep: the error-vs-frames curve, FLIP after 1, 2, 4, ... accumulated frames up to N (0: none)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "Ray-pass threads (0 = all)")->check(CLI::Range(0, 1024))->capture_default_str();
  app.add_option("--out", o.out, "Output folder")->capture_default_str();
  app.add_option("--heavy-counts", heavyCounts, "Triangle counts for --heavy")->capture_default_str();
  app.add_option("--heavy-sizes", heavySizes, "Sizes for --heavy")->capture_default_str();
  app.add_flag("--no-plots", noPlots, "Skip gnuplot");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  o.plots = !noPlots;
  if (exact) {
    if (sweep || heavy || summary || budget || radiosity) {
      std::fprintf(stderr, "tandem-bench: --exact runs alone\n");
      return 1;
    }
    ExactBenchOptions eo;
    std::vector<Size> one;
    std::string error;
    if (app.count("--sizes") > 0) {
      if (!parseSizes(sizes, one, error) || one.empty()) {
        std::fprintf(stderr, "tandem-bench: %s\n", error.c_str());
        return 1;
      }
      eo.width = one.front().width;
      eo.height = one.front().height;
    }
    if (app.count("--truth-spp") > 0 && o.truthSpp > 0) eo.truthSpp = o.truthSpp;
    if (app.count("--frames") > 0) eo.frames = o.frames;
    eo.threads = o.threads;
    eo.out = o.out;
    return runExact(eo);
  }
  if (radiosity) {
    if (sweep || heavy || summary || budget) {
      std::fprintf(stderr, "tandem-bench: --radiosity runs alone\n");
      return 1;
    }
    RadiosityBenchOptions ro;
    ro.patches.clear();
    for (const std::string& p : split(radiosityPatches)) {
      char* end = nullptr;
      const long n = std::strtol(p.c_str(), &end, 10);
      if (end == p.c_str() || *end != '\0' || n < 16 || n > (1 << 20)) {
        std::fprintf(stderr, "tandem-bench: --radiosity-patches: bad count '%s' (16..1048576)\n", p.c_str());
        return 1;
      }
      ro.patches.push_back(static_cast<int>(n));
    }
    if (app.count("--scenes") > 0) ro.scene = split(scenes).front();
    if (app.count("--truth-spp") > 0 && o.truthSpp > 0) ro.truthSpp = o.truthSpp;
    if (app.count("--frames") > 0) ro.frames = o.frames;
    ro.threads = o.threads;
    ro.out = o.out;
    ro.plots = !noPlots;
    return runRadiosity(ro);
  }
  if (budget && (sweep || heavy || summary)) {
    std::fprintf(stderr, "tandem-bench: --budget runs alone\n");
    return 1;
  }
  if (budget) {
    for (const std::string& t : split(targets)) {
      char* end = nullptr;
      const double ms = std::strtod(t.c_str(), &end);
      if (end == t.c_str() || *end != '\0' || !(ms >= 1.0 && ms <= 10000.0)) {
        std::fprintf(stderr, "tandem-bench: --targets: bad target '%s' (ms, 1..10000)\n", t.c_str());
        return 1;
      }
      b.targetsMs.push_back(ms);
    }
    b.threads = o.threads;
    b.out = o.out;
    b.plots = !noPlots;
    return runBudget(b);
  }
  if (summary && (sweep || heavy)) {
    // The summary has its own defaults (scenes, sizes, frames): run it on its own.
    std::fprintf(stderr, "tandem-bench: --summary runs alone, not with --sweep or --heavy\n");
    return 1;
  }
  if (summary) {
    // The summary's own defaults: the Whitted scene, three sizes, enough frames for a median and a worst.
    if (app.count("--scenes") == 0) scenes = sourceDir() + "/assets/scenes/whitted.json";
    if (app.count("--sizes") == 0) sizes = "640x360,1280x720,1920x1080";
    if (app.count("--frames") == 0) o.frames = 10;
    if (app.count("--warmup") == 0) o.warmup = 2;
  }
  o.scenes = split(scenes);
  std::string error;
  if (!parseSizes(sizes, o.sizes, error) || !parseSizes(heavySizes, o.heavySizes, error)) {
    std::fprintf(stderr, "tandem-bench: %s\n", error.c_str());
    return 1;
  }
  for (const std::string& c : split(heavyCounts)) {
    try {
      o.heavyCounts.push_back(static_cast<std::size_t>(std::stoull(c)));
    } catch (const std::exception&) {
      std::fprintf(stderr, "tandem-bench: bad triangle count '%s'\n", c.c_str());
      return 1;
    }
  }
  int rc = 0;
  if (sweep) rc = runSweep(o);
  if (rc == 0 && heavy) rc = runHeavy(o);
  if (rc == 0 && summary) rc = runSummary(o);
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--sweep") || !std::strcmp(argv[i], "--heavy") || !std::strcmp(argv[i], "--summary") ||
        !std::strcmp(argv[i], "--budget") || !std::strcmp(argv[i], "--radiosity") ||
        !std::strcmp(argv[i], "--exact"))
      return sweepMain(argc, argv);
  registerMicroBenchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
