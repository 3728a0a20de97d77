#include "tandem/Camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include "core/Sampling.h"

namespace tandem {

namespace {

// The camera's view basis (right-handed, y up): the one rayThroughPixel and the lens share.
struct ViewBasis {
  glm::vec3 forward, right, up;
};
ViewBasis viewBasis(const Camera& c) {
  ViewBasis b;
  b.forward = glm::normalize(c.targetW - c.posW);
  b.right = glm::normalize(glm::cross(b.forward, c.upW));
  b.up = glm::cross(b.right, b.forward);
  return b;
}

}  // namespace

glm::mat4 Camera::viewFromWorld() const { return glm::lookAtRH(posW, targetW, upW); }

glm::mat4 Camera::worldFromView() const { return glm::inverse(viewFromWorld()); }

glm::mat4 Camera::clipFromView(float aspect) const {
  glm::mat4 m(0.0f);
  if (orthographic) {
    // Reversed-Z orthographic: z_ndc = (z_view + far) / (far - near) maps -near → 1, -far → 0.
    float halfH = orthoHeight * 0.5f;
    float halfW = halfH * aspect;
    float f = std::isinf(farZ) ? 1e7f : farZ;
    m[0][0] = 1.0f / halfW;
    m[1][1] = 1.0f / halfH;
    m[2][2] = 1.0f / (f - nearZ);
    m[3][2] = f / (f - nearZ);
    m[3][3] = 1.0f;
    return m;
  }
  float t = 1.0f / std::tan(glm::radians(yFovDeg) * 0.5f);
  m[0][0] = t / aspect;
  m[1][1] = t;
  m[2][3] = -1.0f;  // w_clip = -z_view
  if (std::isinf(farZ)) {
    // Infinite far plane: z_ndc = near / -z_view.
    m[3][2] = nearZ;
  } else {
    // z_ndc = (near·far / (far − near)) / -z_view + near / (far − near): near → 1, far → 0.
    m[2][2] = nearZ / (farZ - nearZ);
    m[3][2] = farZ * nearZ / (farZ - nearZ);
  }
  return m;
}

glm::mat4 Camera::clipFromView(glm::ivec2 size) const {
  glm::mat4 m = clipFromView(float(size.x) / float(size.y));
  if (jitterPx == glm::vec2(0.0f)) return m;
  // The pixel centre must see what lies at centre + jitter: everything moves by -jitter on screen.
  // x_clip += dx·w_clip moves x_ndc by dx at every depth, perspective or not; NDC y runs up, pixels down.
  glm::mat4 shift(1.0f);
  shift[3][0] = -2.0f * jitterPx.x / float(size.x);
  shift[3][1] = 2.0f * jitterPx.y / float(size.y);
  return shift * m;
}

float Camera::focusPlane() const {
  if (focusDistance > 0.0f && std::isfinite(focusDistance)) return focusDistance;
  return glm::length(targetW - posW);
}

glm::vec3 Camera::lensOffsetW() const {
  // NaN or negative apertures are no lens: per-frame code never fails, the scene file rejects them.
  if (!(aperture > 0.0f) || !std::isfinite(aperture) || orthographic) return glm::vec3(0.0f);
  const auto [forward, right, up] = viewBasis(*this);
  // A NaN lens point is the centre (per-frame code never fails; the scene check refuses it).
  const glm::vec2 uv(std::isfinite(lensUv.x) ? lensUv.x : 0.5f, std::isfinite(lensUv.y) ? lensUv.y : 0.5f);
  const glm::vec2 d = 0.5f * aperture * squareToDisk(glm::clamp(uv, 0.0f, 1.0f));
  return right * d.x + up * d.y;
}

Camera Camera::lensPinhole(glm::ivec2 size) const {
  Camera c = *this;
  const glm::vec3 offsetW = lensOffsetW();
  const float focus = focusPlane();
  if (offsetW == glm::vec3(0.0f) || !(focus > 0.0f) || !std::isfinite(focus)) return c;
  c.aperture = 0.0f;
  c.posW += offsetW;
  // Far from the origin the move rounds to float's grain there: what counts is the move made, so the
  // target moves by it too (the view direction stays) and the image shift below follows it.
  const glm::vec3 movedW = c.posW - posW;
  c.targetW += movedW;
  // The focus plane's point seen at NDC n from the centre is posW + F·(forward + n·(t·aspect, t)); from the
  // lens point it lies at NDC n − d / (F·(t·aspect, t)), d the offset in (right, up). A uniform image shift:
  // d.x·H / (2·F·t) pixels left and d.y·H / (2·F·t) down (pixels run down, NDC up), whatever the aspect.
  const auto [forward, right, up] = viewBasis(*this);
  const float t = std::tan(glm::radians(yFovDeg) * 0.5f);
  const float pxPerWorld = float(size.y) / (2.0f * focus * t);
  c.jitterPx += glm::vec2(-glm::dot(movedW, right), glm::dot(movedW, up)) * pxPerWorld;
  return c;
}

Ray Camera::rayThroughPixel(glm::vec2 pixel, glm::ivec2 size) const {
  pixel += jitterPx;
  float aspect = float(size.x) / float(size.y);
  // NDC of the point, y up.
  float nx = pixel.x / float(size.x) * 2.0f - 1.0f;
  float ny = 1.0f - pixel.y / float(size.y) * 2.0f;
  const auto [forward, right, up] = viewBasis(*this);
  Ray r;
  if (orthographic) {
    float halfH = orthoHeight * 0.5f;
    r.origin = posW + right * (nx * halfH * aspect) + up * (ny * halfH);
    r.dir = forward;
    return r;
  }
  float t = std::tan(glm::radians(yFovDeg) * 0.5f);
  r.origin = posW;
  r.dir = glm::normalize(forward + right * (nx * t * aspect) + up * (ny * t));
  return r;
}

}  // namespace tandem
