#pragma once
// The rules and the physics of the marble game, GL-free and deterministic: the same inputs and the
// same fixed steps give bit-identical states, which is what the headless tests rely on.
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "Input.h"
#include "Level.h"

namespace marble {

// ---- Geometry helpers (exposed for the unit tests) ----

/// Rotates a floor-plane vector (x, z) about +Y by `yaw`, as glm::rotate(yaw, {0,1,0}) does to (x, 0, z).
glm::vec2 rotateXZ(glm::vec2 v, float yaw);

struct Contact {
  glm::vec2 normal{0.0f};  // unit, from the box toward the sphere centre
  float depth = 0.0f;      // > 0: how far the sphere overlaps the box
  glm::vec2 pointXZ{0.0f}; // closest point on the box
};

/// Circle (the marble's footprint) against a rotated rectangle; nullopt when they do not overlap.
std::optional<Contact> circleBoxContact(glm::vec2 centerXZ, float radius, const Obstacle& box);

// ---- The game ----

enum class Outcome { Playing, Won, Lost };
const char* toString(Outcome o);

struct Tuning {
  float accel = 11.0f;        // m/s² from a full stick
  float maxSpeed = 7.5f;      // m/s, caps the marble's speed under input
  float rollDamping = 0.55f;  // 1/s, exponential rolling resistance
  float brakeDamping = 4.0f;  // 1/s, extra damping while braking
  float restitution = 0.55f;  // fraction of normal speed kept after a bounce
  int substeps = 4;           // collision substeps per step, so fast bounces never tunnel a thin wall
};

class Game {
 public:
  explicit Game(Level level, Tuning tuning = {});

  /// Back to the start: marble, gems, timer and score.
  void reset();
  /// Advances the simulation by `dt` seconds. `move` is the player's intent relative to the camera
  /// (x right, y forward) and `cameraYaw` the camera's yaw, which defines "forward".
  void step(float dt, const MoveIntent& intent, float cameraYaw);

  const Level& level() const { return level_; }
  glm::vec3 marblePos() const { return {pos_.x, level_.marbleRadius, pos_.y}; }
  glm::vec2 marbleVelXZ() const { return vel_; }
  glm::quat marbleRotation() const { return rot_; }
  int score() const { return score_; }
  int gemCount() const { return static_cast<int>(level_.gems.size()); }
  bool gemCollected(std::size_t i) const { return collected_[i]; }
  double time() const { return time_; }  // seconds simulated since reset
  double timeLeft() const;
  Outcome outcome() const { return outcome_; }
  /// Time of the last pickup (for the HUD's flash), negative when none yet.
  double lastPickupTime() const { return lastPickup_; }
  int bounces() const { return bounces_; }

  /// World transforms of the animated parts at the current time.
  glm::mat4 marbleTransform() const;
  glm::mat4 gemTransform(std::size_t i) const;      // spins and bobs; collected gems sink out of sight
  glm::mat4 spinnerTransform(std::size_t i) const;
  float spinnerYaw(std::size_t i) const;
  Obstacle spinnerBox(std::size_t i) const;         // the spinner's obstacle at the current time

  /// One parseable line: "state=playing score=2/8 pos=1.234,0.400,-2.345 vel=... time=... left=..."
  std::string stateLine() const;

 private:
  void collide(const Obstacle& box, glm::vec2 boxAngularCenter, float angularSpeed);

  Level level_;
  Tuning tuning_;
  glm::vec2 pos_{0.0f};
  glm::vec2 vel_{0.0f};
  glm::quat rot_{1.0f, 0.0f, 0.0f, 0.0f};
  std::vector<bool> collected_;
  std::vector<double> collectedAt_;
  int score_ = 0;
  int bounces_ = 0;
  double time_ = 0.0;
  double endTime_ = -1.0;
  double lastPickup_ = -1.0;
  Outcome outcome_ = Outcome::Playing;
};

// ---- The third-person camera ----

/// Orbits the marble: yaw about +Y (0 = camera on +z of the marble), pitch above the horizon,
/// distance; kept inside the arena so the walls never hide the marble from behind.
struct CameraRig {
  float yaw = 0.0f;
  float pitch = 0.5f;     // radians, clamped to [0.1, 1.4]
  float distance = 5.0f;  // clamped to [2, 12]

  /// Mouse drag (pixels), keyboard orbit (-1..1) and wheel notches over `dt` seconds.
  void update(float dt, glm::vec2 mouseDelta, float orbit, float scroll);
  /// Eye position for a target, clamped inside the arena (margin 0.3) and above the floor.
  glm::vec3 eye(glm::vec3 target, glm::vec2 arenaHalfSize) const;
};

}  // namespace marble
