#pragma once
// Shared by the sweep and the micro-benchmarks of tandem-bench: machine description, statistics,
// the CPU twin of the tone-map pass, memory figures, scene loading.
#include <string>
#include <vector>

#include "tandem/Image.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::bench {

struct Stat {
  double median = 0, min = 0, max = 0;
};
Stat summarize(std::vector<double> v);

/// CPU model (from /proc/cpuinfo), logical CPUs, TBB's default concurrency, LP_NUM_THREADS.
struct Machine {
  std::string cpu;
  int logicalCpus = 0;
  int tbbThreads = 0;
  std::string lpNumThreads;  // the environment value, or "unset (llvmpipe uses one thread per CPU)"
  std::string embreeVersion;
};
Machine describeMachine();

/// Resident set now and the process's high-water mark so far (getrusage), in MiB.
double currentRssMiB();
double peakRssMiB();

/// Linear radiance → 8-bit sRGB exactly as the GL tone-map pass does (exposure, tone map, encode).
Image toDisplay(const ImageF& linear, const FrameSettings& settings);

/// A scene by path (.json, .gltf, .glb), "heavy:N" for makeHeavyScene(N), or "mirrors:N" for N mirror spheres
/// on a grid over a floor (the raster probes' benchmark).
Result<Scene> loadBenchScene(const std::string& spec);
/// Short name for tables and file names: file stem, or heavy-N.
std::string sceneLabel(const std::string& spec);

/// The repository root: where the default scenes are found.
std::string sourceDir();

std::string formatDuration(double seconds);

}  // namespace tandem::bench
