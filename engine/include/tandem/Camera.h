#pragma once
// A pinhole (or orthographic) camera with reversed-Z projection: near maps to depth 1, far to 0, and
// farZ may be infinite. A perspective camera with an aperture is a thin lens (depth of field): each frame
// sees through one point of the lens, as the pinhole lensPinhole() returns. Pixels are addressed with y down (row 0 is the top of the image), pixel
// centres at integer + 0.5.
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace tandem {

struct Ray {
  glm::vec3 origin{0.0f};
  glm::vec3 dir{0.0f, 0.0f, -1.0f};  // unit
};

struct Camera {
  glm::vec3 posW{0.0f, 1.0f, 5.0f};
  glm::vec3 targetW{0.0f, 0.0f, 0.0f};
  glm::vec3 upW{0.0f, 1.0f, 0.0f};
  float yFovDeg = 45.0f;       // vertical field of view (perspective)
  float nearZ = 0.05f;         // > 0
  float farZ = std::numeric_limits<float>::infinity();  // > nearZ, may be infinite
  bool orthographic = false;
  float orthoHeight = 2.0f;    // world units visible vertically (orthographic)
  /// Where the frame samples each pixel, in pixels from its centre (x right, y down), within ±0.5: the
  /// sub-pixel offset of one anti-aliasing sample (FrameSettings::aa, accumulate). The rasterizer, the shade
  /// pass and every camera ray honour it, so one jittered frame is still exact at its sample points.
  glm::vec2 jitterPx{0.0f};
  /// Which sample of an accumulation this frame is (0 outside one): it picks the frame's area-light samples
  /// (and advances with jitterPx), so accumulated frames add new samples of one stratified sequence.
  std::uint32_t sampleIndex = 0;
  /// Thin lens (depth of field, perspective only): the lens diameter in world units; 0 is a pinhole.
  float aperture = 0.0f;
  /// The distance along the view direction of the plane in focus; 0 or less: the target's distance.
  float focusDistance = 0.0f;
  /// The point of the lens this frame sees through, in [0, 1)² mapped onto the lens disk (squareToDisk,
  /// core/Sampling.h); (0.5, 0.5) is its centre, the pinhole. Accumulated samples move it (lensSample).
  glm::vec2 lensUv{0.5f};
  /// Motion blur: seconds the shutter stays open, centred on the frame's time; 0 (the default) freezes
  /// every instance at its transform. Instance::velocity and angularVelocity say how things move meanwhile.
  float shutter = 0.0f;
  /// When within the shutter this frame is drawn, in [0, 1] (0 opens it, 1 closes it; 0.5, the default, is
  /// the frame's own time, where instances stand at their transforms). Accumulated samples move it (timeSample).
  float timeU = 0.5f;

  glm::mat4 viewFromWorld() const;
  glm::mat4 worldFromView() const;
  /// Reversed-Z, depth range [0, 1] (use with glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)).
  glm::mat4 clipFromView(float aspect) const;
  /// clipFromView for a frame of `size` pixels, shifted by jitterPx: the projection the rasterizer uses.
  glm::mat4 clipFromView(glm::ivec2 size) const;
  /// The ray through a point of the image plane; `pixel` is in pixels with y down, so the centre of
  /// pixel (x, y) is (x + 0.5, y + 0.5), moved by jitterPx. This is the ray the rasterizer samples at that pixel.
  Ray rayThroughPixel(glm::vec2 pixel, glm::ivec2 size) const;

  /// The distance of the plane in focus (focusDistance, else the target's).
  float focusPlane() const;
  /// Where the lens point lensUv lies, in world units from posW (0 without an aperture or orthographic).
  glm::vec3 lensOffsetW() const;
  /// The pinhole camera at the lens point that sees the plane in focus exactly as this camera's centre
  /// does: moved by lensOffsetW and its image shifted (jitterPx) so every point of that plane stays on its
  /// pixel, while nearer and farther points move with the lens (their circle of confusion). A frame with
  /// `size` pixels drawn with it is one exact sample of the thin lens: the rasterizer, the ray pass and the
  /// shading all see an ordinary camera. Without an aperture, or orthographic, this camera unchanged.
  Camera lensPinhole(glm::ivec2 size) const;

  /// Field by field, exactly: a frame can reuse the last one's rays only for the very same camera.
  bool operator==(const Camera&) const = default;
};

}  // namespace tandem
