#include "ExactBench.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "BenchCommon.h"
#include "tandem/Context.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Renderer.h"
#include "tandem/SceneFile.h"

namespace tandem::bench {

namespace fs = std::filesystem;

namespace {

struct Row {
  std::string scene, variant, preset;
  double frameMs = 0, raysMs = 0;
  std::uint64_t resolved = 0;
  double flip = -1;  // against the truth; -1: no truth for this scene
};

// The embedded Whitted scene with its sphere mesh marked exact: the same tessellation, now the proxy.
Result<std::string> exactWhitted() {
  std::string text(defaultSceneText());
  const std::string sphere = R"("primitive": "sphere", "radius": 1, "segments": 64, "rings": 32)";
  const std::size_t at = text.find(sphere);
  if (at == std::string::npos) return Error{"the embedded scene's sphere mesh is not where --exact expects it"};
  text.replace(at, sphere.size(), sphere + R"(, "exact": true)");
  return text;
}

}  // namespace

int runExact(const ExactBenchOptions& o) {
  auto ctx = createGlContext({});
  if (!ctx) {
    std::fprintf(stderr, "tandem-bench: no GL context: %s\n", ctx.error().message.c_str());
    return 1;
  }
  auto exactText = exactWhitted();
  if (!exactText) {
    std::fprintf(stderr, "tandem-bench: %s\n", exactText.error().message.c_str());
    return 1;
  }
  struct Input {
    std::string scene, variant;
    Result<Scene> loaded;
    bool truth;  // the reference of this scene is the truth its rows are measured against
  };
  std::vector<Input> inputs;
  inputs.push_back({"whitted", "exact spheres", parseSceneJson(*exactText, "whitted-exact", "."), true});
  inputs.push_back({"whitted", "tessellated 64 × 32", loadDefaultScene(), false});
  inputs.push_back({"csg", "exact", loadSceneFile(sourceDir() + "/assets/scenes/csg.json"), false});
  fs::create_directories(fs::path(o.out) / "images");
  const Machine machine = describeMachine();
  std::printf("exact solids at %dx%d (%s)\n", o.width, o.height, (*ctx)->describe().c_str());
  std::vector<Row> rows;
  Image truth;
  double truthMs = 0;
  for (Input& in : inputs) {
    if (!in.loaded) {
      std::fprintf(stderr, "tandem-bench: %s\n", in.loaded.error().message.c_str());
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
    const Camera camera = in.loaded->camera;
    if (auto set = r.setScene(std::move(*in.loaded)); !set) {
      std::fprintf(stderr, "tandem-bench: %s\n", set.error().message.c_str());
      return 1;
    }
    FrameSettings base;
    base.width = o.width;
    base.height = o.height;
    base.reuseRays = false;  // every frame pays its whole cost
    if (in.truth) {
      FrameSettings t = *presetSettings("reference", base);
      t.referenceSpp = o.truthSpp;
      const FrameStats st = r.render(camera, t);
      truth = r.readImage();
      truthMs = st.totalMs;
      (void)writePng((fs::path(o.out) / "images" / "exact-truth.png").string(), truth);
      std::printf("  truth: the exact scene's reference, %d spp, %s\n", o.truthSpp * o.truthSpp,
                  formatDuration(truthMs / 1000.0).c_str());
    }
    for (const char* preset : {"raster", "hybrid-fast", "hybrid-full", "reference"}) {
      FrameSettings s = *presetSettings(preset, base);
      s.referenceSpp = 1;
      (void)r.render(camera, s);  // warm-up: shader variants, the Embree scene
      std::vector<double> total, rays;
      FrameStats st;
      for (int i = 0; i < o.frames; ++i) {
        st = r.render(camera, s);
        total.push_back(st.totalMs);
        rays.push_back(st.raysMs);
      }
      Row row{in.scene, in.variant, preset, summarize(total).median, summarize(rays).median, st.rays.resolved, -1};
      const Image image = r.readImage();
      if (!truth.rgba.empty() && in.scene == "whitted")
        if (auto f = flip(image, truth)) row.flip = f->mean;
      rows.push_back(row);
      std::printf("  %-8s %-20s %-12s %8.1f ms (rays %.1f), %llu resolved%s\n", row.scene.c_str(), row.variant.c_str(),
                  preset, row.frameMs, row.raysMs, static_cast<unsigned long long>(row.resolved),
                  row.flip >= 0 ? (", FLIP " + std::to_string(row.flip)).c_str() : "");
    }
  }
  {
    std::ofstream csv(fs::path(o.out) / "exact.csv");
    csv << "scene,variant,preset,width,height,frame_ms,rays_ms,rays_resolved,flip\n";
    for (const Row& r : rows)
      csv << r.scene << "," << r.variant << "," << r.preset << "," << o.width << "," << o.height << "," << r.frameMs
          << "," << r.raysMs << "," << r.resolved << "," << r.flip << "\n";
  }
  std::ofstream md(fs::path(o.out) / "exact.md");
  md << "# Exact solids: cost and error (tandem-bench --exact)\n\n";
  md << o.width << "x" << o.height << ", medians of " << o.frames << " frames after a warm-up, every frame traced; "
     << machine.cpu << ", " << machine.logicalCpus << " logical CPUs; " << (*ctx)->describe() << ".\n\n";
  md << "Truth: the reference of the Whitted scene with exact spheres at " << o.truthSpp * o.truthSpp
     << " samples per pixel (" << formatDuration(truthMs / 1000.0)
     << "). FLIP is LDR-FLIP against it; the reference rows are at 1 spp.\n\n";
  md << "| scene | spheres / solids | preset | frame ms | rays ms | resolved pixels | FLIP vs truth |\n";
  md << "|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "| %s | %s | %s | %.1f | %.1f | %llu | %s |\n", r.scene.c_str(), r.variant.c_str(),
                  r.preset.c_str(), r.frameMs, r.raysMs, static_cast<unsigned long long>(r.resolved),
                  r.flip >= 0 ? std::to_string(r.flip).substr(0, 6).c_str() : "–");
    md << buf;
  }
  std::printf("wrote %s\n", (fs::path(o.out) / "exact.md").string().c_str());
  return 0;
}

}  // namespace tandem::bench
