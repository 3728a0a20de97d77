#include "Plots.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace tandem::bench {

namespace {

std::string safe(std::string s) {
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_' && ch != '.') ch = '_';
  return s;
}

/// pngcairo (antialiased, better fonts) when this gnuplot has it, else libgd's png.
const std::string& terminal() {
  static const std::string t = [] {
    int rc = std::system("gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1");
    return std::string(rc == 0 ? "pngcairo enhanced font 'DejaVu Sans,10'" : "png enhanced font 'DejaVuSans,9'");
  }();
  return t;
}

/// Runs a gnuplot script from OUT so that data paths in it are relative (the script can be re-run by
/// hand: cd OUT && gnuplot NAME.gp).
void runGnuplot(const PlotContext& pc, const std::string& name, const std::string& script) {
  fs::path path = fs::path(pc.out) / (name + ".gp");
  std::ofstream(path) << script;
  std::string cmd = "cd '" + pc.out + "' && gnuplot '" + name + ".gp' 2> '" + name + ".gp.log'";
  int rc = std::system(cmd.c_str());
  if (rc != 0) std::printf("  gnuplot failed on %s (see %s/%s.gp.log)\n", path.string().c_str(), pc.out.c_str(), name.c_str());
}

std::string header(const PlotContext& pc, const std::string& name, int width, int height, int rows, int cols,
                   const std::string& title) {
  std::ostringstream s;
  s << "set terminal " << terminal() << " size " << width << "," << height << "\n";
  s << "set output '" << name << ".png'\n";
  s << "set multiplot layout " << rows << "," << cols << " columnsfirst title \"" << title << "\\n{/*0.75 " << pc.cpu
    << ", " << pc.threads << " ray-pass threads}\\n{/*0.75 " << pc.gl << "}\"\n";
  return s.str();
}

int columnsFor(std::size_t panels, int rows) {
  int r = std::max(rows, 1);
  return std::max(1, static_cast<int>((panels + static_cast<std::size_t>(r) - 1) / static_cast<std::size_t>(r)));
}

// Magma, matching the heat-map PNGs of ImageMetrics (black = no error, pale yellow = maximum).
constexpr const char* kMagma =
    "set palette defined (0 '#000004', 0.13 '#1c1044', 0.25 '#4f127b', 0.38 '#812581', 0.5 '#b5367a', "
    "0.63 '#e55064', 0.75 '#fb8761', 0.88 '#fec287', 1 '#fcfdbf')\n";

}  // namespace

void plotPareto(const PlotContext& pc, const std::vector<ParetoPanel>& panels) {
  if (panels.empty()) return;
  int cols = columnsFor(panels.size(), pc.rows);
  std::ostringstream s;
  s << header(pc, "pareto", 620 * cols, 480 * pc.rows, pc.rows, cols,
              "Error against the converged reference vs frame time (Pareto front in red)");
  s << "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n";
  s << "set xlabel 'frame time, ms (median, log scale)'\nset ylabel 'FLIP mean vs reference (log scale)'\n";
  s << "set key top right box opaque font ',8'\nset format y '%g'\nset format x '%g'\n";
  s << "set offsets graph 0.02, graph 0.12, 0, 0\n";
  for (const ParetoPanel& p : panels) {
    std::string tag = safe(p.scene + "-" + p.size);
    std::string all = "data/pareto-" + tag + ".dat", front = "data/front-" + tag + ".dat";
    {
      std::ofstream f(fs::path(pc.out) / all);
      f << "# name ms flip preset front\n";
      // log scale: a FLIP of exactly 0 (identical to the reference) is drawn at 1e-5.
      for (const ParetoPoint& q : p.points)
        f << q.name << " " << q.ms << " " << std::max(q.flip, 1e-5) << " " << q.preset << " " << q.front << "\n";
    }
    {
      std::vector<ParetoPoint> f = p.points;
      f.erase(std::remove_if(f.begin(), f.end(), [](const ParetoPoint& q) { return !q.front; }), f.end());
      std::sort(f.begin(), f.end(), [](const ParetoPoint& a, const ParetoPoint& b) { return a.ms < b.ms; });
      std::ofstream o(fs::path(pc.out) / front);
      o << "# name ms flip\n";
      for (const ParetoPoint& q : f) o << q.name << " " << q.ms << " " << std::max(q.flip, 1e-5) << "\n";
    }
    s << "set title '" << p.scene << " " << p.size << "'\n";
    s << "plot '" << all << "' using 2:($4==0 ? $3 : 1/0) with points pt 7 ps 1.1 lc rgb '#888888' title 'effect combination', \\\n"
      << "     '" << all << "' using 2:($4==1 ? $3 : 1/0) with points pt 5 ps 1.4 lc rgb '#1f77b4' title 'preset', \\\n"
      << "     '" << front << "' using 2:3 with lines lw 2 lc rgb '#d62728' title 'Pareto front', \\\n"
      << "     '" << front << "' using 2:3 with points pt 6 ps 2.2 lw 2 lc rgb '#d62728' notitle, \\\n"
      // Labels alternate above and below their point so that neighbours do not print over each other.
      << "     '" << all << "' using 2:3:(($4==1 || $5==1) && int($0)%2==0 ? stringcolumn(1) : '') with labels left offset char 0.9,0.6 font ',8' notitle, \\\n"
      << "     '" << all << "' using 2:3:(($4==1 || $5==1) && int($0)%2==1 ? stringcolumn(1) : '') with labels left offset char 0.9,-0.6 font ',8' notitle\n";
  }
  s << "unset multiplot\n";
  runGnuplot(pc, "pareto", s.str());
}

