// Motion blur's transforms and samples (core/Motion.h, core/Sampling.h timeSample; docs/motion-blur.md): the
// rigid motion is exact in double and worldFromObject at the middle of the shutter; its time steps are
// the motion itself, a step at u = 0.5, finely enough spaced that the linear blend between them stays on the
// arc; shutter times are stratified in every prefix and unrelated to the other sample dimensions.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "core/Motion.h"
#include "core/RenderSpace.h"
#include "core/Sampling.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem {
namespace {

Instance moving(glm::vec3 at, float scale, glm::vec3 velocity, glm::vec3 angularVelocity) {
  Instance inst;
  inst.worldFromObject = glm::scale(glm::translate(glm::mat4(1.0f), at), glm::vec3(scale));
  inst.velocity = velocity;
  inst.angularVelocity = angularVelocity;
  return inst;
}

TEST(Motion, AtRestOrWithTheShutterClosedNothingMoves) {
  Instance still = moving(glm::vec3(1.0f), 1.0f, glm::vec3(0.0f), glm::vec3(0.0f));
  EXPECT_FALSE(isMoving(still, 0.1f));
  EXPECT_TRUE(motionSteps(still, 0.1f, glm::vec3(0.0f)).empty());
  Instance fast = moving(glm::vec3(1.0f), 1.0f, glm::vec3(3.0f, 0.0f, 0.0f), glm::vec3(0.0f));
  EXPECT_FALSE(isMoving(fast, 0.0f));
  EXPECT_FALSE(isMoving(fast, std::nanf("")));
  EXPECT_TRUE(motionSteps(fast, 0.0f, glm::vec3(0.0f)).empty());
  EXPECT_EQ(glm::mat4(rigidMotionAt(fast, 0.0f, 0.9)), fast.worldFromObject);
}

TEST(Motion, TheRigidMotionIsExactAndCentredOnTheTransform) {
  const Instance inst = moving(glm::vec3(2.0f, 1.0f, -3.0f), 0.5f, glm::vec3(-3.0f, 0.5f, 0.0f), glm::vec3(0.0f, 0.0f, 8.0f));
  const float shutter = 0.1f;
  EXPECT_EQ(glm::mat4(rigidMotionAt(inst, shutter, 0.5)), inst.worldFromObject);
  for (double u : {0.0, 0.25, 0.8, 1.0}) {
    const double tau = (u - 0.5) * shutter;
    const glm::dmat4 m = rigidMotionAt(inst, shutter, u);
    // The origin (the pivot) moves with the velocity alone.
    const glm::dvec3 origin(m[3]);
    const glm::dvec3 expected = glm::dvec3(2.0, 1.0, -3.0) + glm::dvec3(-3.0, 0.5, 0.0) * tau;
    EXPECT_NEAR(glm::length(origin - expected), 0.0, 1e-7);
    // A point of the object turns about the pivot by ω·τ, keeping its distance.
    const glm::dvec3 p(m * glm::dvec4(1.0, 0.0, 0.0, 1.0));
    const glm::dvec3 r = p - origin;
    EXPECT_NEAR(glm::length(r), 0.5, 1e-7);
    EXPECT_NEAR(std::atan2(r.y, r.x), 8.0 * tau, 1e-7) << u;
  }
}

TEST(Motion, StepsFollowTheArcAtEveryScale) {
  // Linear blends of the steps stay within 1.6e-4 of the radius of the exact motion: at scales 1e-4 to 1e4
  // and 1e5 from the origin (render space around a nearby anchor, as the frame uses it).
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    for (glm::vec3 origin : {glm::vec3(0.0f), glm::vec3(1e5f, -2e4f, 1e5f)}) {
      if (origin != glm::vec3(0.0f) && scale < 1.0f) continue;  // below float's grain there
      const glm::vec3 anchor = origin + scale * glm::vec3(0.0f, 1.0f, 6.0f);
      for (float spin : {0.0f, 1.0f, 40.0f, 1000.0f}) {  // radians per second
        const Instance inst = moving(origin + scale * glm::vec3(0.5f, 0.3f, 0.0f), scale * 0.35f,
                                     scale * glm::vec3(-3.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.6f, 0.8f) * spin);
        const float shutter = 0.1f;
        const std::vector<glm::mat4> steps = motionSteps(inst, shutter, anchor);
        ASSERT_GE(steps.size(), 3u);
        ASSERT_LE(steps.size(), static_cast<std::size_t>(kMaxMotionSteps));
        EXPECT_EQ(steps.size() % 2, 1u) << "an even number of segments";
        // The middle step is the transform itself, exactly as render space holds a still instance.
        EXPECT_EQ(steps[steps.size() / 2], toRenderSpace(inst.worldFromObject, anchor));
        EXPECT_EQ(motionAt(steps, 0.5f), steps[steps.size() / 2]);
        const double segments = static_cast<double>(steps.size() - 1);
        if (spin * shutter / segments > 2.0 * 3.14159265 / 180.0 * 1.0001 && steps.size() < kMaxMotionSteps)
          ADD_FAILURE() << "a segment turns by more than 2 degrees";
        // Past kMaxMotionSteps (a turn of more than 256 degrees in one shutter) the segments grow, and so does
        // the blend's shortcut across the arc: radius·(1 − cos(θ/2)) for a segment of θ.
        const double theta = static_cast<double>(spin) * shutter / segments;
        const double bound = std::max(1.6e-4, 1.0 - std::cos(theta / 2.0) + 1e-6);
        if (steps.size() < static_cast<std::size_t>(kMaxMotionSteps)) {
          EXPECT_LT(bound, 1.6e-4 + 1e-6);
        }
        for (int k = 0; k <= 64; ++k) {
          const float u = std::min(1.0f, (static_cast<float>(k) + 0.37f) / 64.0f);  // between steps too
          const glm::mat4 blended = motionAt(steps, u);
          glm::dmat4 exact = rigidMotionAt(inst, shutter, u);
          exact[3] -= glm::dvec4(glm::dvec3(anchor), 0.0);
          for (glm::vec3 corner : {glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f, -1.0f, 0.0f), glm::vec3(0.6f, 0.0f, 0.8f)}) {
            const glm::dvec3 a(blended * glm::vec4(corner, 1.0f));
            const glm::dvec3 b(exact * glm::dvec4(corner, 1.0));
            const double radius = 0.35 * scale;
            const double grain = origin == glm::vec3(0.0f) ? 1e-6 * scale : 1e-2;  // float far from the origin
            EXPECT_LT(glm::length(a - b), bound * radius + grain)
                << "scale " << scale << " spin " << spin << " u " << u;
            ASSERT_TRUE(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z));
          }
        }
      }
    }
  }
}

