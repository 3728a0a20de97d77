#include "Progress.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace tandem::cli {

std::string formatDuration(double seconds) {
  char buf[48];
  seconds = std::max(0.0, seconds);
  if (seconds < 59.95) {
    std::snprintf(buf, sizeof buf, "%.1f s", seconds);
  } else if (seconds < 3599.5) {
    long s = std::lround(seconds);
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
  } else {
    long m = std::lround(seconds / 60.0);
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", m / 60, m % 60);
  }
  return buf;
}

std::string formatProgress(double fraction, double elapsedSeconds) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  // Floor, so "100%" means done and a frame at 99.7% does not claim it.
  std::string line = std::to_string(static_cast<int>(std::floor(fraction * 100.0))) + "%, " +
                     formatDuration(elapsedSeconds) + " elapsed, ETA ";
  if (fraction <= 0.0) return line + "unknown";
  return line + formatDuration(elapsedSeconds * (1.0 - fraction) / fraction);
}

double ProgressLine::steadySeconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

ProgressLine::ProgressLine(std::FILE* out, bool rewrite, double showAfterSeconds, int frames, Clock clock)
    : out_(out),
      rewrite_(rewrite),
      showAfter_(showAfterSeconds),
      // A terminal redraws one line, so it can be smooth; a log gets a line per call, so they are rare.
      interval_(rewrite ? 0.2 : 5.0),
      frames_(std::max(1, frames)),
      clock_(std::move(clock)),
      start_(clock_()),
      nextPrint_(start_ + showAfterSeconds) {}

void ProgressLine::beginFrame(int index) {
  frame_.store(index, std::memory_order_relaxed);
  if (index == 0) {
    start_ = clock_();
    nextPrint_.store(start_ + showAfter_, std::memory_order_relaxed);
    return;
  }
  report(static_cast<double>(index) / frames_);
}

void ProgressLine::onRayPass(const RayPassProgress& p) {
  if (p.tiles == 0) return;
  // The cheap test first: this runs once per tile on the ray pass's threads.
  if (clock_() < nextPrint_.load(std::memory_order_relaxed)) return;
  double inFrame = static_cast<double>(p.tilesDone) / static_cast<double>(p.tiles);
  report((frame_.load(std::memory_order_relaxed) + inFrame) / frames_);
}

void ProgressLine::report(double fraction) {
  double now = clock_();
  if (now < nextPrint_.load(std::memory_order_relaxed)) return;
  // A worker finding the line busy skips this update rather than wait: the next tile brings another.
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || now < nextPrint_.load(std::memory_order_relaxed)) return;
  shownFraction_ = std::max(shownFraction_, fraction);
  std::string line = "tandem-render: " + formatProgress(shownFraction_, now - start_);
  if (frames_ > 1)
    line += " (frame " + std::to_string(frame_.load(std::memory_order_relaxed) + 1) + "/" + std::to_string(frames_) + ")";
  if (rewrite_) {
    std::size_t length = line.size();
    line.append(lastLength_ > length ? lastLength_ - length : 0, ' ');  // clear the longer line before
    lastLength_ = length;
    std::fprintf(out_, "\r%s", line.c_str());
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
  shown_ = true;
  nextPrint_.store(now + interval_, std::memory_order_relaxed);
}

void ProgressLine::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!shown_) return;
  std::string line = "tandem-render: 100%, done in " + formatDuration(clock_() - start_);
  if (rewrite_) {
    line.append(lastLength_ > line.size() ? lastLength_ - line.size() : 0, ' ');
    std::fprintf(out_, "\r%s\n", line.c_str());
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
  shown_ = false;
}

}  // namespace tandem::cli
