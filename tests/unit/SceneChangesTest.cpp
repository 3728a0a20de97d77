// The scene's change record (render/SceneChanges.h) and what the frame history makes of it
// (FrameHistory::apply): the Renderer's mutators only record, and each consumer reads the record.
#include <gtest/gtest.h>

#include "render/FrameHistory.h"
#include "render/SceneChanges.h"

namespace tandem {
namespace {

TEST(SceneChanges, RecordsAccumulateUntilApplied) {
  SceneChanges c;
  EXPECT_FALSE(c.any());
  EXPECT_FALSE(c.instancesMoved());
  SceneChanges moved;
  moved.dynamicMoved = true;
  c |= moved;
  EXPECT_TRUE(c.any());
  EXPECT_TRUE(c.instancesMoved());
  EXPECT_FALSE(c.staticMoved);
  SceneChanges light;
  light.lights = true;
  c |= light;
  EXPECT_TRUE(c.dynamicMoved);  // an earlier change is not forgotten by a later one
  EXPECT_TRUE(c.lights);
  EXPECT_FALSE(c.replaced);
  SceneChanges each[4];
  each[0].replaced = true;
  each[1].staticMoved = true;
  each[2].dynamicMoved = true;
  each[3].lights = true;
  for (const SceneChanges& e : each) EXPECT_TRUE(e.any());
  EXPECT_TRUE(each[1].instancesMoved());
  EXPECT_FALSE(each[0].instancesMoved());  // a new scene is more than a move: its consumers start again
}

TEST(SceneChanges, TheHistorySeesEveryChangeAndANewSceneAsReplaced) {
  for (int k = 0; k < 4; ++k) {
    SceneChanges c;
    if (k == 0) c.replaced = true;
    if (k == 1) c.staticMoved = true;
    if (k == 2) c.dynamicMoved = true;
    if (k == 3) c.lights = true;
    FrameHistory h;
    h.apply(SceneChanges{});
    EXPECT_FALSE(h.sceneChanged);  // nothing recorded, nothing stale
    h.apply(c);
    EXPECT_TRUE(h.sceneChanged) << k;
    EXPECT_EQ(h.sceneReplaced, k == 0) << k;
    // Applying nothing afterwards keeps what is stale until the next frame is remembered.
    h.apply(SceneChanges{});
    EXPECT_TRUE(h.sceneChanged) << k;
    h.remember(FramePlan{}, Camera{}, Scene{}, false, 0);
    EXPECT_FALSE(h.sceneChanged) << k;
    EXPECT_FALSE(h.sceneReplaced) << k;
  }
}

}  // namespace
}  // namespace tandem
