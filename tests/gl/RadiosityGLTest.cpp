// Radiosity in the frame (FrameSettings::radiosity; docs/radiosity.md): every preset shows the solution in
// place of the ambient term and agrees with the path-traced ground truth; the raster's pixels and the rays'
// hits read the same solution; a mirror shows the radiosity-lit room; the background solve converges to
// the solution a frame solves for itself, and follows a moving light.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "gl/GlTestUtil.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Primitives.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

using namespace tandem::gltest;

constexpr int kSize = 128;

Result<Scene> cornellBox() { return loadSceneFile(test::sourceDir() + "/assets/scenes/cornell-box.json"); }

FrameSettings withRadiosity(FrameSettings s) {
  s.radiosity = true;
  s.radiosityPatches = 512;
  s.radiosityError = 0.01f;
  return s;
}

// Mean display value of a block of pixels (row 0 at the top).
glm::dvec3 blockMean(const Image& image, int x0, int y0, int x1, int y1) {
  glm::dvec3 sum(0.0);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const std::size_t i = 4 * (static_cast<std::size_t>(y) * image.width + x);
      sum += glm::dvec3(image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]);
    }
  return sum / static_cast<double>((x1 - x0) * (y1 - y0));
}

TEST(RadiosityGL, EveryPresetShowsTheSolutionAndMeetsThePathTracedTruth) {
  TD_REQUIRE_GL_CONTEXT();
  GlContext* context = glContext_;
  SceneFrame f = sceneFrame(*context, cornellBox(), kSize, kSize);
  ASSERT_TRUE(f.renderer);
  FrameSettings truth = presetFor(f, "reference");
  truth.gi = GlobalIllumination::Path;
  truth.referenceSpp = 8;
  const Image path = drawFrame(f, truth);
  savePng("radiosity-truth.png", path);
  for (const char* name : {"raster", "hybrid-fast", "hybrid-full", "reference"}) {
    const FrameSettings ambient = presetFor(f, name);
    const Image without = drawFrame(f, ambient);
    FrameStats stats;
    const Image with = drawFrame(f, withRadiosity(ambient), &stats);
    savePng(std::string("radiosity-") + name + ".png", with);
    EXPECT_TRUE(stats.radiosity.active) << name;
    EXPECT_TRUE(stats.radiosity.converged) << name;
    EXPECT_LE(stats.radiosity.residual, 0.01f) << name;
    const double flipWith = flipMean(with, path), flipWithout = flipMean(without, path);
    std::printf("%-12s FLIP against the path-traced truth: %.4f with radiosity, %.4f with the ambient term\n", name,
                flipWith, flipWithout);
    EXPECT_LT(flipWith, 0.5 * flipWithout) << name;
    // The ceiling, which no light reaches directly, is lit by the room; its left end is redder than its
    // right (the red wall's light), its right end greener.
    const glm::dvec3 ceilingLeft = blockMean(with, 20, 4, 44, 9), ceilingRight = blockMean(with, 84, 4, 108, 9);
    const glm::dvec3 truthLeft = blockMean(path, 20, 4, 44, 9);
    EXPECT_GT(ceilingLeft.x, 0.8 * truthLeft.x) << name;
    EXPECT_LT(ceilingLeft.x, 1.2 * truthLeft.x) << name;
    EXPECT_GT(ceilingLeft.x / ceilingLeft.y, 1.05 * ceilingRight.x / ceilingRight.y) << name;
  }
}

TEST(RadiosityGL, TheRasterAndTheRaysReadOneSolution) {
  TD_REQUIRE_GL_CONTEXT();
  GlContext* context = glContext_;
  SceneFrame f = sceneFrame(*context, cornellBox(), kSize, kSize);
  ASSERT_TRUE(f.renderer);
  // Shadows off: the raster's shade pass and the reference's CPU shading then differ only by rounding, so
  // the radiosity term each adds (GLSL and C++ from one source) must agree too.
  FrameSettings raster = withRadiosity(presetFor(f, "raster"));
  FrameSettings reference = withRadiosity(presetFor(f, "reference"));
  raster.shadows = reference.shadows = EffectMode::Off;
  const Image gl = drawFrame(f, raster);
  const Image cpu = drawFrame(f, reference);
  std::size_t over = 0;
  for (std::size_t i = 0; i < gl.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(int(gl.rgba[i + c]) - int(cpu.rgba[i + c])) > 2) {
        ++over;
        break;
      }
  const double fraction = double(over) / double(gl.rgba.size() / 4), flip = flipMean(gl, cpu);
  std::printf("raster vs reference with radiosity: %.5f of pixels over 2/255, FLIP %.5f\n", fraction, flip);
  EXPECT_LT(fraction, 0.02);
  EXPECT_LT(flip, 0.01);
}

