#include "core/Motion.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace tandem {

bool isMoving(const Instance& inst, float shutter) {
  return shutter > 0.0f && std::isfinite(shutter) &&
         (inst.velocity != glm::vec3(0.0f) || inst.angularVelocity != glm::vec3(0.0f));
}

glm::dmat4 rigidMotionAt(const Instance& inst, float shutter, double u) {
  const glm::dmat4 base(inst.worldFromObject);
  if (!isMoving(inst, shutter)) return base;
  const double tau = (u - 0.5) * static_cast<double>(shutter);
  const glm::dvec3 pivot(base[3]);
  const glm::dvec3 omega(inst.angularVelocity);
  const double angle = glm::length(omega) * tau;
  glm::dmat4 turn(1.0);
  if (angle != 0.0) turn = glm::rotate(glm::dmat4(1.0), angle, omega / glm::length(omega));
  // About the pivot: p ↦ pivot + v·τ + R·(p − pivot).
  glm::dmat4 m = turn * glm::translate(glm::dmat4(1.0), -pivot) * base;
  m[3] += glm::dvec4(pivot + glm::dvec3(inst.velocity) * tau, 0.0);
  return m;
}

std::vector<glm::mat4> motionSteps(const Instance& inst, float shutter, glm::vec3 anchor) {
  if (!isMoving(inst, shutter)) return {};
  const double turned = static_cast<double>(glm::length(inst.angularVelocity)) * static_cast<double>(shutter);
  constexpr double kStepRadians = 2.0 * 3.14159265358979323846 / 180.0;
  // An even count puts a step at u = 0.5, the transform itself: a frame drawn at the middle of the shutter
  // is the frame without motion blur, bit for bit.
  // Clamped in double: a huge spin times shutter would overflow the conversion to int.
  int segments = static_cast<int>(std::clamp(std::ceil(turned / kStepRadians), 2.0, double(kMaxMotionSteps - 1)));
  segments += segments % 2;
  std::vector<glm::mat4> steps;
  steps.reserve(static_cast<std::size_t>(segments) + 1);
  for (int k = 0; k <= segments; ++k) {
    glm::dmat4 m = rigidMotionAt(inst, shutter, static_cast<double>(k) / segments);
    m[3] -= glm::dvec4(glm::dvec3(anchor), 0.0);  // render space, rebased in double
    steps.push_back(glm::mat4(m));
  }
  return steps;
}

glm::mat4 motionAt(const std::vector<glm::mat4>& steps, float u) {
  if (steps.empty()) return glm::mat4(1.0f);
  if (steps.size() == 1) return steps.front();
  const float segments = static_cast<float>(steps.size() - 1);
  const float x = std::clamp(std::isfinite(u) ? u : 0.5f, 0.0f, 1.0f) * segments;
  const std::size_t i = std::min(static_cast<std::size_t>(x), steps.size() - 2);
  const float f = x - static_cast<float>(i);
  return steps[i] * (1.0f - f) + steps[i + 1] * f;
}

}  // namespace tandem
