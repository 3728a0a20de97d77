#pragma once
// The largest frame the GL can hold: the driver's size limits on the textures and framebuffers a frame
// renders into. Checked before anything is allocated, so a size beyond them is an error naming the limit
// rather than a frame drawn into nothing.
#include "tandem/Result.h"

namespace tandem::gl {

struct FrameLimits {
  int maxTextureSize = 0;        // GL_MAX_TEXTURE_SIZE: every frame target is a 2D texture
  int maxFramebufferWidth = 0;   // GL_MAX_FRAMEBUFFER_WIDTH
  int maxFramebufferHeight = 0;  // GL_MAX_FRAMEBUFFER_HEIGHT
  int maxViewportWidth = 0;      // GL_MAX_VIEWPORT_DIMS: a larger viewport is silently clamped
  int maxViewportHeight = 0;
  /// The GL rasterizes on the CPU (Mesa's llvmpipe, softpipe or swrast: GL_RENDERER names them), sharing the
  /// cores with the ray pass: the plan keeps per-pixel work there that a GPU would take (SceneFacts::softwareGl).
  bool software = false;
};

/// The current context's limits.
FrameLimits queryFrameLimits();

/// The first limit a width × height frame exceeds, named with its value, e.g. "width 16385 exceeds
/// GL_MAX_TEXTURE_SIZE = 16384"; nothing when the frame is within all of them.
Result<void> checkFrameLimits(int width, int height, const FrameLimits& limits);

}  // namespace tandem::gl