TEST(Motion, AnyFiniteSpinGivesFiniteSteps) {
  // |ω|·shutter far beyond int's range: the step count is clamped before it becomes an int.
  const Instance inst = moving(glm::vec3(1.0f, 2.0f, 3.0f), 1.0f, glm::vec3(0.0f), glm::vec3(0.0f, 3e38f, 0.0f));
  const std::vector<glm::mat4> steps = motionSteps(inst, 1e3f, glm::vec3(0.0f));
  ASSERT_EQ(steps.size(), static_cast<std::size_t>(kMaxMotionSteps));
  for (const glm::mat4& m : steps)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) ASSERT_TRUE(std::isfinite(m[c][r]));
}

TEST(Motion, TimesOutsideTheShutterAreClamped) {
  const Instance inst = moving(glm::vec3(0.0f), 1.0f, glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(0.0f));
  const std::vector<glm::mat4> steps = motionSteps(inst, 1.0f, glm::vec3(0.0f));
  EXPECT_EQ(motionAt(steps, -3.0f), steps.front());
  EXPECT_EQ(motionAt(steps, 7.0f), steps.back());
  EXPECT_EQ(motionAt(steps, std::nanf("")), motionAt(steps, 0.5f));
  EXPECT_NEAR(motionAt(steps, 1.0f)[3].x, 0.5f, 1e-7f);
  EXPECT_NEAR(motionAt(steps, 0.0f)[3].x, -0.5f, 1e-7f);
}

TEST(TimeSample, EveryPrefixCoversTheShutterOnceInEachStratum) {
  for (int k = 0; k <= 10; ++k) {
    const std::uint32_t n = 1u << k;
    std::set<std::uint32_t> strata;
    for (std::uint32_t i = 0; i < n; ++i) {
      const float t = timeSample(i);
      ASSERT_GE(t, 0.0f);
      ASSERT_LT(t, 1.0f);
      strata.insert(static_cast<std::uint32_t>(t * static_cast<float>(n)));
    }
    EXPECT_EQ(strata.size(), n) << n << " samples";
  }
  // Unrelated to the sub-pixel offset and the lens point of the same sample: every pairing of halves occurs.
  std::set<int> pairs;
  for (std::uint32_t i = 0; i < 64; ++i) {
    const glm::vec2 j = subpixelJitter(i) + 0.5f, l = lensSample(i);
    pairs.insert(int(timeSample(i) * 2) * 16 + int(j.x * 2) * 8 + int(j.y * 2) * 4 + int(l.x * 2) * 2 + int(l.y * 2));
  }
  EXPECT_GE(pairs.size(), 28u) << "of 32 pairings";
}

TEST(Motion, SceneValidationRefusesABadMotionOrShutter) {
  Scene s;
  s.meshes.push_back({});
  s.materials.push_back({});
  s.instances.push_back({});
  EXPECT_TRUE(validateScene(s).ok());
  s.instances[0].velocity = glm::vec3(std::nanf(""), 0.0f, 0.0f);
  EXPECT_FALSE(validateScene(s).ok());
  s.instances[0].velocity = glm::vec3(1.0f);
  s.instances[0].angularVelocity = glm::vec3(0.0f, std::numeric_limits<float>::infinity(), 0.0f);
  EXPECT_FALSE(validateScene(s).ok());
  s.instances[0].angularVelocity = glm::vec3(0.0f);
  s.camera.shutter = -0.01f;
  EXPECT_FALSE(validateScene(s).ok());
  s.camera.shutter = 0.02f;
  EXPECT_TRUE(validateScene(s).ok());
}

}  // namespace
}  // namespace tandem