TEST(RadiosityGL, AMirrorShowsTheRoomTheSolutionLit) {
  TD_REQUIRE_GL_CONTEXT();
  GlContext* context = glContext_;
  auto scene = cornellBox();
  ASSERT_TRUE(scene.ok());
  // A mirror ball on the floor in front of the tall box: its top reflects the ceiling, which only
  // interreflection lights (the rect light has no geometry for the mirror to show).
  Material mirror;
  mirror.kd = glm::vec3(0.0f);
  mirror.ka = glm::vec3(0.0f);
  mirror.ks = glm::vec3(0.0f);
  mirror.kr = 0.95f;
  scene->materials.push_back(mirror);
  scene->meshes.push_back(makeSphere(0.5f, 48, 24));
  Instance ball;
  ball.name = "mirror ball";
  ball.mesh = static_cast<std::uint32_t>(scene->meshes.size() - 1);
  ball.material = static_cast<std::uint32_t>(scene->materials.size() - 1);
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(3.6f, 0.5f, 0.9f));
  scene->instances.push_back(ball);
  SceneFrame f = sceneFrame(*context, std::move(scene), kSize, kSize);
  ASSERT_TRUE(f.renderer);
  for (const char* name : {"hybrid-full", "raster"}) {
    FrameSettings s = presetFor(f, name);
    s.radiosityPatches = 512;
    Image without = drawFrame(f, s);
    Image with = drawFrame(f, withRadiosity(s));
    savePng(std::string("radiosity-mirror-") + name + ".png", with);
    // The ball's top, where it mirrors the ceiling (the ball is about 20 pixels across, centred at (47, 109)).
    const glm::dvec3 top = blockMean(with, 45, 100, 50, 103), topWithout = blockMean(without, 45, 100, 50, 103);
    std::printf("%s: the mirror's top %.1f with radiosity, %.1f with the ambient term\n", name, top.x, topWithout.x);
    EXPECT_GT(top.x, topWithout.x + 10.0) << name;
  }
}

// The Cornell box with a white ball on its floor at `x`, static (in the solution) or dynamic (drawn, not solved).
Result<Scene> boxWithBall(float x, bool dynamic) {
  auto scene = cornellBox();
  if (!scene.ok()) return scene;
  scene->meshes.push_back(makeSphere(0.6f, 32, 16));
  Instance ball;
  ball.name = "ball";
  ball.mesh = static_cast<std::uint32_t>(scene->meshes.size() - 1);
  ball.material = 0;
  ball.dynamic = dynamic;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.6f, 1.2f));
  scene->instances.push_back(ball);
  return scene;
}

TEST(RadiosityGL, AStaticInstanceMovedIsSolvedAgainADynamicOneIsNot) {
  TD_REQUIRE_GL_CONTEXT();
  GlContext* context = glContext_;
  const float from = 1.4f, to = 3.8f;
  for (bool dynamic : {false, true}) {
    SceneFrame moved = sceneFrame(*context, boxWithBall(from, dynamic), kSize, kSize);
    SceneFrame placed = sceneFrame(*context, boxWithBall(to, dynamic), kSize, kSize);
    ASSERT_TRUE(moved.renderer && placed.renderer);
    const FrameSettings s = withRadiosity(presetFor(moved, "raster"));
    FrameStats solvedBefore, solvedAfter;
    const Image before = drawFrame(moved, s, &solvedBefore);
    const std::uint32_t ball = static_cast<std::uint32_t>(moved.renderer->scene().instances.size() - 1);
    moved.renderer->setInstanceTransform(ball, glm::translate(glm::mat4(1.0f), glm::vec3(to, 0.6f, 1.2f)));
    const Image after = drawFrame(moved, s, &solvedAfter);
    const Image fresh = drawFrame(placed, s);
    savePng(std::string("radiosity-ball-moved-") + (dynamic ? "dynamic" : "static") + ".png", after);
    const double flip = flipMean(after, fresh), stale = flipMean(before, fresh);
    std::printf("%s ball moved: FLIP %.5f against the ball solved in place (before the move: %.5f)\n",
                dynamic ? "dynamic" : "static", flip, stale);
    if (!dynamic) {
      // A static instance is part of the solution: moved, it is solved again, as if it had been there.
      EXPECT_TRUE(sameImage(after, fresh)) << "FLIP " << flip;
    } else {
      // A dynamic one is not: the solution is the one solved before the move (its solve time to the bit, not a
      // new solve's), and, leaving the ball out as a fresh one does, it agrees; the ball is drawn where it is.
      EXPECT_EQ(solvedAfter.radiosity.solveMs, solvedBefore.radiosity.solveMs);
      EXPECT_EQ(solvedAfter.radiosity.shots, solvedBefore.radiosity.shots);
      EXPECT_TRUE(sameImage(after, fresh)) << "FLIP " << flip;
    }
    EXPECT_GT(stale, 10.0 * flip);
  }
}

