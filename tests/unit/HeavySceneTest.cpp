// makeHeavyScene: exact triangle counts, valid scenes, and every effect present.
#include <gtest/gtest.h>

#include "tandem/HeavyScene.h"
#include "tandem/Result.h"

namespace tandem {
namespace {

TEST(HeavyScene, HitsTheTargetTriangleCountExactly) {
  for (std::size_t target : {10'000u, 10'001u, 100'000u, 123'457u, 500'000u}) {
    Scene s = makeHeavyScene(target);
    EXPECT_EQ(s.triangleCount(), target) << "target " << target;
  }
}

TEST(HeavyScene, SmallTargetsClampToTheMinimum) {
  HeavySceneOptions o;
  std::size_t min = heavySceneMinTriangles(o);
  EXPECT_EQ(makeHeavyScene(0, o).triangleCount(), min);
  EXPECT_EQ(makeHeavyScene(min + 1, o).triangleCount(), min + 1);
}

TEST(HeavyScene, IsValidAndHasMirrorsGlassAndLights) {
  Scene s = makeHeavyScene(50'000);
  auto valid = validateScene(s);
  EXPECT_TRUE(valid.ok()) << (valid ? std::string() : valid.error().message);
  bool mirror = false, glass = false;
  for (const Material& m : s.materials) {
    mirror |= m.kr > 0.0f;
    glass |= m.kt > 0.0f;
  }
  EXPECT_TRUE(mirror);
  EXPECT_TRUE(glass);
  EXPECT_GE(s.directLights().size(), 3u);
  // Every instance owns its mesh, so the count is also what Embree stores.
  EXPECT_EQ(s.meshes.size(), s.instances.size());
}

TEST(HeavyScene, OptionsRemoveEffectsAndKeepTheCount) {
  HeavySceneOptions o;
  o.mirrors = false;
  o.glass = false;
  Scene s = makeHeavyScene(20'000, o);
  EXPECT_EQ(s.triangleCount(), 20'000u);
  for (const Material& m : s.materials) {
    EXPECT_EQ(m.kr, 0.0f);
    EXPECT_EQ(m.kt, 0.0f);
  }
}

TEST(HeavyScene, IsDeterministic) {
  Scene a = makeHeavyScene(30'000), b = makeHeavyScene(30'000);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t i = 0; i < a.meshes.size(); ++i) {
    EXPECT_EQ(a.meshes[i].positions, b.meshes[i].positions);
    EXPECT_EQ(a.meshes[i].indices, b.meshes[i].indices);
  }
}

}  // namespace
}  // namespace tandem
