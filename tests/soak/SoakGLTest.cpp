// Soak (label `long`): 2,000 frames of the Whitted scene with every effect ray traced, in throughput mode (each
// frame's rays traced while the next is rasterized, docs/pipeline.md) with one instance moving every frame, the
// scene reloaded every 100 frames (which drains the pipeline) and one of those reloads failing. After a warm-up, the live GL objects and Embree
// handles must be exactly what they were, Embree's memory within its build-threading spread, and the
// resident set flat.
//
// How it is measured: GL objects by the RAII owners' live count (every GL object has exactly one owner,
// engine/src/gl/GlObjects.h); Embree handles likewise (engine/src/rt/EmbreeScene.h); Embree memory by
// the device's memory monitor callback; RSS from
// /proc/self/statm, sampled at every reload. Frames are small (160×90) so the run takes about a minute.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

#include <vector>

#include "gl/GlTestUtil.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

std::size_t residentBytes() {
  long pages = 0, resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
  std::fclose(f);
  return static_cast<std::size_t>(resident) * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

TEST(Soak, TwoThousandFramesWithReloadsKeepResourcesFlat) {
  TD_REQUIRE_GL_CONTEXT();
  auto created = Renderer::create(*glContext_, RendererDesc{2});
  ASSERT_TRUE(created.ok()) << created.error().message;
  std::unique_ptr<Renderer> renderer = std::move(*created);
  auto scene = loadDefaultScene();
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  const Scene original = *scene;
  ASSERT_TRUE(renderer->setScene(original).ok());

  FrameSettings settings = *presetSettings("hybrid-full");
  settings.width = 160;
  settings.height = 90;
  settings.reuseRays = false;  // the camera stands still: without this only the first frame would trace
  settings.pipelined = true;
  // One instance bobs every frame: the rays in flight trace their copy of the scene while the next frame's
  // instance records go into the GL copy's second slot (made again after each reload).
  const auto bobbing = static_cast<std::uint32_t>(original.instances.size() - 1);
  auto bob = [&](int frame) {
    const glm::vec3 lift(0.0f, frame % 2 == 0 ? 0.05f : 0.0f, 0.0f);
    renderer->setInstanceTransform(bobbing, glm::translate(glm::mat4(1.0f), lift) * original.instances[bobbing].worldFromObject);
  };

  constexpr int kFrames = 2000, kReloadEvery = 100, kWarmupFrames = 300, kFailingReload = 1000;
  std::vector<ResourceStats> resources;
  std::vector<std::size_t> rss;
  int failedLoads = 0;
  for (int frame = 1; frame <= kFrames; ++frame) {
    bob(frame);
    FrameStats stats = renderer->render(original.camera, settings);
    ASSERT_TRUE(stats.pipelined) << "frame " << frame;
    if (!stats.pipelineFilling) {
      ASSERT_GT(stats.rays.shadow, 0u) << "frame " << frame << " showed no shadow rays";
    }
    if (frame % kReloadEvery != 0) continue;
    if (frame == kFailingReload) {
      // A scene that fails validation: the renderer must refuse it and keep the previous one.
      Scene broken = original;
      broken.instances[1].mesh = 999;
      ASSERT_FALSE(renderer->setScene(std::move(broken)).ok());
      ++failedLoads;
    } else {
      ASSERT_TRUE(renderer->setScene(original).ok());
    }
    // Render twice after the reload so the lazily built caches exist: the GL buffers and the Embree scene, and
    // the GL copy's second instance slot (made by the first frame that moves an instance while another is in
    // flight; a new scene drops it, a failed reload keeps it).
    for (int again = 1; again <= 2; ++again) {
      bob(frame + again);
      renderer->render(original.camera, settings);
    }
    if (frame >= kWarmupFrames) {
      resources.push_back(renderer->resources());
      rss.push_back(residentBytes());
    }
  }
  EXPECT_EQ(failedLoads, 1);
  ASSERT_GE(resources.size(), 10u);
  // GL objects and Embree handles (device, one scene per BLAS, the top level): exactly the same count after
  // every reload; a scene or buffer that outlived its reload shows here as one more, whatever its size.
  //
  // Embree's bytes cannot be compared exactly: its parallel BVH builder hands each thread that joins a build
  // its own allocation block, so the total depends on how many threads took part (seen over three runs on
  // 2 threads: 590,548 bytes most of the time, 577,108 and 575,956 now and then, never above). The renderer
  // therefore runs on a fixed 2 threads, whatever the machine, and the spread of all samples must stay under
  // 5 % of the largest: a leaked scene would add about 100 % per reload, and even a leak of 2 KB per reload
  // would pass 5 % over the 17 reloads sampled.
  std::size_t embreeMin = resources[0].embreeBytes, embreeMax = resources[0].embreeBytes;
  for (std::size_t i = 1; i < resources.size(); ++i) {
    EXPECT_EQ(resources[i].glObjects, resources[0].glObjects) << "live GL objects changed at sample " << i;
    EXPECT_EQ(resources[i].embreeHandles, resources[0].embreeHandles) << "live Embree handles changed at sample " << i;
    embreeMin = std::min(embreeMin, resources[i].embreeBytes);
    embreeMax = std::max(embreeMax, resources[i].embreeBytes);
  }
  EXPECT_LE(double(embreeMax - embreeMin), 0.05 * double(embreeMax))
      << "Embree memory spread " << embreeMin << " .. " << embreeMax << " bytes over " << resources.size() << " reloads";
  EXPECT_GT(resources[0].embreeHandles, 2u);
  EXPECT_GT(resources[0].glObjects, 0u);
  EXPECT_GT(resources[0].embreeBytes, 0u);
  // Allocator caches and llvmpipe's shader cache may settle a little; a leak of one frame's or one scene's
  // worth (the Whitted scene's Embree BVH alone is over a megabyte) over 17 reloads would show far above this.
  const double growthMiB = (double(rss.back()) - double(rss.front())) / (1024.0 * 1024.0);
  std::printf("soak: %zu GL objects, %zu Embree handles, %zu..%zu Embree bytes, RSS %.1f MiB -> %.1f MiB\n", resources[0].glObjects,
              resources[0].embreeHandles, embreeMin, embreeMax, double(rss.front()) / 1048576.0, double(rss.back()) / 1048576.0);
  EXPECT_LT(growthMiB, 4.0) << "resident set grew after warm-up";
}

}  // namespace
}  // namespace tandem