// Two renderers of the Cornell box: one solves before its frames, the other (a game's way) in the background.
struct SolvedAndGame {
  SceneFrame solved, game;
};
SolvedAndGame solvedAndGame(GlContext& context) {
  return {sceneFrame(context, cornellBox(), kSize, kSize), sceneFrame(context, cornellBox(), kSize, kSize)};
}

TEST(RadiosityGL, TheBackgroundSolveConvergesToTheFramesOwnAndFollowsAMovingLight) {
  TD_REQUIRE_GL_CONTEXT();
  auto [solved, game] = solvedAndGame(*glContext_);
  ASSERT_TRUE(solved.renderer && game.renderer);
  FrameSettings s = withRadiosity(presetFor(solved, "hybrid-full"));
  s.radiosityError = 0.002f;  // two solutions 1 % short of converged can differ by FLIP 0.02: compare closer ones
  const Image expected = drawFrame(solved, s);
  FrameSettings background = s;
  background.radiosityBackground = true;
  FrameStats stats;
  Image shown = drawFrame(game, background, &stats);
  const auto start = std::chrono::steady_clock::now();
  int frames = 1;
  std::uint64_t lastShots = 0;
  bool monotone = true;
  while (!stats.radiosity.converged && std::chrono::steady_clock::now() - start < std::chrono::seconds(120)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    shown = drawFrame(game, background, &stats);
    ++frames;
    if (stats.radiosity.shots < lastShots) monotone = false;
    lastShots = stats.radiosity.shots;
  }
  std::printf("background solve: converged after %d frames, %llu shots, %.0f ms\n", frames,
              static_cast<unsigned long long>(stats.radiosity.shots), stats.radiosity.solveMs);
  ASSERT_TRUE(stats.radiosity.converged);
  EXPECT_TRUE(monotone);
  EXPECT_TRUE(sameImage(shown, expected));

  // Moving the light: the running solve takes the new light and carries its solution over (negative unshot
  // light where patches lost some, the form factors kept); it converges to what a fresh solve for the moved
  // light gives, to within what is left unshot.
  Light light = game.renderer->scene().lights[1];
  light.posW.x -= 1.0f;
  game.renderer->setLight(1, light);
  drawFrame(game, background, &stats);
  EXPECT_FALSE(stats.radiosity.converged);
  while (!stats.radiosity.converged && std::chrono::steady_clock::now() - start < std::chrono::seconds(240)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    shown = drawFrame(game, background, &stats);
  }
  ASSERT_TRUE(stats.radiosity.converged);
  solved.renderer->setLight(1, light);
  const Image fresh = drawFrame(solved, s);
  const double flip = flipMean(shown, fresh), moved = flipMean(expected, fresh);
  std::printf("after the light moved: FLIP %.5f against a fresh solve (the old light's frame: %.5f)\n", flip, moved);
  EXPECT_LT(flip, 0.01);
  EXPECT_LT(flip, 0.25 * moved);
}

TEST(RadiosityGL, RefinementRefinesWhatTheFrameShowsInTheBackgroundToo) {
  TD_REQUIRE_GL_CONTEXT();
  auto [solved, game] = solvedAndGame(*glContext_);
  ASSERT_TRUE(solved.renderer && game.renderer);
  FrameSettings s = withRadiosity(presetFor(solved, "hybrid-full"));
  FrameStats coarseStats, refinedStats;
  const Image coarse = drawFrame(solved, s, &coarseStats);
  s.radiosityRefine = true;
  const Image refined = drawFrame(solved, s, &refinedStats);
  std::printf("refined: %d patch sides (coarse %d), %llu shots\n", refinedStats.radiosity.patches,
              coarseStats.radiosity.patches, static_cast<unsigned long long>(refinedStats.radiosity.shots));
  EXPECT_GT(refinedStats.radiosity.patches, coarseStats.radiosity.patches);
  EXPECT_LE(refinedStats.radiosity.patches, 2 * coarseStats.radiosity.patches);
  EXPECT_FALSE(sameImage(coarse, refined));
  // In the background: the coarse solution first, then the refined one, the same as the frame's own.
  FrameSettings background = s;
  background.radiosityBackground = true;
  FrameStats stats;
  Image shown = drawFrame(game, background, &stats);
  bool sawCoarse = false;
  const auto start = std::chrono::steady_clock::now();
  while (!stats.radiosity.converged && std::chrono::steady_clock::now() - start < std::chrono::seconds(120)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    shown = drawFrame(game, background, &stats);
    if (stats.radiosity.active && stats.radiosity.patches == coarseStats.radiosity.patches) sawCoarse = true;
  }
  ASSERT_TRUE(stats.radiosity.converged);
  EXPECT_EQ(stats.radiosity.patches, refinedStats.radiosity.patches);
  EXPECT_TRUE(sawCoarse);
  EXPECT_TRUE(sameImage(shown, refined));
}

}  // namespace
}  // namespace tandem
