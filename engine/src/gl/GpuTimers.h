#pragma once
// The GPU's own time of the frame's GL stages (FrameStats::gpu), by timestamp queries (glQueryCounter at each
// stage's start and end: llvmpipe's GL_TIME_ELAPSED returned its clock's value, not an interval, for a stage
// begun right after a glFinish). Results are collected a frame or more later, when the GL says they are there:
// the frame never waits for them. The Renderer times whole stages; the passes inside them time nothing.
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include "gl/Gl.h"
#include "tandem/FrameStats.h"

namespace tandem::gl {

class GpuTimers {
 public:
  enum Stage { Shadows, Probes, Raster, Upload, Composite, Accumulate, kStages };
  GpuTimers() = default;
  GpuTimers(const GpuTimers&) = delete;
  GpuTimers& operator=(const GpuTimers&) = delete;
  ~GpuTimers() { release(); }

  /// Starts timing `stage` (added up when a frame times it several times); end() before the next begin().
  void begin(Stage stage);
  void end();
  /// The frame's queries are all issued. Collects the results of earlier frames that have come back, without
  /// waiting, and returns the latest complete frame's times (valid = false before the first).
  GpuStageTimes endFrame();
  /// Deletes the query objects (with the context current).
  void release();

 private:
  struct Timed {
    Stage stage;
    GLuint start, end;
  };
  struct Frame {
    std::uint64_t index = 0;
    std::vector<Timed> queries;
  };
  GLuint take();
  std::vector<GLuint> free_;
  Frame current_;
  std::deque<Frame> pending_;
  GpuStageTimes latest_;
  std::uint64_t latestIndex_ = 0, frames_ = 0;
  bool running_ = false;
};

/// Times one stage for its scope: `GpuStage g(timers, GpuTimers::Raster);` (timers may be null: not timed).
class GpuStage {
 public:
  GpuStage(GpuTimers* timers, GpuTimers::Stage stage) : timers_(timers) {
    if (timers_) timers_->begin(stage);
  }
  ~GpuStage() {
    if (timers_) timers_->end();
  }
  GpuStage(const GpuStage&) = delete;
  GpuStage& operator=(const GpuStage&) = delete;

 private:
  GpuTimers* timers_;
};

}  // namespace tandem::gl
