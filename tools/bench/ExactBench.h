#pragma once
// tandem-bench --exact: what exact solids cost and buy (docs/csg.md, docs/bench.md): the Whitted scene with its
// spheres tessellated (64 × 32) and exact, each preset's frame time, resolved pixels and error against the
// converged reference of the exact scene (real spheres: the truth); and the CSG scene's resolve cost per preset.
#include <string>

namespace tandem::bench {

struct ExactBenchOptions {
  int width = 640, height = 360;
  int truthSpp = 8;   // the exact reference's N (N×N samples per pixel)
  int frames = 5;     // measured frames per row (after one warm-up)
  int threads = 0;
  std::string out = "out/bench";
};

/// Writes OUT/exact.md and OUT/exact.csv.
int runExact(const ExactBenchOptions& options);

}  // namespace tandem::bench
