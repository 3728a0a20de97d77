#pragma once
// A pinhole (or orthographic) camera with reversed-Z projection: near maps to depth 1, far to 0, and
// farZ may be infinite. Pixels are addressed with y down (row 0 is the top of the image), pixel
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

  glm::mat4 viewFromWorld() const;
  glm::mat4 worldFromView() const;
  /// Reversed-Z, depth range [0, 1] (use with glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)).
  glm::mat4 clipFromView(float aspect) const;
  /// clipFromView for a frame of `size` pixels, shifted by jitterPx: the projection the rasterizer uses.
  glm::mat4 clipFromView(glm::ivec2 size) const;
  /// The ray through a point of the image plane; `pixel` is in pixels with y down, so the centre of
  /// pixel (x, y) is (x + 0.5, y + 0.5), moved by jitterPx. This is the ray the rasterizer samples at that pixel.
  Ray rayThroughPixel(glm::vec2 pixel, glm::ivec2 size) const;

  /// Field by field, exactly: a frame can reuse the last one's rays only for the very same camera.
  bool operator==(const Camera&) const = default;
};

}  // namespace tandem
