#pragma once
// Moving and scaling a whole scene for the precision tests (numerics, gl): every instance, light and the
// camera, composed in double and rounded to float once, as a user's far-away scene would be.
#include <cmath>

#include <glm/glm.hpp>

#include "tandem/Scene.h"

namespace tandem {

inline void transformScene(Scene& s, double scale, glm::dvec3 offset) {
  glm::dmat4 m(1.0);
  m[0][0] = m[1][1] = m[2][2] = scale;
  m[3] = glm::dvec4(offset, 1.0);
  auto point = [&](glm::vec3 p) { return glm::vec3(offset + scale * glm::dvec3(p)); };
  for (Instance& i : s.instances) i.worldFromObject = glm::mat4(m * glm::dmat4(i.worldFromObject));
  for (Light& l : s.lights) {
    l.posW = point(l.posW);
    l.range = static_cast<float>(l.range * scale);
    // 1/(c + l·d + q·d²) with d scaled by s: the same falloff needs l/s and q/s².
    l.attenuation.y = static_cast<float>(l.attenuation.y / scale);
    l.attenuation.z = static_cast<float>(l.attenuation.z / (scale * scale));
  }
  s.camera.posW = point(s.camera.posW);
  s.camera.targetW = point(s.camera.targetW);
  s.camera.nearZ = static_cast<float>(s.camera.nearZ * scale);
  if (std::isfinite(s.camera.farZ)) s.camera.farZ = static_cast<float>(s.camera.farZ * scale);
  s.camera.orthoHeight = static_cast<float>(s.camera.orthoHeight * scale);
}

}  // namespace tandem
