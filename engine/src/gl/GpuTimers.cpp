#include "gl/GpuTimers.h"

#include <cassert>

namespace tandem::gl {

namespace {
// Frames whose results are still out are kept this many deep; older ones are dropped unread.
constexpr std::size_t kMaxPending = 8;
}  // namespace

GLuint GpuTimers::take() {
  if (!free_.empty()) {
    const GLuint q = free_.back();
    free_.pop_back();
    return q;
  }
  GLuint q = 0;
  glGenQueries(1, &q);
  return q;
}

void GpuTimers::begin(Stage stage) {
  assert(!running_ && "GpuTimers: stages do not nest");
  const GLuint start = take();
  glQueryCounter(start, GL_TIMESTAMP);
  current_.queries.push_back({stage, start, 0});
  running_ = true;
}

void GpuTimers::end() {
  assert(running_ && "GpuTimers: end() without begin()");
  current_.queries.back().end = take();
  glQueryCounter(current_.queries.back().end, GL_TIMESTAMP);
  running_ = false;
}

GpuStageTimes GpuTimers::endFrame() {
  assert(!running_ && "GpuTimers: a stage still running at the frame's end");
  current_.index = ++frames_;
  if (!current_.queries.empty()) pending_.push_back(std::move(current_));
  current_ = Frame{};
  while (pending_.size() > kMaxPending) {  // results that never came (a lost context): forget them
    for (const Timed& q : pending_.front().queries) free_.push_back(q.start), free_.push_back(q.end);
    pending_.pop_front();
  }
  // The oldest frames first: a frame's results are there when its last query's are (they finish in order).
  while (!pending_.empty()) {
    Frame& f = pending_.front();
    GLuint available = 0;
    glGetQueryObjectuiv(f.queries.back().end, GL_QUERY_RESULT_AVAILABLE, &available);
    if (!available) break;
    GpuStageTimes t;
    t.valid = true;
    for (const Timed& q : f.queries) {
      GLuint64 start = 0, end = 0;
      glGetQueryObjectui64v(q.start, GL_QUERY_RESULT, &start);
      glGetQueryObjectui64v(q.end, GL_QUERY_RESULT, &end);
      free_.push_back(q.start);
      free_.push_back(q.end);
      const double ms = end > start ? static_cast<double>(end - start) * 1e-6 : 0.0;
      switch (q.stage) {
        case Shadows: t.shadowsMs += ms; break;
        case Probes: t.probesMs += ms; break;
        case Raster: t.rasterMs += ms; break;
        case Upload: t.uploadMs += ms; break;
        case Composite: t.compositeMs += ms; break;
        case Accumulate: t.accumulateMs += ms; break;
        case kStages: break;
      }
    }
    latest_ = t;
    latestIndex_ = f.index;
    pending_.pop_front();
  }
  GpuStageTimes out = latest_;
  out.framesAgo = latest_.valid ? static_cast<int>(frames_ - latestIndex_) : 0;
  return out;
}

void GpuTimers::release() {
  for (Frame& f : pending_)
    for (const Timed& q : f.queries) free_.push_back(q.start), free_.push_back(q.end);
  for (const Timed& q : current_.queries) {
    free_.push_back(q.start);
    if (q.end != 0) free_.push_back(q.end);
  }
  pending_.clear();
  current_ = Frame{};
  if (!free_.empty()) glDeleteQueries(static_cast<GLsizei>(free_.size()), free_.data());
  free_.clear();
  running_ = false;
}

}  // namespace tandem::gl
