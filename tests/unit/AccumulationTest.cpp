// Anti-aliasing and progressive accumulation as a unit (render/Accumulation.h), without GL: when a frame goes on
// with the samples so far, starts again or has converged; each sample's camera; sums of partial frames; the
// mean. Worked out here from the rules docs/antialiasing.md states.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/Sampling.h"
#include "render/Accumulation.h"

namespace tandem {
namespace {

using Step = Accumulation::Step;

FrameSettings accumulating(int frames, AntiAlias aa = AntiAlias::Off) {
  FrameSettings s;
  s.width = 4;
  s.height = 3;
  s.accumulate = frames;
  s.aa = aa;
  return s;
}

ImageF flat(int w, int h, glm::vec3 value) {
  ImageF f;
  f.width = w;
  f.height = h;
  f.rgb.assign(std::size_t(w * h), value);
  return f;
}

const Accumulation::Since kStill{true, false, true};  // drawn, nothing changed, probes current

TEST(Accumulation, GoesOnOnlyWhileNothingItShowsChanged) {
  Accumulation a;
  Camera camera;
  const FrameSettings s = accumulating(8);
  EXPECT_EQ(a.step(camera, s, kStill), Step::Restart) << "no samples yet";
  a.restart(camera, s);
  EXPECT_EQ(a.step(camera, s, kStill), Step::GoOn);

  Camera moved = camera;
  moved.posW.x += 1e-3f;
  EXPECT_EQ(a.step(moved, s, kStill), Step::Restart) << "the camera moved";
  FrameSettings other = s;
  other.exposure = 2.0f;
  EXPECT_EQ(a.step(camera, other, kStill), Step::Restart) << "a setting changed";
  other = s;
  other.width = 5;
  EXPECT_EQ(a.step(camera, other, kStill), Step::Restart) << "the size changed";
  EXPECT_EQ(a.step(camera, s, {false, false, true}), Step::Restart) << "the last frame was not drawn";
  EXPECT_EQ(a.step(camera, s, {true, true, true}), Step::Restart) << "the scene changed";
  EXPECT_EQ(a.step(camera, s, {true, false, false}), Step::Restart) << "probes still catching up";
  Accumulation ssaa;
  ssaa.restart(camera, accumulating(1, AntiAlias::Ssaa));
  ssaa.frameDone();
  EXPECT_EQ(ssaa.step(camera, accumulating(1, AntiAlias::Ssaa), kStill), Step::Restart)
      << "anti-aliasing alone starts every frame from nothing";

  // The camera as the application gives it: a sample's jitter is not a move.
  const Camera sample = a.nextSample(camera);
  EXPECT_NE(sample, camera);
  EXPECT_EQ(a.step(camera, s, kStill), Step::GoOn);
}

// The motion view shows each frame's own motion since the frame before: never a mean over frames.
TEST(Accumulation, TheMotionViewStartsAgainEveryFrame) {
  Accumulation a;
  Camera camera;
  FrameSettings s = accumulating(8);
  s.debugView = DebugView::Motion;
  a.restart(camera, s);
  EXPECT_EQ(a.step(camera, s, kStill), Step::Restart);
  s.debugView = DebugView::NormalW;
  a.restart(camera, s);
  EXPECT_EQ(a.step(camera, s, kStill), Step::GoOn) << "other views accumulate as the frame does";
}

TEST(Accumulation, ConvergesAfterItsFramesAndEarlyWhenAdaptiveRoundsAgree) {
  Accumulation a;
  const Camera camera;
  const FrameSettings s = accumulating(3);
  a.restart(camera, s);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(a.step(camera, s, kStill), Step::GoOn) << "frame " << k;
    a.frameDone();
  }
  EXPECT_EQ(a.step(camera, s, kStill), Step::Converged);
  EXPECT_EQ(a.step(camera, s, {true, true, true}), Step::Restart) << "converged, then the scene changed";

