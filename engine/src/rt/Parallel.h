#pragma once
// The ray pass's parallel loops: tiles of the ray grid, each run start to end on one thread.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

// ThreadSanitizer builds (tools/test.sh --tsan) run the parallel loops on plain std::threads: Debian's
// libtbb is not built with -fsanitize=thread, so TSan never sees the synchronisation inside it and reports
// every hand-over in TBB's inlined partitioner as a race, burying anything real. std::thread's start and
// join and the atomic counter below are visible to TSan, so our own code (the tile bodies, the shared
// outputs and counters) is still checked, on the same number of threads. Normal builds keep TBB.
#if defined(__SANITIZE_THREAD__)
#define TANDEM_TSAN_THREADS 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TANDEM_TSAN_THREADS 1
#endif
#endif

#ifdef TANDEM_TSAN_THREADS
#include <sanitizer/tsan_interface.h>
#endif

namespace tandem::rt {

/// Square tiles of ray-grid pixels: the unit of parallel work, of one batched shadow-ray call, and of
/// the bench's capture (RayCapture::tiles).
inline constexpr int kTile = 16;

inline int tileCount(int n) { return (n + kTile - 1) / kTile; }
/// Row-major index of the tile starting at (x0, y0) on a grid `width` wide: the RayCapture tile order.
inline std::size_t tileIndex(int x0, int y0, int width) {
  return static_cast<std::size_t>(y0 / kTile) * static_cast<std::size_t>(tileCount(width)) +
         static_cast<std::size_t>(x0 / kTile);
}

// Embree's builders call back into our code from TBB worker threads (a user geometry's bounds, the device's
// memory and error callbacks), which TBB hands the build to through the same uninstrumented queues: TSan
// sees the callback read an object the main thread wrote with nothing ordering the two. publishToBuilders
// (after the writes, before anything is committed) and receivedFromBuilder (first thing in the callback)
// state that ordering, which TBB's hand-over provides; they compile to nothing outside ThreadSanitizer
// builds, and our code stays checked. (The ray pass's own loops run on std::threads under TSan, above, but
// direct EmbreeScene::build calls and the radiosity job's arenas build on TBB's workers.)
inline void publishToBuilders([[maybe_unused]] const void* object) {
#ifdef TANDEM_TSAN_THREADS
  __tsan_release(const_cast<void*>(object));
#endif
}
inline void receivedFromBuilder([[maybe_unused]] const void* object) {
#ifdef TANDEM_TSAN_THREADS
  __tsan_acquire(const_cast<void*>(object));
#endif
}

/// Runs body(i) for i in [0, n) on `threads` threads (TBB: inside the caller's arena), in any order.
template <class Body>
void parallelIndices(int threads, std::size_t n, Body&& body) {
#ifdef TANDEM_TSAN_THREADS
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) body(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
#else
  (void)threads;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
#endif
}

/// Runs body(x0, y0, x1, y1) for every tile of a width × height grid, in parallel. The order tiles run
/// in does not matter: every pixel depends on nothing but its own inputs.
template <class Body>
void forEachTile(int threads, int width, int height, Body&& body) {
  int tilesX = tileCount(width), tilesY = tileCount(height);
  parallelIndices(threads, static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY), [&](std::size_t i) {
    int t = static_cast<int>(i);
    int x0 = (t % tilesX) * kTile, y0 = (t / tilesX) * kTile;
    body(x0, y0, std::min(x0 + kTile, width), std::min(y0 + kTile, height));
  });
}

}  // namespace tandem::rt
