#include "core/RenderSpace.h"

#include <cmath>

namespace tandem {

glm::vec3 renderAnchor(const Scene& scene) {
  const glm::vec3 p = scene.camera.posW;
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? p : glm::vec3(0.0f);
}

glm::vec3 toRenderSpace(glm::vec3 posW, glm::vec3 anchor) {
  return glm::vec3(glm::dvec3(posW) - glm::dvec3(anchor));
}

Camera toRenderSpace(const Camera& camera, glm::vec3 anchor) {
  Camera c = camera;
  c.posW = toRenderSpace(camera.posW, anchor);
  // The view direction from the world-space difference (exact in double): rounding the two rebased
  // points separately would tilt it by their rounding when the target is close to the camera.
  glm::dvec3 forward = glm::dvec3(camera.targetW) - glm::dvec3(camera.posW);
  c.targetW = glm::vec3(glm::dvec3(c.posW) + forward);
  return c;
}

glm::mat4 toRenderSpace(const glm::mat4& worldFromObject, glm::vec3 anchor) {
  glm::mat4 m = worldFromObject;
  m[3] = glm::vec4(toRenderSpace(glm::vec3(worldFromObject[3]), anchor), worldFromObject[3].w);
  return m;
}

}  // namespace tandem
