#pragma once
// gnuplot figures of tandem-bench: each writes its data under OUT/data, a script OUT/NAME.gp (kept, so a
// figure can be restyled and re-run by hand) and OUT/NAME.png. pngcairo when gnuplot has it, else png.
#include <string>
#include <vector>

#include "tandem/FrameStats.h"

namespace tandem::bench {

struct PlotContext {
  std::string out;
  int rows = 1;  // sizes: one row of panels per size
  std::string gl;
  std::string cpu;
  int threads = 0;
};

struct ParetoPoint {
  std::string name;
  bool preset = false;
  bool front = false;
  double ms = 0;
  double flip = 0;
};
struct ParetoPanel {
  std::string scene, size;
  std::vector<ParetoPoint> points;
};
struct StageBar {
  std::string name;
  std::vector<double> ms;  // per stage
};
struct StagePanel {
  std::string scene, size;
  std::vector<StageBar> bars;
};
struct HeatPanel {
  std::string effect, scene, size, dataPath;  // dataPath: width×height float32, row 0 at the top
  int width = 0, height = 0;
  double mean = 0;
};
struct HeavyRow {
  std::size_t triangles = 0;
  std::string size;
  double generateMs = 0, setSceneMs = 0, embreeBuildMs = 0;
  std::vector<double> stageMs;  // hybrid-full medians per stage
  double totalMs = 0;
  double rasterPresetMs = 0;
  double castVisibilityMs = 0;
  double peakRssMiB = 0;
  RayCounts rays;
};

struct ConvergeCurve {
  std::string panel, name;  // panel: "scene size"
  struct Point {
    int frames = 0;
    double totalMs = 0;
    double flip = 0;
  };
  std::vector<Point> points;
};

/// FLIP vs frame time, log-log, one panel per scene × size, the Pareto front as a line.
void plotPareto(const PlotContext& pc, const std::vector<ParetoPanel>& panels);
/// Stacked stage times per preset, one panel per scene × size.
void plotStages(const PlotContext& pc, const std::vector<StagePanel>& panels, const std::vector<std::string>& stages);
/// Per effect one figure heat-EFFECT.png: the FLIP map between "effect ray traced" and "raster" per scene × size.
void plotHeat(const PlotContext& pc, const std::vector<HeatPanel>& panels);
/// FLIP vs accumulated frames, log-log, one panel per scene × size, one line per combination.
void plotConvergence(const PlotContext& pc, const std::vector<ConvergeCurve>& curves);
/// Radiosity: FLIP against the path-traced truth vs solve time, log-log, one line per patch count (each
/// curve's points: shots, solve ms, FLIP), the ambient term's FLIP as a level line.
void plotRadiosity(const PlotContext& pc, const std::vector<ConvergeCurve>& curves, double ambientFlip);
void writeHeavyTables(const std::string& out, const std::vector<HeavyRow>& rows, const std::vector<std::string>& stages,
                      const std::string& cpu, const std::string& gl, int threads);
void plotHeavy(const PlotContext& pc, const std::vector<HeavyRow>& rows, const std::vector<std::string>& stages);

}  // namespace tandem::bench
