#pragma once
// The raster pass: the visibility G-buffer (instance + 1, triangle) over reversed-Z float depth, and its
// read-back for the ray pass. Channel table: docs/gbuffer.md.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"

namespace tandem::gl {

class VisibilityPass {
 public:
  static Result<VisibilityPass> create();

  /// Reallocates the targets when the frame size changes. An error names the target the GL refused
  /// (out of memory, an incomplete framebuffer); the pass then holds no targets (width() 0) until a
  /// resize succeeds.
  Result<void> resize(int width, int height);
  /// Drops the targets (width() 0).
  void release();
  /// The GL memory resize(width, height) allocates.
  static std::size_t targetBytes(int width, int height);
  /// `camera` in render space, the space of the GL copy: toRenderSpace(cameraW, scene.anchor()).
  void render(const GpuScene& scene, const Camera& camera);
  /// The same raster into another target (a shadow map's depth, a probe face's ids + depth) of
  /// width × height pixels, seen from `camera` (aspect width / height); `excluded` (an instance index)
  /// is left out when given. Clears the target's depth to far (0) and its colour 0 (if any) to 0.
  void renderInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Camera& camera,
                  std::optional<std::uint32_t> excluded = std::nullopt) const;
  /// The ids channel, row 0 = top (the ray pass's convention); `ids` is resized to width × height.
  void readIds(std::vector<glm::uvec2>& ids) const;

  const Texture& ids() const { return ids_; }
  const Texture& depth() const { return depth_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Program program_;
  Program maskProgram_;  // TD_ALPHA_MASK: discards texels of MASK materials under their cutoff
  Texture ids_, depth_;
  Framebuffer fbo_;
  int width_ = 0, height_ = 0;
};

}  // namespace tandem::gl
