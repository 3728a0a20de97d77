#pragma once
// tandem-render's progress line on stderr: percent done, time elapsed and an estimate of the time left,
// shown once a render has run longer than a threshold (2 s by default) so that short renders stay silent.
#include <atomic>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>

#include "tandem/Progress.h"

namespace tandem::cli {

/// "12.3 s" under a minute, "2 min 05 s" under an hour, else "1 h 02 min".
std::string formatDuration(double seconds);
/// "42%, 12.3 s elapsed, ETA 17.0 s" (fraction in [0, 1]). The ETA assumes the rest goes at the pace so
/// far; with nothing done yet there is no pace, and it says "ETA unknown".
std::string formatProgress(double fraction, double elapsedSeconds);

class ProgressLine {
 public:
  using Clock = std::function<double()>;  // seconds, monotonic
  static double steadySeconds();

  /// `out` receives the line: with `rewrite` (a terminal) one line redrawn after '\r' at most 5 times a
  /// second, else a new line at most every 5 s (a log). Nothing is printed before `showAfterSeconds`.
  /// `frames` is how many frames the run renders: the percentage covers all of them.
  ProgressLine(std::FILE* out, bool rewrite, double showAfterSeconds, int frames, Clock clock = steadySeconds);

  /// Main thread, before frame `index` (0-based) renders; frame 0 starts the clock, so the time spent
  /// creating the renderer does not count towards the pace (and the ETA).
  void beginFrame(int index);
  /// The renderer's progress callback: any thread, concurrently (RendererDesc::progress).
  void onRayPass(const RayPassProgress& p);
  /// Main thread, after the last frame: when a line was shown, ends it with "100%, done in ...".
  void finish();

 private:
  void report(double fraction);  // any thread; prints when due

  std::FILE* out_;
  bool rewrite_;
  double showAfter_;
  double interval_;
  int frames_;
  Clock clock_;
  double start_;                   // written by beginFrame(0), before any ray pass runs
  std::atomic<int> frame_{0};
  std::atomic<double> nextPrint_;  // no line before this time (seconds on clock_)
  std::mutex mutex_;               // guards the members below and the output
  double shownFraction_ = 0.0;     // calls arrive out of order: the line never goes backwards
  std::size_t lastLength_ = 0;
  bool shown_ = false;
};

}  // namespace tandem::cli
