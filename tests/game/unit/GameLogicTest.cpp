// The game's rules and physics without any GL: collision, pickup, timer, determinism, camera.
#include <cmath>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "Game.h"
#include "Level.h"

using namespace marble;

namespace {

constexpr float kDt = 1.0f / 60.0f;

// A bare square room, for tests that want one effect at a time. Its one gem floats out of reach (a
// level with no gems left is already won).
Level emptyRoom() {
  Level l = makeHallOfMirrors();
  l.obstacles.resize(4);  // keep only the walls
  l.spinners.clear();
  l.gems = {{{0.0f, 0.0f}, glm::vec3(1.0f)}};
  l.gemHeight = 50.0f;
  l.startXZ = {0.0f, 0.0f};
  return l;
}

MoveIntent forward() {
  MoveIntent m;
  m.move = {0.0f, 1.0f};
  return m;
}

}  // namespace

TEST(Geometry, RotateXZMatchesGlmRotateAboutY) {
  for (float yaw : {0.3f, -1.2f, 2.5f}) {
    const glm::vec4 g = glm::rotate(glm::mat4(1.0f), yaw, glm::vec3(0, 1, 0)) * glm::vec4(0.7f, 0.0f, -1.9f, 1.0f);
    const glm::vec2 r = rotateXZ({0.7f, -1.9f}, yaw);
    EXPECT_NEAR(r.x, g.x, 1e-5f);
    EXPECT_NEAR(r.y, g.z, 1e-5f);
  }
}

TEST(Geometry, CircleBoxContact) {
  Obstacle box{"b", {0.0f, 0.0f}, {1.0f, 0.5f}, 1.0f, 0.0f, Surface::Stone};
  EXPECT_FALSE(circleBoxContact({1.5f, 0.0f}, 0.4f, box).has_value());
  auto c = circleBoxContact({1.3f, 0.0f}, 0.4f, box);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->normal.x, 1.0f, 1e-6f);
  EXPECT_NEAR(c->normal.y, 0.0f, 1e-6f);
  EXPECT_NEAR(c->depth, 0.1f, 1e-5f);
  EXPECT_NEAR(c->pointXZ.x, 1.0f, 1e-6f);

  // Centre inside: leave through the nearest face (here +z, 0.1 away, not +x, 0.6 away).
  c = circleBoxContact({0.4f, 0.4f}, 0.4f, box);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->normal.y, 1.0f, 1e-6f);
  EXPECT_NEAR(c->depth, 0.5f, 1e-5f);

  // Rotated a quarter turn the long side lies along z: a point 0.8 along +z is now inside its reach.
  box.yaw = glm::half_pi<float>();
  c = circleBoxContact({0.0f, 1.3f}, 0.4f, box);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(std::abs(c->normal.y), 1.0f, 1e-5f);
  EXPECT_NEAR(c->depth, 0.1f, 1e-4f);
  EXPECT_FALSE(circleBoxContact({1.3f, 0.0f}, 0.4f, box).has_value());
}

TEST(Game, StartsAtRestAndStaysWithoutInput) {
  Game g(emptyRoom());
  for (int i = 0; i < 120; ++i) g.step(kDt, {}, 0.0f);
  EXPECT_FLOAT_EQ(g.marblePos().x, 0.0f);
  EXPECT_FLOAT_EQ(g.marblePos().z, 0.0f);
  EXPECT_FLOAT_EQ(g.marblePos().y, g.level().marbleRadius);
  EXPECT_NEAR(g.time(), 2.0, 1e-4);
  EXPECT_EQ(g.outcome(), Outcome::Playing);
}

