#pragma once
// tandem-bench --budget: the game's scripted run at several frame-time targets, its frame times and its error
// per frame (docs/bench.md, docs/budget.md).
#include <string>
#include <vector>

namespace tandem::bench {

struct BudgetOptions {
  std::vector<double> targetsMs;  // empty: 80 %, 60 % and 45 % of the requested settings' median frame
  std::string preset = "hybrid-full";
  std::string size = "640x360";
  int frames = 330;
  int errorEvery = 10;
  int threads = 0;
  std::string out = "out/bench";
  bool plots = true;
};

/// Writes OUT/budget.md, budget.csv, budget-*.csv (the game's per-frame logs) and budget.png.
int runBudget(const BudgetOptions& options);

}  // namespace tandem::bench
