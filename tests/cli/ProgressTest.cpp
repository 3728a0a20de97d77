// tandem-render's progress line, on a fake clock: silent before the threshold, then percent, elapsed and
// ETA, throttled, never going backwards, over all frames; finished with a 100% line only if it was shown.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "Progress.h"

namespace tandem::cli {
namespace {

TEST(FormatDuration, SecondsMinutesHours) {
  EXPECT_EQ(formatDuration(0.0), "0.0 s");
  EXPECT_EQ(formatDuration(12.34), "12.3 s");
  EXPECT_EQ(formatDuration(59.9), "59.9 s");
  EXPECT_EQ(formatDuration(59.97), "1 min 00 s");
  EXPECT_EQ(formatDuration(125.0), "2 min 05 s");
  EXPECT_EQ(formatDuration(3725.0), "1 h 02 min");
  EXPECT_EQ(formatDuration(-1.0), "0.0 s");
}

TEST(FormatProgress, PercentElapsedAndEtaAtThePaceSoFar) {
  EXPECT_EQ(formatProgress(0.25, 10.0), "25%, 10.0 s elapsed, ETA 30.0 s");
  EXPECT_EQ(formatProgress(0.5, 61.0), "50%, 1 min 01 s elapsed, ETA 1 min 01 s");
  EXPECT_EQ(formatProgress(0.999, 5.0), "99%, 5.0 s elapsed, ETA 0.0 s");  // never 100% before the end
  EXPECT_EQ(formatProgress(0.0, 3.0), "0%, 3.0 s elapsed, ETA unknown");
  EXPECT_EQ(formatProgress(1.0, 4.0), "100%, 4.0 s elapsed, ETA 0.0 s");
}

/// A ProgressLine writing into memory, on a clock the test moves.
struct Harness {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  double now = 100.0;
  ~Harness() {
    std::fclose(out);
    std::free(buffer);
  }
  ProgressLine make(bool rewrite, double showAfter, int frames) {
    return ProgressLine(out, rewrite, showAfter, frames, [this] { return now; });
  }
  std::string text() {
    std::fflush(out);
    return std::string(buffer, size);
  }
};

TEST(ProgressLine, SilentUntilTheThresholdThenOneLinePerInterval) {
  Harness h;
  ProgressLine line = h.make(false, 2.0, 1);
  line.beginFrame(0);
  h.now += 1.9;
  line.onRayPass({10, 100});
  EXPECT_EQ(h.text(), "");
  h.now += 0.2;  // 2.1 s: past the threshold
  line.onRayPass({30, 100});
  EXPECT_EQ(h.text(), "tandem-render: 30%, 2.1 s elapsed, ETA 4.9 s\n");
  h.now += 1.0;  // within the 5 s a log line waits
  line.onRayPass({40, 100});
  EXPECT_EQ(h.text(), "tandem-render: 30%, 2.1 s elapsed, ETA 4.9 s\n");
  h.now += 4.5;
  line.onRayPass({80, 100});
  line.finish();
  EXPECT_EQ(h.text(),
            "tandem-render: 30%, 2.1 s elapsed, ETA 4.9 s\n"
            "tandem-render: 80%, 7.6 s elapsed, ETA 1.9 s\n"
            "tandem-render: 100%, done in 7.6 s\n");
}

TEST(ProgressLine, ShortRenderPrintsNothingAtAll) {
  Harness h;
  ProgressLine line = h.make(false, 2.0, 1);
  line.beginFrame(0);
  for (std::uint64_t t = 1; t <= 100; ++t) {
    h.now += 0.01;
    line.onRayPass({t, 100});
  }
  line.finish();
  EXPECT_EQ(h.text(), "");
}

TEST(ProgressLine, TheClockStartsWithTheFirstFrame) {
  Harness h;
  ProgressLine line = h.make(false, 2.0, 1);
  h.now += 30.0;  // creating the renderer, building nothing the progress is about
  line.beginFrame(0);
  h.now += 1.0;
  line.onRayPass({50, 100});
  EXPECT_EQ(h.text(), "");
}

TEST(ProgressLine, PercentCoversEveryFrameAndNeverGoesBack) {
  Harness h;
  ProgressLine line = h.make(false, 0.0, 4);
  line.beginFrame(0);
  h.now += 1.0;
  line.onRayPass({50, 100});  // half of frame 1 of 4
  h.now += 5.0;
  line.onRayPass({40, 100});  // a late call from another thread: the line stays at 12%
  line.beginFrame(2);         // frames 1 and 2 done
  h.now += 6.0;
  line.beginFrame(3);
  EXPECT_EQ(h.text(),
            "tandem-render: 12%, 1.0 s elapsed, ETA 7.0 s (frame 1/4)\n"
            "tandem-render: 12%, 6.0 s elapsed, ETA 42.0 s (frame 1/4)\n"
            "tandem-render: 75%, 12.0 s elapsed, ETA 4.0 s (frame 4/4)\n");
}

TEST(ProgressLine, TerminalRedrawsOneLineAndEndsIt) {
  Harness h;
  ProgressLine line = h.make(true, 0.0, 1);
  line.beginFrame(0);
  h.now += 10.0;
  line.onRayPass({1, 10});
  h.now += 0.1;  // within the 0.2 s a terminal redraw waits
  line.onRayPass({2, 10});
  h.now += 0.2;
  line.onRayPass({9, 10});
  line.finish();
  EXPECT_EQ(h.text(),
            "\rtandem-render: 10%, 10.0 s elapsed, ETA 1 min 30 s"
            "\rtandem-render: 90%, 10.3 s elapsed, ETA 1.1 s" + std::string(5, ' ') +  // clears the longer line
                "\rtandem-render: 100%, done in 10.3 s" + std::string(10, ' ') + "\n");
}

}  // namespace
}  // namespace tandem::cli