  const FrameSettings adaptive = accumulating(16, AntiAlias::Adaptive);
  a.restart(camera, adaptive);
  a.frameDone();
  a.convergedEarly();
  EXPECT_EQ(a.frames(), 16);
  EXPECT_EQ(a.step(camera, adaptive, kStill), Step::Converged);
}

TEST(Accumulation, EachSampleTakesTheNextPointsOfTheSequences) {
  Accumulation a;
  Camera camera;
  camera.aperture = 0.1f;
  camera.shutter = 0.02f;
  a.restart(camera, accumulating(4));
  for (std::uint32_t i = 0; i < 5; ++i) {
    const Camera c = a.nextSample(camera);
    EXPECT_EQ(c.sampleIndex, i);
    EXPECT_EQ(c.jitterPx, subpixelJitter(i));
    EXPECT_EQ(c.lensUv, lensSample(i));
    EXPECT_EQ(c.timeU, timeSample(i));
  }
  // A pinhole camera keeps its lens point and its time: only what the camera has is sampled.
  Camera pinhole;
  Accumulation b;
  b.restart(pinhole, accumulating(4));
  b.nextSample(pinhole);
  const Camera c = b.nextSample(pinhole);
  EXPECT_EQ(c.lensUv, pinhole.lensUv);
  EXPECT_EQ(c.timeU, pinhole.timeU);
  // Starting again starts the sequences again.
  b.restart(pinhole, accumulating(4));
  EXPECT_EQ(b.nextSample(pinhole).jitterPx, subpixelJitter(0));
}

TEST(Accumulation, TheMeanIsEachPixelsOwnSamples) {
  Accumulation a;
  const Camera camera;
  a.restart(camera, accumulating(8));
  EXPECT_EQ(a.mostSamples(), 0);
  a.add(flat(4, 3, glm::vec3(1.0f, 2.0f, 3.0f)), nullptr);
  a.add(flat(4, 3, glm::vec3(3.0f, 2.0f, 1.0f)), nullptr);
  // A partial round: only pixel (1, 1) gets a third sample.
  std::vector<std::uint8_t> only(12, 0);
  only[5] = 1;
  a.add(flat(4, 3, glm::vec3(8.0f)), &only);
  // A frame of another size (a debug view without a linear frame) adds nothing.
  a.add(flat(2, 2, glm::vec3(100.0f)), nullptr);
  EXPECT_EQ(a.mostSamples(), 3);
  const ImageF& m = a.mean();
  ASSERT_EQ(m.width, 4);
  ASSERT_EQ(m.height, 3);
  EXPECT_EQ(m.at(0, 0), glm::vec3(2.0f));
  EXPECT_EQ(m.at(1, 1), glm::vec3(4.0f));  // (1 + 3 + 8) / 3 = 4 in each channel
  EXPECT_EQ(m.at(3, 2), glm::vec3(2.0f));
  // A pixel without samples shows black, not NaN.
  Accumulation b;
  b.restart(camera, accumulating(8));
  b.add(flat(4, 3, glm::vec3(1.0f)), &only);
  EXPECT_EQ(b.mean().at(0, 0), glm::vec3(0.0f));
  EXPECT_EQ(b.mean().at(1, 1), glm::vec3(1.0f));
}

TEST(Accumulation, AdaptiveRoundsFollowTheSamplesThatDisagree) {
  Accumulation a;
  const Camera camera;
  FrameSettings s = accumulating(16, AntiAlias::Adaptive);
  s.width = 9;
  s.height = 9;
  s.aaThreshold = 0.05f;
  s.rayScale = 1;
  a.restart(camera, s);
  std::vector<std::uint8_t> refine, traced;
  ImageF grey = flat(9, 9, glm::vec3(0.2f));
  a.add(grey, nullptr);
  a.add(grey, nullptr);
  EXPECT_FALSE(a.nextRound(refine, traced)) << "every pixel's samples agree";
  // One pixel's second sample is much brighter: it and its 8 neighbours are refined, no other.
  ImageF edge = grey;
  edge.at(4, 4) = glm::vec3(5.0f);
  a.add(edge, nullptr);
  ASSERT_TRUE(a.nextRound(refine, traced));
  int marked = 0;
  for (int y = 0; y < 9; ++y)
    for (int x = 0; x < 9; ++x) {
      const bool want = std::abs(x - 4) <= 1 && std::abs(y - 4) <= 1;
      EXPECT_EQ(refine[std::size_t(y * 9 + x)] != 0, want) << x << "," << y;
      marked += refine[std::size_t(y * 9 + x)];
    }
  EXPECT_EQ(marked, 9);
  EXPECT_EQ(traced, refine) << "full-resolution rays: the traced pixels are the refined ones";
  // Starting again forgets the ranges.
  a.restart(camera, s);
  a.add(grey, nullptr);
  EXPECT_FALSE(a.nextRound(refine, traced));
}

TEST(Accumulation, ARestartSetsUpNoSumsUntilASampleIsAdded) {
  // A game that accumulates at rest restarts every frame while things move and shows its one sample as drawn:
  // the restart must cost nothing, and the sums appear with the first sample added, empty of the last ones.
  Accumulation a;
  a.restart(Camera{}, accumulating(8));
  EXPECT_FALSE(a.holdsSums());
  a.add(flat(4, 3, glm::vec3(5.0f)), nullptr);
  a.add(flat(4, 3, glm::vec3(7.0f)), nullptr);
  a.frameDone();
  EXPECT_TRUE(a.holdsSums());
  Camera moved;
  moved.posW.x += 1.0f;
  FrameSettings bigger = accumulating(8);
  bigger.width = 5;
  a.restart(moved, bigger);
  EXPECT_FALSE(a.holdsSums());
  EXPECT_EQ(a.frames(), 0);
  EXPECT_EQ(a.mostSamples(), 0);
  EXPECT_EQ(a.mean().rgb.size(), 15u);
  EXPECT_EQ(a.mean().at(4, 2), glm::vec3(0.0f));
  std::vector<std::uint8_t> refine, traced;
  EXPECT_FALSE(a.nextRound(refine, traced));  // nothing drawn, nothing to compare
  // The next sample alone is the mean: nothing of the samples before the restart is left in the sums.
  a.add(flat(5, 3, glm::vec3(1.0f)), nullptr);
  EXPECT_TRUE(a.holdsSums());
  EXPECT_EQ(a.mostSamples(), 1);
  EXPECT_EQ(a.mean().at(0, 0), glm::vec3(1.0f));
  EXPECT_EQ(a.mean().at(4, 2), glm::vec3(1.0f));
  // A frame of the old size adds nothing after the restart.
  a.add(flat(4, 3, glm::vec3(9.0f)), nullptr);
  EXPECT_EQ(a.mostSamples(), 1);
}

TEST(Accumulation, SamplesOfOneFrameSeeTheSameProbes) {
  Accumulation a;
  FramePlan plan;
  plan.settings = accumulating(8);
  plan.settings.probesPerFrame = 2;
  a.restart(Camera{}, plan.settings);
  // The first frame's one sample is a plain frame: its probes catch up a few at a time, as without
  // accumulation.
  EXPECT_TRUE(a.singleSample(plan.settings));
  EXPECT_EQ(a.samplePlan(plan).settings.probesPerFrame, 2);
  a.frameDone();
  // Later frames (and any frame of several samples) draw every sample with the probes brought up to date by
  // the first, so no two samples of a mean show different probes (a new scene's first sample included: with
  // a budget it would show the environment in the probes it had not drawn yet).
  EXPECT_FALSE(a.singleSample(plan.settings));
  EXPECT_EQ(a.samplePlan(plan).settings.probesPerFrame, 0);
  Accumulation b;
  FramePlan ssaa = plan;
  ssaa.settings.aa = AntiAlias::Ssaa;
  ssaa.settings.aaSamples = 4;
  b.restart(Camera{}, ssaa.settings);
  EXPECT_FALSE(b.singleSample(ssaa.settings));
  EXPECT_EQ(b.samplePlan(ssaa).settings.probesPerFrame, 0);
  // Only the probes' pace changes: the rest of the plan is the frame's.
  FramePlan caught = b.samplePlan(ssaa);
  caught.settings.probesPerFrame = ssaa.settings.probesPerFrame;
  EXPECT_TRUE(caught.settings == ssaa.settings);
}

TEST(Accumulation, TheFilterRunsOnTheFirstFrameAloneAndTheSamplesGoOnAlongItsSequence) {
  // The spatiotemporal filter (docs/denoise.md): a first frame of one sample is shown filtered; the samples
  // summed after it are drawn as they are, their plan without the filter (the mean converges to the exact
  // image), and they take the sequence on from where the filter's frames had reached.
  Accumulation a;
  FramePlan plan;
  plan.settings = accumulating(8);
  plan.settings.denoise = true;
  plan.denoise = true;
  a.restart(Camera{}, plan.settings, 37);
  EXPECT_TRUE(a.samplePlan(plan).denoise);
  const Camera first = a.nextSample(Camera{});
  EXPECT_EQ(first.sampleIndex, 37u);
  EXPECT_EQ(first.jitterPx, subpixelJitter(37));
  EXPECT_EQ(first, sampleCamera(Camera{}, 37));
  a.frameDone();
  const FramePlan later = a.samplePlan(plan);
  EXPECT_FALSE(later.denoise);
  EXPECT_TRUE(later.settings == plan.settings) << "only the filter is off: the settings are the frame's";
  EXPECT_EQ(a.nextSample(Camera{}).sampleIndex, 38u);
  // Without the filter the sequence starts at 0, as it always did.
  Accumulation b;
  b.restart(Camera{}, accumulating(8));
  EXPECT_EQ(b.nextSample(Camera{}).sampleIndex, 0u);
}

TEST(Accumulation, TheFiltersFirstFrameLosesItsSubPixelOffsetAsTheCameraMovesFaster) {
  // cameraMotionPx: how far the new camera's view moved on the old camera's screen, the most of its target
  // and the points its corners show at the target's distance. A strafe of the eye and the target together by d
  // at distance D moves every such point d / D / tan(fov/2) half-heights: here 0.1 at 10 with a 90-degree fov
  // on a 200-pixel-high frame, 0.01 of the half-height, 1 pixel.
  Camera still;
  still.posW = glm::vec3(0.0f, 0.0f, 10.0f);
  still.targetW = glm::vec3(0.0f);
  still.yFovDeg = 90.0f;
  const glm::ivec2 size(300, 200);
  EXPECT_NEAR(cameraMotionPx(still, still, size), 0.0f, 1e-3f);
  // Far from the origin too (points taken from the old eye: a world-space view matrix rounded them by pixels).
  for (const float far : {1e4f, 1e6f}) {
    Camera away = still;
    away.posW = glm::vec3(far, 0.3f * far, -0.7f * far) + glm::vec3(3.0f, 2.0f, 10.0f);
    away.targetW = glm::vec3(far, 0.3f * far, -0.7f * far) + glm::vec3(-1.0f, 0.5f, 0.0f);
    EXPECT_NEAR(cameraMotionPx(away, away, glm::ivec2(1920, 1080)), 0.0f, 0.01f) << far;
  }
  auto strafed = [&](float d) {
    Camera c = still;
    c.posW.x += d;
    c.targetW.x += d;
    return c;
  };
  EXPECT_NEAR(cameraMotionPx(still, strafed(0.1f), size), 1.0f, 1e-3f);
  EXPECT_NEAR(cameraMotionPx(still, strafed(0.5f), size), 5.0f, 5e-3f);
  // A turn moves the view at any depth, the frame's edge most: 1 degree of yaw to the right takes the direction
  // of the new frame's corner at tangents (t, u) = (1.5, +-1) (a 300x200 frame, 90 degrees high) to (t cos + sin,
  // u) / (cos - t sin) in the old camera's, 100 pixels a unit of tangent (the centre moves tan(1 deg), 1.75).
  Camera turned = still;
  turned.targetW = still.posW + glm::vec3(std::sin(glm::radians(1.0f)), 0.0f, -std::cos(glm::radians(1.0f))) * 10.0f;
  const float cosYaw = std::cos(glm::radians(1.0f)), sinYaw = std::sin(glm::radians(1.0f));
  const glm::vec2 corner(1.5f, 1.0f);
  const glm::vec2 old = glm::vec2(corner.x * cosYaw + sinYaw, corner.y) / (cosYaw - corner.x * sinYaw);
  EXPECT_NEAR(cameraMotionPx(still, turned, size), 100.0f * glm::length(old - corner), 1e-2f);
  // A dolly 2 % of the way to the target moves the centre not at all and the corners' points at the target's
  // distance (tangents (1.5, 1) at 9.8) to (1.47, 0.98) in the old camera, 10 away: 3.6 pixels.
  Camera dolly = still;
  dolly.posW.z = 9.8f;
  EXPECT_NEAR(cameraMotionPx(still, dolly, size), 100.0f * glm::length(glm::vec2(0.03f, 0.02f)), 1e-2f);
  // Behind the old camera: no finite motion.
  Camera behind = still;
  behind.targetW = glm::vec3(0.0f, 0.0f, 20.0f);
  EXPECT_TRUE(std::isinf(cameraMotionPx(still, behind, size)));
  // The scale: whole up to 1.5 pixels a frame, none from 3, linear between.
  EXPECT_EQ(filteredJitterScale(0.0f), 1.0f);
  EXPECT_EQ(filteredJitterScale(1.5f), 1.0f);
  EXPECT_NEAR(filteredJitterScale(2.25f), 0.5f, 1e-6f);
  EXPECT_EQ(filteredJitterScale(3.0f), 0.0f);
  EXPECT_EQ(filteredJitterScale(std::numeric_limits<float>::infinity()), 0.0f);

  // The accumulation's first frame when filtered: its offset scaled by how far the camera moved since the
  // last restart; only the first (the samples summed at rest keep theirs), and only when filtered.
  FrameSettings s = accumulating(8);
  s.width = size.x;
  s.height = size.y;
  s.denoise = true;
  Accumulation a;
  a.restart(still, s, 5, true);  // nothing before it: a whole offset
  EXPECT_EQ(a.nextSample(still).jitterPx, subpixelJitter(5));
  a.frameDone();
  a.restart(strafed(0.5f), s, 6, true);  // 5 pixels: none
  const Camera fast = a.nextSample(strafed(0.5f));
  EXPECT_EQ(fast.jitterPx, glm::vec2(0.0f));
  EXPECT_EQ(fast.sampleIndex, 6u) << "the light samples still go on along the sequence";
  EXPECT_EQ(a.nextSample(strafed(0.5f)).jitterPx, subpixelJitter(7));
  a.restart(strafed(0.5f), s, 8, true);  // the camera held still since: a whole offset
  EXPECT_EQ(a.nextSample(strafed(0.5f)).jitterPx, subpixelJitter(8));
  a.restart(strafed(0.725f), s, 9, true);  // 2.25 pixels: half
  const glm::vec2 half = a.nextSample(strafed(0.725f)).jitterPx, expected = 0.5f * subpixelJitter(9);
  EXPECT_NEAR(half.x, expected.x, 1e-4f);
  EXPECT_NEAR(half.y, expected.y, 1e-4f);
  a.restart(strafed(1.5f), s, 10, false);  // not filtered: a whole offset however far it moved
  EXPECT_EQ(a.nextSample(strafed(1.5f)).jitterPx, subpixelJitter(10));
}

// Frame to frame without accumulation (FilteredSequence): each filtered frame's offset is scaled by how far the
// view moved since the filtered frame just before it, not since the first one: a steady strafe of 2 pixels a
// frame keeps two thirds of every frame's offset however far it has gone, a camera that stops gets whole ones
// back at once, a faster one loses them, and the light samples go on along one sequence throughout.
TEST(Accumulation, TheFiltersOffsetScaleFollowsEachFramesOwnMotion) {
  Camera start;
  start.posW = glm::vec3(0.0f, 0.0f, 10.0f);
  start.targetW = glm::vec3(0.0f);
  start.yFovDeg = 90.0f;
  const glm::ivec2 size(300, 200);  // 10 pixels a unit at the target's distance: 0.1 a pixel
  auto at = [&](float x) {
    Camera c = start;
    c.posW.x += x;
    c.targetW.x += x;
    return c;
  };
  FilteredSequence seq;
  Camera c = seq.next(at(0.0f), size);
  EXPECT_EQ(seq.lastScale(), 1.0f) << "nothing before it: a whole offset";
  EXPECT_EQ(c.jitterPx, subpixelJitter(0));
  float x = 0.0f;
  const float twoThirds = filteredJitterScale(2.0f);
  ASSERT_NEAR(twoThirds, 2.0f / 3.0f, 1e-6f);
  for (std::uint32_t k = 1; k <= 12; ++k) {
    x += 0.2f;  // 2 pixels a frame
    c = seq.next(at(x), size);
    EXPECT_NEAR(seq.lastScale(), twoThirds, 1e-3f) << "frame " << k << ", " << 10.0f * x << " pixels from the start";
    EXPECT_EQ(c.sampleIndex, k);
    EXPECT_NEAR(c.jitterPx.x, seq.lastScale() * subpixelJitter(k).x, 1e-6f);
    EXPECT_NEAR(c.jitterPx.y, seq.lastScale() * subpixelJitter(k).y, 1e-6f);
  }
  c = seq.next(at(x), size);  // stopped
  EXPECT_EQ(seq.lastScale(), 1.0f);
  EXPECT_EQ(c.jitterPx, subpixelJitter(13));
  x += 0.5f;  // 5 pixels
  EXPECT_EQ(seq.next(at(x), size).jitterPx, glm::vec2(0.0f));
  EXPECT_EQ(seq.take(), 15u) << "an accumulation's first frame takes the next index";
  x += 0.1f;  // 1 pixel since the last filtered frame
  c = seq.next(at(x), size);
  EXPECT_EQ(seq.lastScale(), 1.0f);
  EXPECT_EQ(c.sampleIndex, 16u);
}

TEST(Accumulation, ReleaseFreesEverything) {
  Accumulation a;
  a.restart(Camera{}, accumulating(8));
  a.add(flat(4, 3, glm::vec3(1.0f)), nullptr);
  a.firstUnread = true;
  EXPECT_TRUE(a.active());
  a.release();
  EXPECT_FALSE(a.active());
  EXPECT_FALSE(a.firstUnread);
  EXPECT_EQ(a.mostSamples(), 0);
  EXPECT_EQ(a.frames(), 0);
  EXPECT_EQ(a.step(Camera{}, accumulating(8), kStill), Step::Restart);
}

// After a first frame the filter drew, what is shown hands over from it to the mean: the filtered frame is
// not a sample, its weight falls linearly over min(accumulate, 16) - 1 samples, and from then on (the last
// frames of a 16-frame accumulation included) the exact mean is shown.
TEST(Accumulation, AFilteredFirstFrameHandsOverToTheExactMean) {
  for (const int frames : {16, 4, 64}) {
    Accumulation a;
    a.restart(Camera{}, accumulating(frames));
    a.firstShown(true);
    EXPECT_TRUE(a.firstUnread) << "the next frame reads it";
    a.add(flat(4, 3, glm::vec3(1.0f)), nullptr);  // the filtered frame
    EXPECT_EQ(a.mostSamples(), 0) << frames << ": the filtered frame is not a sample";
    const int span = std::min(frames, 16) - 1;
    for (int n = 1; n <= span + 1 && n < frames; ++n) {
      a.add(flat(4, 3, glm::vec3(n % 2 == 0 ? 0.0f : 2.0f)), nullptr);  // samples whose mean is ~1, not exactly
      const float mean = a.mean().rgb[0].r;
      const float w = std::min(1.0f, static_cast<float>(n) / static_cast<float>(span));
      EXPECT_FLOAT_EQ(a.shown().rgb[5].r, (1.0f - w) * 1.0f + w * mean) << frames << " frames, sample " << n;
    }
    EXPECT_EQ(a.shown().rgb[0], a.mean().rgb[0]) << frames << ": handed over";
  }
  // A first frame drawn as it is, the sums take it; nothing is blended.
  Accumulation b;
  b.restart(Camera{}, accumulating(16));
  b.firstShown(false);
  b.add(flat(4, 3, glm::vec3(3.0f)), nullptr);
  b.add(flat(4, 3, glm::vec3(1.0f)), nullptr);
  EXPECT_EQ(b.mostSamples(), 2);
  EXPECT_EQ(b.shown().rgb[0], glm::vec3(2.0f));
}

}  // namespace
}  // namespace tandem
