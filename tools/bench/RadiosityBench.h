#pragma once
// tandem-bench --radiosity: what the radiosity solution costs and buys (docs/radiosity.md, docs/bench.md): its
// solve time and error against the path-traced truth as shots go on, per patch count; the per-frame cost of
// showing it; the Cornell box three ways (ambient term, radiosity + rays, path-traced).
#include <string>
#include <vector>

namespace tandem::bench {

struct RadiosityBenchOptions {
  std::string scene;               // default: assets/scenes/cornell-box.json
  int size = 256;                  // square frames
  std::vector<int> patches{256, 1024, 4096};
  int truthSpp = 16;               // the path tracer's N (N×N samples per pixel)
  int frames = 10;                 // per display-cost measurement
  int threads = 0;
  std::string out = "out/bench";
  bool plots = true;
};

/// Writes OUT/radiosity.md, radiosity.csv, radiosity.png and OUT/images/radiosity-*.png.
int runRadiosity(const RadiosityBenchOptions& options);

}  // namespace tandem::bench