void plotConvergence(const PlotContext& pc, const std::vector<ConvergeCurve>& curves) {
  if (curves.empty()) return;
  std::vector<std::string> panels;
  for (const ConvergeCurve& c : curves)
    if (std::find(panels.begin(), panels.end(), c.panel) == panels.end()) panels.push_back(c.panel);
  const int cols = columnsFor(panels.size(), pc.rows);
  std::ostringstream s;
  s << header(pc, "convergence", 560 * cols, 440 * pc.rows, pc.rows, cols,
              "Error against the reference vs accumulated frames (new samples every frame)");
  s << "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n";
  s << "set xlabel 'frames accumulated (log scale)'\nset ylabel 'FLIP mean vs reference (log scale)'\n";
  s << "set key top right box opaque font ',8'\nset format y '%g'\nset format x '%g'\n";
  for (const std::string& panel : panels) {
    s << "set title '" << panel << "'\nplot ";
    bool first = true;
    for (const ConvergeCurve& c : curves) {
      if (c.panel != panel) continue;
      const std::string data = "data/convergence-" + safe(c.panel + "-" + c.name) + ".dat";
      std::ofstream f(fs::path(pc.out) / data);
      f << "# frames total_ms flip\n";
      for (const ConvergeCurve::Point& p : c.points) f << p.frames << " " << p.totalMs << " " << std::max(p.flip, 1e-5) << "\n";
      s << (first ? "" : ", \\\n     ") << "'" << data << "' using 1:3 with linespoints lw 2 pt 7 title '" << c.name << "'";
      first = false;
    }
    s << "\n";
  }
  s << "unset multiplot\n";
  runGnuplot(pc, "convergence", s.str());
}

void plotRadiosity(const PlotContext& pc, const std::vector<ConvergeCurve>& curves, double ambientFlip) {
  if (curves.empty()) return;
  std::ostringstream s;
  s << header(pc, "radiosity", 640, 460, 1, 1, "Radiosity: error against the path-traced truth vs solve time");
  s << "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n";
  s << "set xlabel 'solve time, ms (log scale)'\nset ylabel 'FLIP mean vs path-traced (log scale)'\n";
  s << "set key top right box opaque font ',8'\nset format y '%g'\nset format x '%g'\n";
  s << "set title '" << curves.front().panel << "'\nplot ";
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const ConvergeCurve& c = curves[i];
    const std::string data = "data/radiosity-" + safe(c.name) + ".dat";
    std::ofstream f(fs::path(pc.out) / data);
    f << "# shots solve_ms flip\n";
    for (const ConvergeCurve::Point& p : c.points) f << p.frames << " " << std::max(p.totalMs, 1e-3) << " " << std::max(p.flip, 1e-5) << "\n";
    s << (i == 0 ? "" : ", \\\n     ") << "'" << data << "' using 2:3 with linespoints lw 2 pt 7 title '" << c.name << "'";
  }
  s << ", \\\n     " << std::max(ambientFlip, 1e-5) << " with lines dt 2 lc rgb '#888888' title 'ambient term'\n";
  s << "unset multiplot\n";
  runGnuplot(pc, "radiosity", s.str());
}

