#pragma once
// tandem-bench --sweep / --heavy / --summary: the speed-for-accuracy table, the ceiling, the heavy-scene table and
// their plots (docs/bench.md).
#include <string>
#include <vector>

namespace tandem::bench {

struct Size {
  int width = 0, height = 0;
  std::string label() const { return std::to_string(width) + "x" + std::to_string(height); }
};

struct SweepOptions {
  std::vector<std::string> scenes;  // paths or heavy:N
  std::vector<Size> sizes;
  int frames = 3;
  int warmup = 1;
  double warmupSeconds = 1.0;  // and at least this long: a GPU's clock comes up from idle (renderFrames)
  int truthSpp = 0;  // 0: 8×8 up to 640×360 pixels, 4×4 above
  int threads = 0;   // ray-pass threads, 0 = all
  std::string out = "out/bench";
  bool plots = true;
  int convergeFrames = 32;  // the error-vs-frames curve: accumulated frames per curve (0: none)
  // --heavy
  std::vector<std::size_t> heavyCounts;
  std::vector<Size> heavySizes;
};

/// Both return the process exit code.
int runSweep(const SweepOptions& options);
int runHeavy(const SweepOptions& options);
/// The one-screen table of this machine: each preset × scene × size → frame ms, fps, the worst frame,
/// each stage, Mrays/s, pass/floor and shader compiles; also written as summary.md in options.out.
int runSummary(const SweepOptions& options);

}  // namespace tandem::bench
