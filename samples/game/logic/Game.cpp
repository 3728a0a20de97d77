#include "Game.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace marble {

glm::vec2 rotateXZ(glm::vec2 v, float yaw) {
  const float c = std::cos(yaw), s = std::sin(yaw);
  return {v.x * c + v.y * s, -v.x * s + v.y * c};
}

std::optional<Contact> circleBoxContact(glm::vec2 centerXZ, float radius, const Obstacle& box) {
  const glm::vec2 local = rotateXZ(centerXZ - box.centerXZ, -box.yaw);
  const glm::vec2 closest = glm::clamp(local, -box.halfXZ, box.halfXZ);
  const glm::vec2 d = local - closest;
  const float dist2 = glm::dot(d, d);
  if (dist2 >= radius * radius) return std::nullopt;
  Contact c;
  glm::vec2 nLocal;
  const float dist = std::sqrt(dist2);
  if (dist > 1e-6f) {
    nLocal = d / dist;
    c.depth = radius - dist;
  } else {
    // The centre is inside the box (only after a deep push, e.g. by the spinner): leave through the
    // nearest face rather than along an undefined direction.
    const float px = box.halfXZ.x - std::abs(local.x);
    const float pz = box.halfXZ.y - std::abs(local.y);
    if (px < pz) {
      nLocal = {local.x < 0.0f ? -1.0f : 1.0f, 0.0f};
      c.depth = px + radius;
    } else {
      nLocal = {0.0f, local.y < 0.0f ? -1.0f : 1.0f};
      c.depth = pz + radius;
    }
  }
  c.normal = rotateXZ(nLocal, box.yaw);
  c.pointXZ = box.centerXZ + rotateXZ(closest, box.yaw);
  return c;
}

const char* toString(Outcome o) {
  switch (o) {
    case Outcome::Playing: return "playing";
    case Outcome::Won: return "won";
    case Outcome::Lost: return "lost";
  }
  return "?";
}

Game::Game(Level level, Tuning tuning) : level_(std::move(level)), tuning_(tuning) { reset(); }

void Game::reset() {
  pos_ = level_.startXZ;
  vel_ = glm::vec2(0.0f);
  rot_ = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  collected_.assign(level_.gems.size(), false);
  collectedAt_.assign(level_.gems.size(), -1.0);
  score_ = 0;
  bounces_ = 0;
  time_ = 0.0;
  endTime_ = -1.0;
  lastPickup_ = -1.0;
  outcome_ = Outcome::Playing;
}

double Game::timeLeft() const {
  const double t = outcome_ == Outcome::Playing ? time_ : endTime_;
  return std::max(0.0, static_cast<double>(level_.timeLimit) - t);
}

float Game::spinnerYaw(std::size_t i) const {
  const Spinner& s = level_.spinners[i];
  return s.box.yaw + s.angularSpeed * static_cast<float>(time_);
}

Obstacle Game::spinnerBox(std::size_t i) const {
  Obstacle b = level_.spinners[i].box;
  b.yaw = spinnerYaw(i);
  return b;
}

void Game::collide(const Obstacle& box, glm::vec2 pivot, float angularSpeed) {
  const auto c = circleBoxContact(pos_, level_.marbleRadius, box);
  if (!c) return;
  pos_ += c->normal * c->depth;
  // The surface's own velocity at the contact (zero for static boxes): d/dt of rotateXZ(r, ω t) is
  // ω·(r.z, -r.x), so a spinning blade bats the marble instead of just blocking it.
  const glm::vec2 r = c->pointXZ - pivot;
  const glm::vec2 surfaceVel = angularSpeed * glm::vec2(r.y, -r.x);
  const float vn = glm::dot(vel_ - surfaceVel, c->normal);
  if (vn < 0.0f) {
    vel_ -= (1.0f + tuning_.restitution) * vn * c->normal;
    if (vn < -0.5f) ++bounces_;  // resting contact is not a bounce
  }
}

