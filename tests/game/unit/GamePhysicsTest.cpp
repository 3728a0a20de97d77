// The game's physics against answers worked out by hand (no tolerance for "about right"): a bounce keeps
// −restitution of the normal speed and all of the tangential, rolling resistance decays speed as exp(−d·t) and
// braking adds its own rate, the discrete integrator puts the marble where its closed form says so a gem is
// picked up on a known step, and the clock counts down by the steps taken and stops at a win.
#include <cmath>

#include <gtest/gtest.h>

#include "Game.h"
#include "Level.h"

using namespace marble;

namespace {

constexpr float kDt = 1.0f / 60.0f;

// The bare room of the hall (its four walls, inner faces at ±halfSize), one gem far overhead.
Level room() {
  Level l = makeHallOfMirrors();
  l.obstacles.resize(4);
  l.spinners.clear();
  l.gems = {{{0.0f, 0.0f}, glm::vec3(1.0f)}};
  l.gemHeight = 50.0f;
  l.startXZ = {0.0f, 0.0f};
  return l;
}

// No rolling resistance, no speed cap in reach, one substep: the integrator is v += a·h, x += v·h.
Tuning frictionless() {
  Tuning t;
  t.rollDamping = 0.0f;
  t.brakeDamping = 0.0f;
  t.maxSpeed = 1000.0f;
  t.substeps = 1;
  return t;
}

MoveIntent push(float x, float y) {
  MoveIntent m;
  m.move = {x, y};
  return m;
}

}  // namespace

TEST(GamePhysics, ABounceKeepsRestitutionOfTheNormalSpeedAndAllTheTangential) {
  const Tuning t = frictionless();
  Game g(room(), t);
  // Camera yaw 0: "right" is +x, "forward" −z. Build up (vx, vz) = (a·T, −a·T/2) in 0.5 s, then coast.
  for (int i = 0; i < 30; ++i) g.step(kDt, push(1.0f, 0.5f), 0.0f);
  const glm::vec2 before = g.marbleVelXZ();
  ASSERT_NEAR(before.x, t.accel * 0.5f / std::sqrt(1.25f), 1e-3f) << "the push is normalised";
  ASSERT_EQ(g.bounces(), 0);
  // Coast to the +x wall (inner face at halfSize.x; the marble's centre stops a radius short of it).
  int steps = 0;
  while (g.bounces() == 0 && steps < 600) {
    g.step(kDt, {}, 0.0f);
    ++steps;
  }
  ASSERT_EQ(g.bounces(), 1);
  const glm::vec2 after = g.marbleVelXZ();
  EXPECT_NEAR(after.x, -t.restitution * before.x, 1e-5f);
  EXPECT_FLOAT_EQ(after.y, before.y) << "the wall is frictionless along itself";
  EXPECT_LE(g.marblePos().x, g.level().halfSize.x - g.level().marbleRadius + 1e-5f);
  // Without rolling resistance the speed stays what the bounce left until the next wall.
  for (int i = 0; i < 10; ++i) g.step(kDt, {}, 0.0f);
  EXPECT_NEAR(g.marbleVelXZ().x, after.x, 1e-5f);
}

TEST(GamePhysics, RollingResistanceAndBrakingDecayExponentially) {
  Tuning t;
  t.maxSpeed = 1000.0f;
  Game g(room(), t);
  for (int i = 0; i < 12; ++i) g.step(kDt, push(1.0f, 0.0f), 0.0f);
  const float v0 = g.marbleVelXZ().x;
  // Coasting 0.5 s: v0·exp(−d·0.5), whatever the substeps (each multiplies by exp(−d·h)).
  for (int i = 0; i < 30; ++i) g.step(kDt, {}, 0.0f);
  const float coasted = g.marbleVelXZ().x;
  EXPECT_NEAR(coasted, v0 * std::exp(-t.rollDamping * 0.5f), 1e-4f * v0);
  // Braking 0.25 s adds the brake's rate: exp(−(d + b)·0.25).
  MoveIntent brake;
  brake.brake = true;
  for (int i = 0; i < 15; ++i) g.step(kDt, brake, 0.0f);
  EXPECT_NEAR(g.marbleVelXZ().x, coasted * std::exp(-(t.rollDamping + t.brakeDamping) * 0.25f), 1e-4f * v0);
}

TEST(GamePhysics, AGemIsPickedUpOnTheStepTheClosedFormPredicts) {
  // From rest under a constant push with one substep, after n steps x_n = a·h²·n(n + 1)/2 (v_k = a·h·k,
  // x_n = h·Σ v_k). The gem 3 units along +x is reached when the centres are nearer than the two radii.
  Level l = room();
  l.gems = {{{3.0f, 0.0f}, glm::vec3(1.0f)}, {{-8.0f, -8.0f}, glm::vec3(1.0f)}};
  l.gemHeight = l.marbleRadius;  // on the marble's plane: the reach is along x only
  const Tuning t = frictionless();
  Game g(l, t);
  const double reach = l.marbleRadius + l.gemRadius;
  int expected = 0;
  for (int n = 1; n < 1000; ++n) {
    const double x = t.accel * double(kDt) * kDt * n * (n + 1) / 2.0;
    if (3.0 - x < reach) {
      expected = n;
      break;
    }
  }
  ASSERT_GT(expected, 5);
  for (int n = 1; n <= expected; ++n) {
    g.step(kDt, push(1.0f, 0.0f), 0.0f);
    EXPECT_EQ(g.gemCollected(0), n == expected) << "step " << n;
    EXPECT_EQ(g.score(), n == expected ? 1 : 0) << "step " << n;
  }
  EXPECT_FALSE(g.gemCollected(1));
  EXPECT_EQ(g.outcome(), Outcome::Playing) << "one gem is left";
  EXPECT_DOUBLE_EQ(g.lastPickupTime(), g.time());
}

TEST(GamePhysics, TheClockCountsTheStepsAndStopsAtAWin) {
  Level l = room();
  l.gems = {{{1.0f, 0.0f}, glm::vec3(1.0f)}};
  l.gemHeight = l.marbleRadius;
  l.timeLimit = 10.0f;
  Game g(l, frictionless());
  for (int n = 1; n <= 7; ++n) {
    g.step(kDt, {}, 0.0f);
    EXPECT_NEAR(g.timeLeft(), 10.0 - n * double(kDt), 1e-9) << "step " << n;
  }
  // Push to the gem: the game is won on that step and the clock stops there, however long it runs on.
  int steps = 0;
  while (g.outcome() == Outcome::Playing && steps < 600) {
    g.step(kDt, push(1.0f, 0.0f), 0.0f);
    ++steps;
  }
  ASSERT_EQ(g.outcome(), Outcome::Won);
  const double left = 10.0 - (7 + steps) * double(kDt);
  EXPECT_NEAR(g.timeLeft(), left, 1e-9);
  for (int i = 0; i < 100; ++i) g.step(kDt, {}, 0.0f);
  EXPECT_NEAR(g.timeLeft(), left, 1e-9);
  EXPECT_NEAR(g.time(), (107 + steps) * double(kDt), 1e-9) << "the simulation itself goes on";
}
