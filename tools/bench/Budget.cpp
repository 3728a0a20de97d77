// tandem-bench --budget: the game's scripted run played at several frame-time targets (tandem-game
// --headless --target-fps, one process per run, the way a player's machine would run it), with the per-frame
// log of each: frame time against the target, the budget's choice, and every Nth frame the FLIP against the
// same instant drawn as requested without a budget.
#include "Budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "BenchCommon.h"

namespace fs = std::filesystem;

namespace tandem::bench {

namespace {

struct LogRow {
  int frame = 0;
  double totalMs = 0;
  double rays = 0;
  double targetMs = 0;
  int step = 0;
  std::string choice;
  bool hasFlip = false;
  double flip = 0;
};

// One CSV line with quoted fields (the choice).
std::vector<std::string> csvCells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    else if (ch == ',' && !quoted) cells.push_back(cell), cell.clear();
    else cell += ch;
  }
  cells.push_back(cell);
  return cells;
}

// The index of column `name` in a --frame-log's header (header.size() when it has none).
std::size_t columnOf(const std::vector<std::string>& header, const char* name) {
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

std::vector<std::string> logHeader(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  return std::getline(f, line) ? csvCells(line) : std::vector<std::string>{};
}

// The game's --frame-log, its columns found by name (docs/game.md lists them).
std::vector<LogRow> readLog(const std::string& path) {
  std::vector<LogRow> rows;
  std::ifstream f(path);
  std::string line;
  if (!std::getline(f, line)) return rows;
  const std::vector<std::string> header = csvCells(line);
  auto column = [&](const char* name) { return columnOf(header, name); };
  const std::size_t frame = column("frame"), total = column("total_ms"), rays = column("rays"),
                    target = column("target_ms"), step = column("step"), choice = column("choice"), flip = column("flip");
  while (std::getline(f, line)) {
    const std::vector<std::string> cells = csvCells(line);
    if (cells.size() != header.size() || flip >= cells.size()) continue;
    LogRow r;
    r.frame = std::atoi(cells[frame].c_str());
    r.totalMs = std::atof(cells[total].c_str());
    r.rays = std::atof(cells[rays].c_str());
    r.targetMs = std::atof(cells[target].c_str());
    r.step = std::atoi(cells[step].c_str());
    r.choice = cells[choice];
    r.hasFlip = !cells[flip].empty();
    r.flip = std::atof(cells[flip].c_str());
    rows.push_back(r);
  }
  return rows;
}

struct RunSummary {
  std::string name;       // "as requested" or "target N ms"
  double targetMs = 0;    // 0: no budget
  std::string logPath;
  std::vector<LogRow> rows;
  double medianMs = 0, p90Ms = 0, p99Ms = 0;
  double within10 = 0;     // share of frames (after the first) at most 1.1 × target
  int changes = 0;
  double meanFlip = 0, maxFlip = 0;
  double raysShare = 0;    // rays per frame relative to the unbudgeted run
  std::string mostChosen;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

// Default targets: fractions of the requested settings' median frame.
constexpr double kDefaultFractions[] = {0.8, 0.6, 0.45};

std::string gameExe() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("tandem-game") : (self.parent_path() / "tandem-game").string();
}

bool playRun(const BudgetOptions& o, const std::string& preset, double targetMs, const std::string& logPath,
             int errorEvery) {
  std::ostringstream cmd;
  cmd << "'" << gameExe() << "' --headless --frames " << o.frames << " --size " << o.size << " --preset " << preset
      << " --script '" << sourceDir() << "/tests/game/collect3.script' --reuse off --frame-log '" << logPath << "'";
  if (o.threads > 0) cmd << " --threads " << o.threads;
  if (targetMs > 0) {
    char fps[32];
    std::snprintf(fps, sizeof fps, "%.6f", 1000.0 / targetMs);
    cmd << " --target-fps " << fps;
  }
  if (errorEvery > 0) cmd << " --error-every " << errorEvery;
  cmd << " > '" << logPath << ".out' 2>&1";
  if (std::system(cmd.str().c_str()) != 0) {
    std::fprintf(stderr, "tandem-bench: the game failed: %s (see %s.out)\n", cmd.str().c_str(), logPath.c_str());
    return false;
  }
  return true;
}

void summarizeRun(RunSummary& r, double baseRays) {
  std::vector<double> ms, rays, flips;
  int within = 0;
  std::map<std::string, int> chosen;
  // Frame 0 builds the scene's caches and compiles shaders: a load-time cost, left out of every figure.
  for (std::size_t i = 1; i < r.rows.size(); ++i) {
    const LogRow& row = r.rows[i];
    ms.push_back(row.totalMs);
    rays.push_back(row.rays);
    within += r.targetMs <= 0 || row.totalMs <= 1.1 * r.targetMs ? 1 : 0;
    r.changes += row.step != r.rows[i - 1].step ? 1 : 0;
    ++chosen[row.choice.empty() ? "as requested" : row.choice];
  }
  for (const LogRow& row : r.rows)
    if (row.hasFlip) flips.push_back(row.flip);
  r.medianMs = quantile(ms, 0.5);
  r.p90Ms = quantile(ms, 0.9);
  r.p99Ms = quantile(ms, 0.99);
  r.within10 = ms.empty() ? 0 : static_cast<double>(within) / static_cast<double>(ms.size());
  double sumFlip = 0;
  for (double f : flips) sumFlip += f, r.maxFlip = std::max(r.maxFlip, f);
  r.meanFlip = flips.empty() ? 0 : sumFlip / static_cast<double>(flips.size());
  double sumRays = 0;
  for (double x : rays) sumRays += x;
  const double meanRays = rays.empty() ? 0 : sumRays / static_cast<double>(rays.size());
  r.raysShare = baseRays > 0 ? meanRays / baseRays : 1.0;
  int best = 0;
  for (const auto& [name, n] : chosen)
    if (n > best) best = n, r.mostChosen = name + " (" + std::to_string(n) + " frames)";
}

void plotBudget(const BudgetOptions& o, const std::vector<RunSummary>& runs, const std::string& cpu) {
  std::ostringstream s;
  s << "set terminal pngcairo enhanced font 'DejaVu Sans,10' size 1100,800\nset output 'budget.png'\n";
  s << "set multiplot layout 2,1 title \"The frame-time budget on the game's scripted run (" << o.preset << ", "
    << o.size << ")\\n{/*0.75 " << cpu << "}\"\n";
  s << "set grid lc rgb '#dddddd'\nset key outside right top font ',8'\nset datafile separator ','\n";
  s << "set xlabel 'frame'\nset ylabel 'frame time, ms'\n";
  const char* colours[] = {"#000000", "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  // gnuplot numbers columns from 1; the log's are found by name (its stage columns grow).
  const std::vector<std::string> header = logHeader(runs.empty() ? std::string() : runs[0].logPath);
  const std::size_t frameColumn = columnOf(header, "frame") + 1, totalColumn = columnOf(header, "total_ms") + 1,
                    flipColumn = columnOf(header, "flip") + 1;
  if (std::max({frameColumn, totalColumn, flipColumn}) > header.size()) {
    std::printf("  no plot: the frame log lacks frame, total_ms or flip\n");
    return;
  }
  s << "plot ";
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunSummary& r = runs[i];
    const std::string file = fs::path(r.logPath).filename().string();
    s << (i ? ", " : "") << "'" << file << "' every ::2 using " << frameColumn << ":" << totalColumn
      << " with lines lw 1 lc rgb '" << colours[i % 7]
      << "' title '" << r.name << "'";
    if (r.targetMs > 0)
      s << ", " << r.targetMs << " with lines dt 2 lw 1.5 lc rgb '" << colours[i % 7] << "' notitle";
  }
  s << "\nset ylabel 'FLIP vs as requested'\nset logscale y\nset format y '%g'\n";
  s << "plot ";
  bool first = true;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RunSummary& r = runs[i];
    if (r.targetMs <= 0) continue;
    const std::string file = fs::path(r.logPath).filename().string();
    // Points only where the frame was measured; FLIP 0 (the frame was drawn as requested) sits off a log axis.
    s << (first ? "" : ", ") << "'" << file << "' every ::1 using " << frameColumn << ":($" << flipColumn << " > 0 ? $"
      << flipColumn << " : 1/0) with linespoints pt 7 ps 0.5 lc rgb '"
      << colours[i % 7] << "' title '" << r.name << "'";
    first = false;
  }
  s << "\nunset multiplot\n";
  std::ofstream(fs::path(o.out) / "budget.gp") << s.str();
  const std::string cmd = "cd '" + o.out + "' && gnuplot budget.gp 2> budget.gp.log";
  if (std::system(cmd.c_str()) != 0) std::printf("  gnuplot failed (see %s/budget.gp.log)\n", o.out.c_str());
}

}  // namespace