void Game::step(float dt, const MoveIntent& intent, float cameraYaw) {
  if (!(dt > 0.0f)) return;
  glm::vec2 dir(0.0f);
  if (outcome_ == Outcome::Playing) {
    const glm::vec2 forward(-std::sin(cameraYaw), -std::cos(cameraYaw));
    const glm::vec2 right(std::cos(cameraYaw), -std::sin(cameraYaw));
    dir = right * intent.move.x + forward * intent.move.y;
    if (glm::dot(dir, dir) > 1.0f) dir = glm::normalize(dir);
  }
  const int n = std::max(1, tuning_.substeps);
  const float h = dt / static_cast<float>(n);
  const float damping = tuning_.rollDamping + (intent.brake ? tuning_.brakeDamping : 0.0f);
  for (int s = 0; s < n; ++s) {
    const glm::vec2 before = vel_;
    vel_ += dir * tuning_.accel * h;
    // Input may not push past maxSpeed, but a bat from the spinner may (and then decays).
    const float cap = std::max(tuning_.maxSpeed, glm::length(before));
    if (float len = glm::length(vel_); len > cap) vel_ *= cap / len;
    vel_ *= std::exp(-damping * h);
    pos_ += vel_ * h;

    const double tSub = time_ + static_cast<double>(h) * (s + 1);
    for (const Obstacle& o : level_.obstacles) collide(o, o.centerXZ, 0.0f);
    for (const Spinner& sp : level_.spinners) {
      Obstacle b = sp.box;
      b.yaw = sp.box.yaw + sp.angularSpeed * static_cast<float>(tSub);
      collide(b, b.centerXZ, sp.angularSpeed);
    }
    // Rolling without slipping: angular velocity (v.z, 0, -v.x)/r, i.e. up × v over the radius.
    const float speed = glm::length(vel_);
    if (speed > 1e-5f) {
      const glm::vec3 axis(vel_.y / speed, 0.0f, -vel_.x / speed);
      rot_ = glm::normalize(glm::angleAxis(speed * h / level_.marbleRadius, axis) * rot_);
    }
  }
  time_ += dt;

  if (outcome_ != Outcome::Playing) return;
  const glm::vec3 p = marblePos();
  for (std::size_t i = 0; i < level_.gems.size(); ++i) {
    if (collected_[i]) continue;
    const glm::vec3 g(level_.gems[i].posXZ.x, level_.gemHeight, level_.gems[i].posXZ.y);
    const float reach = level_.marbleRadius + level_.gemRadius;
    if (glm::dot(p - g, p - g) < reach * reach) {
      collected_[i] = true;
      collectedAt_[i] = time_;
      lastPickup_ = time_;
      ++score_;
    }
  }
  if (score_ == gemCount()) {
    outcome_ = Outcome::Won;
    endTime_ = time_;
  } else if (time_ >= static_cast<double>(level_.timeLimit)) {
    outcome_ = Outcome::Lost;
    endTime_ = time_;
  }
}

glm::mat4 Game::marbleTransform() const {
  return glm::translate(glm::mat4(1.0f), marblePos()) * glm::mat4_cast(rot_);
}

glm::mat4 Game::gemTransform(std::size_t i) const {
  const GemSpec& g = level_.gems[i];
  const float t = static_cast<float>(time_);
  const float phase = static_cast<float>(i) * 0.7f;
  float y = level_.gemHeight + 0.12f * std::sin(2.0f * t + phase);
  float scale = 1.0f;
  if (collected_[i]) {
    // A short flourish (rise and shrink), then parked under the floor: the instance stays in the scene
    // (no rebuild), it just moves out of sight.
    const float age = static_cast<float>(time_ - collectedAt_[i]);
    if (age >= 0.4f) return glm::translate(glm::mat4(1.0f), {g.posXZ.x, -10.0f, g.posXZ.y}) *
                            glm::scale(glm::mat4(1.0f), glm::vec3(0.01f));
    y += 1.5f * age;
    scale = std::max(0.05f, 1.0f - age / 0.4f);
  }
  glm::mat4 m = glm::translate(glm::mat4(1.0f), {g.posXZ.x, y, g.posXZ.y});
  m = glm::rotate(m, 1.6f * t + phase, glm::vec3(0, 1, 0));
  // A cube balanced on a corner reads as a gem: tilt the body diagonal onto +Y.
  m = glm::rotate(m, std::atan(std::sqrt(2.0f)), glm::vec3(1, 0, 0));
  m = glm::rotate(m, glm::quarter_pi<float>(), glm::vec3(0, 0, 1));
  return glm::scale(m, glm::vec3(scale));
}

glm::mat4 Game::spinnerTransform(std::size_t i) const {
  const Obstacle& b = level_.spinners[i].box;
  glm::mat4 m = glm::translate(glm::mat4(1.0f), {b.centerXZ.x, 0.5f * b.height, b.centerXZ.y});
  return glm::rotate(m, spinnerYaw(i), glm::vec3(0, 1, 0));
}

std::string Game::stateLine() const {
  const glm::vec3 p = marblePos();
  char buf[256];
  std::snprintf(buf, sizeof buf, "state=%s score=%d/%d pos=%.3f,%.3f,%.3f vel=%.3f,%.3f time=%.3f left=%.3f bounces=%d",
                toString(outcome_), score_, gemCount(), static_cast<double>(p.x), static_cast<double>(p.y),
                static_cast<double>(p.z), static_cast<double>(vel_.x), static_cast<double>(vel_.y), time_,
                timeLeft(), bounces_);
  return buf;
}

void CameraRig::update(float dt, glm::vec2 mouseDelta, float orbit, float scroll) {
  constexpr float kRadPerPixel = 0.005f;
  constexpr float kOrbitRate = 1.8f;  // rad/s with Q / E held
  yaw -= mouseDelta.x * kRadPerPixel;
  yaw += orbit * kOrbitRate * dt;
  pitch = std::clamp(pitch + mouseDelta.y * kRadPerPixel, 0.1f, 1.4f);
  distance = std::clamp(distance * std::pow(0.9f, scroll), 2.0f, 12.0f);
  // Keep yaw bounded so a long session does not lose float precision in sin/cos.
  yaw = std::remainder(yaw, glm::two_pi<float>());
}

glm::vec3 CameraRig::eye(glm::vec3 target, glm::vec2 arenaHalfSize) const {
  const float c = std::cos(pitch);
  glm::vec3 e = target + distance * glm::vec3(std::sin(yaw) * c, std::sin(pitch), std::cos(yaw) * c);
  const glm::vec2 lim = arenaHalfSize - glm::vec2(0.3f);
  e.x = std::clamp(e.x, -lim.x, lim.x);
  e.z = std::clamp(e.z, -lim.y, lim.y);
  e.y = std::max(e.y, 0.3f);
  return e;
}

}  // namespace marble
