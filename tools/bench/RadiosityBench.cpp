#include "RadiosityBench.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "BenchCommon.h"
#include "Plots.h"
#include "tandem/Context.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Renderer.h"
#include "tandem/SceneFile.h"

namespace tandem::bench {

namespace fs = std::filesystem;

namespace {

struct Row {
  int patches = 0, patchSides = 0;
  std::uint64_t shots = 0;
  double residual = 0, solveMs = 0, flip = 0;
  bool converged = false;
};

// Three images side by side (the same size): the README's figure.
Image sideBySide(const std::vector<const Image*>& images) {
  Image out;
  out.width = 0;
  out.height = images.front()->height;
  for (const Image* i : images) out.width += i->width;
  out.rgba.assign(static_cast<std::size_t>(out.width) * out.height * 4, 255);
  int x0 = 0;
  for (const Image* i : images) {
    for (int y = 0; y < i->height; ++y)
      std::copy_n(i->rgba.begin() + static_cast<std::ptrdiff_t>(4 * static_cast<std::size_t>(y) * i->width),
                  4 * i->width,
                  out.rgba.begin() + static_cast<std::ptrdiff_t>(4 * (static_cast<std::size_t>(y) * out.width + x0)));
    x0 += i->width;
  }
  return out;
}

}  // namespace

int runRadiosity(const RadiosityBenchOptions& o) {
  const std::string scenePath = o.scene.empty() ? sourceDir() + "/assets/scenes/cornell-box.json" : o.scene;
  auto scene = loadSceneFile(scenePath);
  if (!scene) {
    std::fprintf(stderr, "tandem-bench: %s\n", scene.error().message.c_str());
    return 1;
  }
  auto ctx = createGlContext({});
  if (!ctx) {
    std::fprintf(stderr, "tandem-bench: no GL context: %s\n", ctx.error().message.c_str());
    return 1;
  }
  RendererDesc desc;
  desc.threads = o.threads;
  auto renderer = Renderer::create(**ctx, desc);
  if (!renderer) {
    std::fprintf(stderr, "tandem-bench: %s\n", renderer.error().message.c_str());
    return 1;
  }
  Renderer& r = **renderer;
  const Camera camera = scene->camera;
  const std::string name = sceneLabel(scenePath);
  if (auto set = r.setScene(std::move(*scene)); !set) {
    std::fprintf(stderr, "tandem-bench: %s\n", set.error().message.c_str());
    return 1;
  }
  fs::create_directories(fs::path(o.out) / "images");
  fs::create_directories(fs::path(o.out) / "data");
  const Machine machine = describeMachine();
  std::printf("radiosity on %s at %dx%d (%s)\n", name.c_str(), o.size, o.size, (*ctx)->describe().c_str());

  FrameSettings base = *presetSettings("hybrid-full");
  base.width = base.height = o.size;
  base.reuseRays = false;  // every frame pays its whole cost
  auto frame = [&](const FrameSettings& s, FrameStats* stats = nullptr) {
    const FrameStats st = r.render(camera, s);
    if (stats) *stats = st;
    return r.readImage();
  };
  auto flipOf = [](const Image& a, const Image& b) {
    auto f = flip(a, b);
    return f ? f->mean : 1.0;
  };
  auto medianMs = [&](const FrameSettings& s, double FrameStats::* stage) {
    std::vector<double> ms;
    for (int i = 0; i < o.frames; ++i) {
      const FrameStats st = r.render(camera, s);
      ms.push_back(st.*stage);
    }
    return summarize(ms).median;
  };

  // The path-traced truth.
  FrameSettings truthSettings = *presetSettings("reference", base);
  truthSettings.gi = GlobalIllumination::Path;
  truthSettings.referenceSpp = o.truthSpp;
  FrameStats truthStats;
  const Image truth = frame(truthSettings, &truthStats);
  std::printf("  truth: path-traced, %d spp, %s\n", o.truthSpp * o.truthSpp, formatDuration(truthStats.totalMs / 1000.0).c_str());
  (void)writePng((fs::path(o.out) / "images" / "radiosity-path.png").string(), truth);

  // The ambient term.
  const Image ambient = frame(base);
  const double ambientFlip = flipOf(ambient, truth);
  const double ambientMs = medianMs(base, &FrameStats::totalMs);
  (void)writePng((fs::path(o.out) / "images" / "radiosity-ambient.png").string(), ambient);
  std::printf("  ambient term: FLIP %.4f, %.1f ms a frame\n", ambientFlip, ambientMs);

  // Per patch count: the error as the shots go on (each cap a solve from the start, timed by the solver).
  std::vector<Row> rows;
  std::vector<ConvergeCurve> curves;
  for (int patches : o.patches) {
    ConvergeCurve curve;
    curve.panel = name + " " + std::to_string(o.size) + "x" + std::to_string(o.size);
    curve.name = std::to_string(patches) + " patches";
    for (int cap = 16;; cap *= 4) {
      FrameSettings s = base;
      s.radiosity = true;
      s.radiosityPatches = patches;
      s.radiosityShots = cap;
      FrameStats st;
      const Image image = frame(s, &st);
      Row row;
      row.patches = patches;
      row.patchSides = st.radiosity.patches;
      row.shots = st.radiosity.shots;
      row.residual = st.radiosity.residual;
      row.solveMs = st.radiosity.solveMs;
      row.flip = flipOf(image, truth);
      row.converged = st.radiosity.residual <= s.radiosityError;
      rows.push_back(row);
      curve.points.push_back({static_cast<int>(row.shots), row.solveMs, row.flip});
      std::printf("  %5d patches (%5d sides), %6llu shots: unshot %.4f, solve %8.1f ms, FLIP %.4f\n", patches,
                  row.patchSides, static_cast<unsigned long long>(row.shots), row.residual, row.solveMs, row.flip);
      if (row.converged) {
        (void)writePng((fs::path(o.out) / "images" / ("radiosity-" + std::to_string(patches) + ".png")).string(), image);
        break;
      }
    }
    curves.push_back(std::move(curve));
  }

  // What showing a converged solution costs a frame (the default patch count), raster and hybrid-full.
  struct Display {
    std::string preset;
    double without = 0, with = 0, compositeWithout = 0, compositeWith = 0;
  };
  std::vector<Display> display;
  Image twoPass;
  for (const char* preset : {"raster", "hybrid-full"}) {
    FrameSettings s = *presetSettings(preset, base);
    FrameSettings withR = s;
    withR.radiosity = true;
    Display d;
    d.preset = preset;
    d.without = medianMs(s, &FrameStats::totalMs);
    d.compositeWithout = medianMs(s, &FrameStats::compositeMs);
    const Image image = frame(withR);  // solves once
    if (std::string(preset) == "hybrid-full") twoPass = image;
    d.with = medianMs(withR, &FrameStats::totalMs);
    d.compositeWith = medianMs(withR, &FrameStats::compositeMs);
    display.push_back(d);
    std::printf("  %s: %.1f ms a frame with radiosity shown, %.1f without (composite %.2f vs %.2f ms)\n", preset, d.with,
                d.without, d.compositeWith, d.compositeWithout);
  }
  FrameSettings defaults = base;
  defaults.radiosity = true;
  FrameStats defaultStats;
  (void)frame(defaults, &defaultStats);
  const double twoPassFlip = flipOf(twoPass, truth);
  (void)writePng((fs::path(o.out) / "images" / "radiosity-three-ways.png").string(),
                 sideBySide({&ambient, &twoPass, &truth}));

  {
    std::ofstream csv(fs::path(o.out) / "radiosity.csv");
    csv << "scene,size,patches,patch_sides,shots,residual,solve_ms,flip\n";
    for (const Row& row : rows)
      csv << name << "," << o.size << "," << row.patches << "," << row.patchSides << "," << row.shots << ","
          << row.residual << "," << row.solveMs << "," << row.flip << "\n";
  }
  std::ofstream md(fs::path(o.out) / "radiosity.md");
  md << "# Radiosity: solve time, error and display cost (tandem-bench --radiosity)\n\n";
  md << name << " at " << o.size << "x" << o.size << "; " << machine.cpu << ", " << machine.logicalCpus
     << " logical CPUs; " << (*ctx)->describe() << ".\n\n";
  md << "Truth: the path tracer (`--gi path`) at " << o.truthSpp * o.truthSpp << " samples per pixel ("
     << formatDuration(truthStats.totalMs / 1000.0) << "). FLIP is LDR-FLIP of the hybrid-full frame against it.\n\n";
  md << "| frame | FLIP vs path-traced | cost |\n|---|---|---|\n";
  md << "| hybrid-full, ambient term | " << ambientFlip << " | " << ambientMs << " ms a frame |\n";
  md << "| hybrid-full + radiosity (" << defaultStats.radiosity.patches << " patch sides, "
     << defaultStats.radiosity.shots << " shots) | " << twoPassFlip << " | solve " << defaultStats.radiosity.solveMs
     << " ms once, then " << display.back().with << " ms a frame |\n";
  md << "| path-traced, " << o.truthSpp * o.truthSpp << " spp | 0 (the truth) | " << truthStats.totalMs << " ms |\n\n";
  md << "Error as the shots go on (each row a solve from the start to that many shots):\n\n";
  md << "| patches | patch sides | shots | unshot | solve ms | FLIP |\n|---|---|---|---|---|---|\n";
  for (const Row& row : rows)
    md << "| " << row.patches << " | " << row.patchSides << " | " << row.shots << " | " << row.residual << " | "
       << row.solveMs << " | " << row.flip << " |\n";
  md << "\nShowing a converged solution (median of " << o.frames << " frames, reuse off):\n\n";
  md << "| preset | ms a frame without | with | composite without | with |\n|---|---|---|---|---|\n";
  for (const Display& d : display)
    md << "| " << d.preset << " | " << d.without << " | " << d.with << " | " << d.compositeWithout << " | "
       << d.compositeWith << " |\n";
  std::printf("  wrote %s/radiosity.md, radiosity.csv, images/radiosity-*.png\n", o.out.c_str());

  if (o.plots) {
    PlotContext pc;
    pc.out = o.out;
    pc.gl = (*ctx)->describe();
    pc.cpu = machine.cpu;
    pc.threads = truthStats.threads;  // the ray pass's own count (o.threads may be 0: all)
    plotRadiosity(pc, curves, ambientFlip);
  }
  return 0;
}

}  // namespace tandem::bench