int runBudget(const BudgetOptions& o) {
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) {
    std::fprintf(stderr, "tandem-bench: cannot create %s: %s\n", o.out.c_str(), ec.message().c_str());
    return 1;
  }
  if (!fs::exists(gameExe())) {
    std::fprintf(stderr, "tandem-bench: --budget plays tandem-game, not found at %s (build it)\n", gameExe().c_str());
    return 1;
  }
  const Machine m = describeMachine();
  std::printf("tandem-bench --budget on %s (%d logical CPUs): the game's scripted run, %d frames at %s, preset %s\n",
              m.cpu.c_str(), m.logicalCpus, o.frames, o.size.c_str(), o.preset.c_str());
  std::vector<RunSummary> runs;
  auto makeRun = [&](std::string name, double targetMs, const std::string& file) {
    RunSummary r;
    r.name = std::move(name);
    r.targetMs = targetMs;
    r.logPath = (fs::path(o.out) / file).string();
    return r;
  };
  RunSummary base = makeRun("as requested", 0, "budget-none.csv");
  if (!playRun(o, o.preset, 0, base.logPath, 0)) return 1;
  base.rows = readLog(base.logPath);
  summarizeRun(base, 0);
  std::printf("  as requested: median %.1f ms, p90 %.1f ms\n", base.medianMs, base.p90Ms);
  double baseRays = 0;
  for (std::size_t i = 1; i < base.rows.size(); ++i) baseRays += base.rows[i].rays;
  baseRays /= static_cast<double>(std::max<std::size_t>(base.rows.size(), 2) - 1);
  // The raster preset for comparison: every effect by raster, no budget (what a game without rays would draw).
  RunSummary raster = makeRun("raster preset", 0, "budget-raster.csv");
  if (!playRun(o, "raster", 0, raster.logPath, 0)) return 1;
  raster.rows = readLog(raster.logPath);
  summarizeRun(raster, baseRays);
  std::printf("  raster preset: median %.1f ms, p90 %.1f ms\n", raster.medianMs, raster.p90Ms);
  std::vector<double> targets = o.targetsMs;
  if (targets.empty())
    for (double f : kDefaultFractions) targets.push_back(std::round(f * base.medianMs * 10.0) / 10.0);
  runs.push_back(base);
  runs.push_back(raster);
  for (double t : targets) {
    char name[64], file[64];
    std::snprintf(name, sizeof name, "target %.1f ms", t);
    std::snprintf(file, sizeof file, "budget-%.1fms.csv", t);
    RunSummary r = makeRun(name, t, file);
    if (!playRun(o, o.preset, t, r.logPath, o.errorEvery)) return 1;
    r.rows = readLog(r.logPath);
    summarizeRun(r, baseRays);
    std::printf("  %s: median %.1f ms, p90 %.1f ms, within 10 %% %.1f %%, %d changes, FLIP mean %.4f, rays %.0f %%; "
                "mostly %s\n",
                name, r.medianMs, r.p90Ms, 100.0 * r.within10, r.changes, r.meanFlip, 100.0 * r.raysShare,
                r.mostChosen.c_str());
    std::fflush(stdout);
    runs.push_back(std::move(r));
  }
  std::ofstream md(fs::path(o.out) / "budget.md");
  md << "# tandem-bench --budget\n\n" << m.cpu << ", " << m.logicalCpus << " logical CPUs. The game's scripted run ("
     << o.frames << " frames, " << o.size << ", preset " << o.preset
     << ", --reuse off), one process per target. Frame 0 (scene build, shader compiles) is left out; FLIP every "
     << o.errorEvery << " frames against the same instant drawn as requested.\n\n";
  md << "| run | median ms | p90 ms | p99 ms | frames ≤ 1.1 × target | changes | FLIP mean | FLIP max | rays/frame | "
        "mostly drawn |\n|---|---|---|---|---|---|---|---|---|---|\n";
  std::ofstream csv(fs::path(o.out) / "budget.csv");
  csv << "run,target_ms,median_ms,p90_ms,p99_ms,within_10pct,changes,flip_mean,flip_max,rays_share\n";
  for (const RunSummary& r : runs) {
    char line[512];
    const bool budgeted = r.targetMs > 0;
    char within[16] = "–", flipMean[16] = "–", flipMax[16] = "–";
    if (budgeted) {
      std::snprintf(within, sizeof within, "%.0f %%", 100.0 * r.within10);
      std::snprintf(flipMean, sizeof flipMean, "%.4f", r.meanFlip);
      std::snprintf(flipMax, sizeof flipMax, "%.4f", r.maxFlip);
    }
    std::snprintf(line, sizeof line, "| %s | %.1f | %.1f | %.1f | %s | %d | %s | %s | %.0f %% | %s |\n",
                  r.name.c_str(), r.medianMs, r.p90Ms, r.p99Ms, within, r.changes, flipMean, flipMax,
                  100.0 * r.raysShare, r.mostChosen.c_str());
    md << line;
    csv << r.name << "," << r.targetMs << "," << r.medianMs << "," << r.p90Ms << "," << r.p99Ms << "," << r.within10
        << "," << r.changes << "," << r.meanFlip << "," << r.maxFlip << "," << r.raysShare << "\n";
  }
  if (o.plots) plotBudget(o, runs, m.cpu);
  std::printf("wrote %s/budget.md, budget.csv%s\n", o.out.c_str(), o.plots ? ", budget.png" : "");
  return 0;
}

}  // namespace tandem::bench
