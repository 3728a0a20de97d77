#include "core/RenderSpace.h"

#include <cmath>

namespace tandem {

glm::vec3 renderAnchor(const Scene& scene) {
  const glm::vec3 p = scene.camera.posW;
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? p : glm::vec3(0.0f);
}

double anchorReach(const Camera& camera) { return 1024.0 * static_cast<double>(camera.nearZ); }

bool anchorDue(glm::vec3 anchor, const Camera& camera) {
  const glm::vec3 p = camera.posW;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return false;
  return glm::length(glm::dvec3(p) - glm::dvec3(anchor)) > anchorReach(camera);
}

glm::vec3 toRenderSpace(glm::vec3 posW, glm::vec3 anchor) {
  return glm::vec3(glm::dvec3(posW) - glm::dvec3(anchor));
}

Camera toRenderSpace(const Camera& camera, glm::vec3 anchor) {
  Camera c = camera;
  c.posW = toRenderSpace(camera.posW, anchor);
  // The view direction from the world-space difference (exact in double), lengthened by a power of two (exact
  // too) until the target is at least as far from the camera as the camera is from the anchor: then rounding
  // the target tilts the direction by an ulp of its own length at most. A camera at the anchor keeps its target.
  const glm::dvec3 forward = glm::dvec3(camera.targetW) - glm::dvec3(camera.posW);
  const double length = glm::length(forward), far = glm::length(glm::dvec3(c.posW));
  const double scale = length > 0.0 && far > length && std::isfinite(far) ? std::exp2(std::ceil(std::log2(far / length)))
                                                                           : 1.0;
  c.targetW = glm::vec3(glm::dvec3(c.posW) + forward * scale);
  if (scale > 1.0 && camera.aperture > 0.0f && !(camera.focusDistance > 0.0f && std::isfinite(camera.focusDistance)))
    c.focusDistance = static_cast<float>(length);  // (the target's distance was the plane in focus)
  return c;
}

glm::mat4 toRenderSpace(const glm::mat4& worldFromObject, glm::vec3 anchor) {
  glm::mat4 m = worldFromObject;
  m[3] = glm::vec4(toRenderSpace(glm::vec3(worldFromObject[3]), anchor), worldFromObject[3].w);
  return m;
}

}  // namespace tandem
