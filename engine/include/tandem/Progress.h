#pragma once
// Progress of a frame's ray pass, for callers that show it while a long frame renders (tandem-render's
// progress line). Reference frames trace everything in the ray pass, so for them it is the frame's progress.
#include <cstdint>
#include <functional>

namespace tandem {

/// Tiles of the current frame's ray pass finished so far, out of all of them. A tile is a 16×16 block of
/// the ray grid (hybrid frames) or of the image (reference frames).
struct RayPassProgress {
  std::uint64_t tilesDone = 0;  // 1..tiles
  std::uint64_t tiles = 0;
};

/// Called by the ray pass as each tile finishes, from its worker threads: concurrently, and not
/// necessarily in order of tilesDone (each value 1..tiles is reported exactly once per frame; the call
/// with tilesDone == tiles may come before others). It runs inside the pass, so it must be thread-safe,
/// must not throw, and should return quickly: a 1280×720 frame makes 3 600 calls.
using RayPassProgressCallback = std::function<void(const RayPassProgress&)>;

}  // namespace tandem