void plotStages(const PlotContext& pc, const std::vector<StagePanel>& panels, const std::vector<std::string>& stages) {
  if (panels.empty()) return;
  int cols = columnsFor(panels.size(), pc.rows);
  std::ostringstream s;
  s << header(pc, "stages", 560 * cols, 440 * pc.rows, pc.rows, cols, "Frame time by stage per preset (median)");
  s << "set style data histograms\nset style histogram rowstacked\nset style fill solid 0.85 border -1\n";
  s << "set boxwidth 0.7\nset ylabel 'ms per frame (median)'\nset grid ytics lc rgb '#dddddd'\n";
  s << "set key top left reverse Left font ',8'\nset xtics font ',9'\nset yrange [0:*]\n";
  for (const StagePanel& p : panels) {
    std::string file = "data/stages-" + safe(p.scene + "-" + p.size) + ".dat";
    std::ofstream f(fs::path(pc.out) / file);
    f << "preset";
    for (const std::string& st : stages) f << " " << st;
    f << "\n";
    for (const StageBar& b : p.bars) {
      f << b.name;
      for (double v : b.ms) f << " " << v;
      f << "\n";
    }
    s << "set title '" << p.scene << " " << p.size << "'\n";
    s << "plot for [i=2:" << stages.size() + 1 << "] '" << file << "' using i:xtic(1) title columnheader(i)\n";
  }
  s << "unset multiplot\n";
  runGnuplot(pc, "stages", s.str());
}

void plotHeat(const PlotContext& pc, const std::vector<HeatPanel>& panels) {
  std::vector<std::string> effects;
  for (const HeatPanel& p : panels)
    if (std::find(effects.begin(), effects.end(), p.effect) == effects.end()) effects.push_back(p.effect);
  for (const std::string& effect : effects) {
    std::vector<const HeatPanel*> mine;
    for (const HeatPanel& p : panels)
      if (p.effect == effect) mine.push_back(&p);
    int cols = columnsFor(mine.size(), pc.rows);
    std::ostringstream s;
    s << header(pc, "heat-" + effect, 640 * cols, 420 * pc.rows, pc.rows, cols,
                "Where " + effect + " by rays and by raster disagree (FLIP, " + effect + " ray traced vs raster preset)");
    s << kMagma << "set cbrange [0:1]\nset cblabel 'FLIP'\nset size ratio -1\nunset xtics\nunset ytics\n";
    s << "set autoscale xfix\nset autoscale yfix\n";
    for (const HeatPanel* p : mine) {
      std::string rel = fs::relative(p->dataPath, pc.out).string();
      char mean[32];
      std::snprintf(mean, sizeof mean, "%.4f", p->mean);
      s << "set title '" << p->scene << " " << p->size << ", mean FLIP " << mean << "'\n";
      s << "plot '" << rel << "' binary array=(" << p->width << "," << p->height
        << ") flipy format='%float' with image notitle\n";
    }
    s << "unset multiplot\n";
    runGnuplot(pc, "heat-" + effect, s.str());
  }
}

