// The ray pass's progress callback (tandem/Progress.h): every tile of the frame reported exactly once, with
// the frame's tile count, from whichever worker thread finished it; none when no callback is set.
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>
#include <numeric>
#include <vector>

#include "RtTestScenes.h"

namespace tandem::rt::test {
namespace {

struct Recorder {
  std::mutex mutex;
  std::vector<RayPassProgress> calls;
  RayPassProgressCallback callback() {
    return [this](const RayPassProgress& p) {
      std::lock_guard<std::mutex> lock(mutex);
      calls.push_back(p);
    };
  }
  /// tilesDone over all calls is exactly 1..tiles, each with `tiles` as the total.
  void expectEveryTileOnce(std::uint64_t tiles) {
    ASSERT_EQ(calls.size(), tiles);
    std::vector<std::uint64_t> done;
    for (const RayPassProgress& p : calls) {
      EXPECT_EQ(p.tiles, tiles);
      done.push_back(p.tilesDone);
    }
    std::sort(done.begin(), done.end());
    std::vector<std::uint64_t> expected(tiles);
    std::iota(expected.begin(), expected.end(), 1u);
    EXPECT_EQ(done, expected);
  }
};

TEST(RayPassProgress, HybridPassReportsEveryTileOfTheRayGrid) {
  Scene scene = makeWhittedScene();
  auto rt = makeTracer(scene, 2);
  ASSERT_TRUE(rt);
  Recorder rec;
  rt->setProgressCallback(rec.callback());
  FrameSettings s = settingsFor(100, 60);  // 7 × 4 tiles of 16×16
  VisibilityBuffer vis;
  RayOutputs out;
  castAndTrace(*rt, scene, s, vis, out);
  rec.expectEveryTileOnce(7 * 4);
  // At half resolution the grid is 50 × 30: 4 × 2 tiles. The count restarts with each frame.
  rec.calls.clear();
  s.rayScale = 2;
  castAndTrace(*rt, scene, s, vis, out);
  rec.expectEveryTileOnce(4 * 2);
}

TEST(RayPassProgress, ReferenceFrameReportsEveryTileOfTheImage) {
  Scene scene = makeWhittedScene();
  auto rt = makeTracer(scene, 2);
  ASSERT_TRUE(rt);
  Recorder rec;
  rt->setProgressCallback(rec.callback());
  FrameSettings s = *presetSettings("reference", settingsFor(40, 33));  // 3 × 3 tiles
  ImageF image;
  RayCounts counts;
  rt->renderReference(scene, scene.camera, s, image, counts);
  rec.expectEveryTileOnce(3 * 3);
}

TEST(RayPassProgress, ClearedCallbackIsNotCalled) {
  Scene scene = makeWhittedScene();
  auto rt = makeTracer(scene, 2);
  ASSERT_TRUE(rt);
  Recorder rec;
  rt->setProgressCallback(rec.callback());
  rt->setProgressCallback({});
  VisibilityBuffer vis;
  RayOutputs out;
  castAndTrace(*rt, scene, settingsFor(64, 32), vis, out);
  EXPECT_GT(out.counts.primary, 0u);
  EXPECT_TRUE(rec.calls.empty());
}

}  // namespace
}  // namespace tandem::rt::test
