#pragma once
// A read-back of one colour target through a pixel-pack buffer: start() asks the GL to copy the texels into
// buffer memory the CPU keeps mapped (persistent, coherent) and fences the copy; finish() waits for the fence
// and copies the rows out top-down, the flip GL's bottom-up rows need done by the copy itself (one pass over
// the texels instead of a read and then a flip in place). Between the two the caller goes on: on a GPU the
// copy runs beside it (throughput mode starts the frame's id read-back after its raster and finishes it only
// once the frame before has landed, docs/pipeline.md "Transfers"); on a software GL the copy is done by
// start() itself and finish() is the flip.
#include <cstddef>
#include <cstring>
#include <vector>

#include "gl/GlObjects.h"

namespace tandem::gl {

class PixelReadback {
 public:
  PixelReadback() = default;
  ~PixelReadback() { drop(); }
  PixelReadback(const PixelReadback&) = delete;
  PixelReadback& operator=(const PixelReadback&) = delete;
  PixelReadback(PixelReadback&& other) noexcept { *this = std::move(other); }
  PixelReadback& operator=(PixelReadback&& other) noexcept;

  /// Starts the copy of `fbo`'s colour target 0 (width × height texels of `channel`, tightly packed); the
  /// buffer is made on first need, made again larger when a copy needs more and smaller when it needs under a
  /// quarter. A read-back already pending is dropped. Where the GL
  /// refuses the buffer (out of memory, no mapping) the texels are read into client memory at once instead,
  /// and finish() takes them from there: the same result, without the overlap.
  void start(const Framebuffer& fbo, const ChannelFormat& channel, int width, int height);
  bool pending() const { return pending_; }
  /// Waits for the copy start() began and writes its texels into `pixels` (resized to width × height), row 0
  /// at the top. One T per texel.
  template <class T>
  void finish(std::vector<T>& pixels) {
    assert(pending() && "PixelReadback::finish without start");
    assert(sizeof(T) == texelBytes_ && "PixelReadback::finish: one T per texel of the channel");
    wait();
    pixels.resize(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
    const std::size_t row = static_cast<std::size_t>(width_) * sizeof(T);
    const auto* from = static_cast<const unsigned char*>(source());
    for (int y = 0; y < height_; ++y)
      std::memcpy(pixels.data() + static_cast<std::size_t>(height_ - 1 - y) * static_cast<std::size_t>(width_),
                  from + static_cast<std::size_t>(y) * row, row);
  }
  /// Frees the buffer (a pending read-back is dropped).
  void drop();
  /// Drops a pending read-back, keeping the buffer.
  void cancel();
  /// A size the GL refused may be asked for again (a new frame size: the memory may be there now).
  void retry() { refused_ = 0; }
  /// The mapped buffer's size (0 when none is held).
  std::size_t bytes() const { return bytes_; }

 private:
  void wait();
  bool makeBuffer(std::size_t bytes);
  const void* source() const { return mapped_ ? mapped_ : static_cast<const void*>(fallback_.data()); }

  Buffer buffer_;
  void* mapped_ = nullptr;
  std::size_t bytes_ = 0;
  std::vector<unsigned char> fallback_;  // the texels read at once when the GL refused the buffer
  std::size_t refused_ = 0;              // the size the GL refused (not asked again until drop())
  GLsync fence_ = nullptr;
  bool pending_ = false;
  int width_ = 0, height_ = 0;
  std::size_t texelBytes_ = 0;
};

}  // namespace tandem::gl