void writeHeavyTables(const std::string& out, const std::vector<HeavyRow>& rows, const std::vector<std::string>& stages,
                      const std::string& cpu, const std::string& gl, int threads) {
  {
    std::ofstream f(fs::path(out) / "heavy.csv");
    f << "triangles,size,generate_ms,set_scene_ms,embree_build_ms";
    for (const std::string& s : stages) f << "," << s << "_ms";
    f << ",total_ms,raster_preset_ms,cast_visibility_ms,rays_primary,rays_shadow,rays_reflection,rays_refraction,"
         "peak_rss_mib\n";
    for (const HeavyRow& r : rows) {
      f << r.triangles << "," << r.size << "," << r.generateMs << "," << r.setSceneMs << "," << r.embreeBuildMs;
      for (double v : r.stageMs) f << "," << v;
      f << "," << r.totalMs << "," << r.rasterPresetMs << "," << r.castVisibilityMs << "," << r.rays.primary << ","
        << r.rays.shadow << "," << r.rays.reflection << "," << r.rays.refraction << "," << r.peakRssMiB << "\n";
    }
  }
  std::ofstream f(fs::path(out) / "heavy.md");
  f << "# tandem-bench heavy scenes (hybrid-full; makeHeavyScene)\n\n" << cpu << ", " << threads
    << " ray-pass threads; " << gl << ". Stage times in ms, median per frame. setScene = GL upload + Embree "
    << "build inside the Renderer; Embree build = a separate RayTracer::setScene. castVisibility = primary "
    << "visibility by Embree rays at the same size, to compare with raster + readback.\n\n";
  f << "| triangles | size | setScene | Embree build";
  for (const std::string& s : stages) f << " | " << s;
  f << " | frame | raster preset frame | castVisibility | peak RSS MiB |\n|---|---|---|---";
  for (std::size_t i = 0; i < stages.size(); ++i) f << "|---";
  f << "|---|---|---|---|\n";
  char buf[64];
  for (const HeavyRow& r : rows) {
    f << "| " << r.triangles << " | " << r.size;
    for (double v : {r.setSceneMs, r.embreeBuildMs}) {
      std::snprintf(buf, sizeof buf, " | %.0f", v);
      f << buf;
    }
    for (double v : r.stageMs) {
      std::snprintf(buf, sizeof buf, " | %.1f", v);
      f << buf;
    }
    std::snprintf(buf, sizeof buf, " | %.1f | %.1f | %.1f | %.0f |\n", r.totalMs, r.rasterPresetMs, r.castVisibilityMs,
                  r.peakRssMiB);
    f << buf;
  }
}

void plotHeavy(const PlotContext& pc, const std::vector<HeavyRow>& rows, const std::vector<std::string>& stages) {
  std::vector<std::string> sizes;
  for (const HeavyRow& r : rows)
    if (std::find(sizes.begin(), sizes.end(), r.size) == sizes.end()) sizes.push_back(r.size);
  if (sizes.empty()) return;
  std::ostringstream s;
  int cols = static_cast<int>(sizes.size());
  s << "set terminal " << terminal() << " size " << 620 * cols << ",500\nset output 'heavy.png'\n";
  s << "set multiplot layout 1," << cols << " title \"Cost growth with triangles (hybrid-full, makeHeavyScene)\\n{/*0.75 "
    << pc.cpu << ", " << pc.threads << " ray-pass threads}\\n{/*0.75 " << pc.gl << "}\"\n";
  s << "set logscale xy\nset grid xtics ytics lc rgb '#dddddd'\nset xlabel 'triangles (log scale)'\n";
  s << "set ylabel 'ms per frame (median, log scale)'\nset key outside right font ',9'\nset format x '%.0s%c'\n";
  for (const std::string& size : sizes) {
    std::string file = "data/heavy-" + safe(size) + ".dat";
    std::ofstream f(fs::path(pc.out) / file);
    f << "triangles";
    for (const std::string& st : stages) f << " " << st;
    f << " frame raster-preset castVisibility\n";
    for (const HeavyRow& r : rows) {
      if (r.size != size) continue;
      f << r.triangles;
      for (double v : r.stageMs) f << " " << std::max(v, 1e-3);
      f << " " << r.totalMs << " " << r.rasterPresetMs << " " << std::max(r.castVisibilityMs, 1e-3) << "\n";
    }
    s << "set title '" << size << "'\n";
    // Column 2 (prepare) is left out: after the warm-up frame it is ~0 and cannot sit on a log axis.
    s << "plot for [i=3:" << stages.size() + 4 << "] '" << file
      << "' using 1:i with linespoints lw 2 pt 7 title columnheader(i)\n";
  }
  s << "unset multiplot\n";
  runGnuplot(pc, "heavy", s.str());
}

}  // namespace tandem::bench