TEST(Game, ForwardFollowsTheCameraYaw) {
  Game a(emptyRoom());
  for (int i = 0; i < 30; ++i) a.step(kDt, forward(), 0.0f);
  EXPECT_LT(a.marblePos().z, -0.5f);  // camera on +z looks toward -z
  EXPECT_NEAR(a.marblePos().x, 0.0f, 1e-5f);

  Game b(emptyRoom());
  for (int i = 0; i < 30; ++i) b.step(kDt, forward(), glm::half_pi<float>());
  EXPECT_LT(b.marblePos().x, -0.5f);  // camera on +x looks toward -x
  EXPECT_NEAR(b.marblePos().z, 0.0f, 1e-4f);
}

TEST(Game, WallsContainTheMarbleAndBounceIt) {
  Game g(emptyRoom());
  const float lim = g.level().halfSize.x - g.level().marbleRadius + 1e-3f;
  float maxSpeed = 0.0f;
  // Drive diagonally into the corner for 10 s, turning the camera so the marble hits every wall.
  for (int i = 0; i < 600; ++i) {
    MoveIntent m = forward();
    m.move.x = 0.5f;
    g.step(kDt, m, static_cast<float>(i) * 0.01f);
    ASSERT_LE(std::abs(g.marblePos().x), lim) << "step " << i;
    ASSERT_LE(std::abs(g.marblePos().z), lim) << "step " << i;
    maxSpeed = std::max(maxSpeed, glm::length(g.marbleVelXZ()));
  }
  EXPECT_GT(g.bounces(), 0);
  EXPECT_LE(maxSpeed, Tuning{}.maxSpeed + 1e-3f);
}

TEST(Game, RollingTurnsTheMarbleByDistanceOverRadius) {
  Game g(emptyRoom());
  for (int i = 0; i < 20; ++i) g.step(kDt, forward(), 0.0f);
  const float dist = std::abs(g.marblePos().z);
  ASSERT_LT(dist, glm::pi<float>() * g.level().marbleRadius);  // under half a turn, so the angle is unique
  const float angle = 2.0f * std::acos(std::min(1.0f, std::abs(g.marbleRotation().w)));
  EXPECT_NEAR(angle, dist / g.level().marbleRadius, 1e-3f);
}

TEST(Game, PickingUpEveryGemWins) {
  Level l = emptyRoom();
  l.gems = {{{0.0f, -3.0f}, glm::vec3(1.0f)}};
  l.gemHeight = 0.6f;
  Game g(l);
  for (int i = 0; i < 120 && g.outcome() == Outcome::Playing; ++i) g.step(kDt, forward(), 0.0f);
  EXPECT_EQ(g.score(), 1);
  EXPECT_TRUE(g.gemCollected(0));
  EXPECT_EQ(g.outcome(), Outcome::Won);
  const double left = g.timeLeft();
  EXPECT_GT(left, 50.0);
  // The clock stops once the game is won, and the marble no longer takes input.
  const glm::vec3 p = g.marblePos();
  for (int i = 0; i < 600; ++i) g.step(kDt, forward(), 0.0f);
  EXPECT_DOUBLE_EQ(g.timeLeft(), left);
  EXPECT_LT(g.marblePos().z, p.z + 1e-3f);     // only coasts further the way it was going
  EXPECT_NEAR(glm::length(g.marbleVelXZ()), 0.0f, 0.3f);  // and comes to rest
  // A collected gem sinks out of sight under the floor.
  EXPECT_LT(g.gemTransform(0)[3].y, -1.0f);
}

TEST(Game, RunningOutOfTimeLoses) {
  Level l = emptyRoom();
  l.gems = {{{5.0f, 5.0f}, glm::vec3(1.0f)}};
  l.timeLimit = 2.0f;
  Game g(l);
  for (int i = 0; i < 119; ++i) g.step(kDt, {}, 0.0f);
  EXPECT_EQ(g.outcome(), Outcome::Playing);
  for (int i = 0; i < 2; ++i) g.step(kDt, {}, 0.0f);
  EXPECT_EQ(g.outcome(), Outcome::Lost);
  EXPECT_DOUBLE_EQ(g.timeLeft(), 0.0);
  g.reset();
  EXPECT_EQ(g.outcome(), Outcome::Playing);
  EXPECT_DOUBLE_EQ(g.time(), 0.0);
}

TEST(Game, SpinnerBatsAWaitingMarble) {
  Level l = emptyRoom();
  l.spinners.push_back({{"s", {0.0f, 0.0f}, {2.4f, 0.12f}, 0.8f, 0.0f, Surface::Mirror}, 0.8f});
  l.startXZ = {1.5f, -1.0f};  // in the blade's sweep, ahead of it (it turns +yaw, x toward -z)
  Game g(l);
  for (int i = 0; i < 120; ++i) g.step(kDt, {}, 0.0f);
  const glm::vec2 p(g.marblePos().x, g.marblePos().z);
  EXPECT_GT(glm::length(p - l.startXZ), 0.3f) << g.stateLine();
  // Never left inside the blade.
  EXPECT_FALSE(circleBoxContact(p, l.marbleRadius - 0.01f, g.spinnerBox(0)).has_value()) << g.stateLine();
}

TEST(Game, IsDeterministic) {
  auto run = [] {
    Game g(makeHallOfMirrors());
    for (int i = 0; i < 900; ++i) {
      MoveIntent m;
      m.move = {std::sin(static_cast<float>(i) * 0.05f), 1.0f};
      m.brake = (i / 100) % 3 == 2;
      g.step(kDt, m, static_cast<float>(i) * 0.003f);
    }
    return g.stateLine();
  };
  const std::string a = run();
  EXPECT_EQ(a, run());
  EXPECT_NE(a.find("state="), std::string::npos);
}

TEST(Game, StateLineIsParseable) {
  Game g(makeHallOfMirrors());
  const std::string s = g.stateLine();
  EXPECT_EQ(s.rfind("state=playing score=0/8 pos=0.000,0.400,4.500 ", 0), 0u) << s;
  EXPECT_NE(s.find(" left=60.000"), std::string::npos) << s;
}

TEST(Camera, OrbitClampAndStayInsideTheArena) {
  CameraRig rig;
  rig.update(1.0f, {0.0f, 10000.0f}, 0.0f, 0.0f);
  EXPECT_FLOAT_EQ(rig.pitch, 1.4f);
  rig.update(1.0f, {0.0f, -10000.0f}, 0.0f, 0.0f);
  EXPECT_FLOAT_EQ(rig.pitch, 0.1f);
  rig.update(0.5f, {0.0f, 0.0f}, 1.0f, 0.0f);
  EXPECT_NEAR(rig.yaw, 0.9f, 1e-5f);
  rig.update(0.0f, {0.0f, 0.0f}, 0.0f, 100.0f);
  EXPECT_FLOAT_EQ(rig.distance, 2.0f);
  rig.distance = 12.0f;
  const glm::vec3 e = rig.eye({8.5f, 0.4f, 8.5f}, glm::vec2(9.0f));
  EXPECT_LE(std::abs(e.x), 8.7f + 1e-5f);
  EXPECT_LE(std::abs(e.z), 8.7f + 1e-5f);
  EXPECT_GE(e.y, 0.3f);
}

TEST(Level, HallOfMirrorsIsPlayable) {
  const Level l = makeHallOfMirrors();
  EXPECT_EQ(l.gems.size(), 8u);
  // Every gem and the start are reachable: not inside any obstacle or the spinner's sweep.
  auto clear = [&](glm::vec2 p) {
    for (const Obstacle& o : l.obstacles)
      if (circleBoxContact(p, l.marbleRadius, o)) return false;
    for (const Spinner& s : l.spinners)
      if (glm::length(p - s.box.centerXZ) < glm::length(s.box.halfXZ) + l.marbleRadius) return false;
    return true;
  };
  EXPECT_TRUE(clear(l.startXZ));
  for (const GemSpec& g : l.gems) EXPECT_TRUE(clear(g.posXZ)) << g.posXZ.x << "," << g.posXZ.y;
}
