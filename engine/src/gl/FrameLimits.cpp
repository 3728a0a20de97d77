#include "gl/FrameLimits.h"

#include <string>

#include "gl/Gl.h"

namespace tandem::gl {

FrameLimits queryFrameLimits() {
  FrameLimits l;
  GLint viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &l.maxTextureSize);
  glGetIntegerv(GL_MAX_FRAMEBUFFER_WIDTH, &l.maxFramebufferWidth);
  glGetIntegerv(GL_MAX_FRAMEBUFFER_HEIGHT, &l.maxFramebufferHeight);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  l.maxViewportWidth = viewport[0];
  l.maxViewportHeight = viewport[1];
  const GLubyte* renderer = glGetString(GL_RENDERER);
  const std::string name = renderer ? reinterpret_cast<const char*>(renderer) : "";
  l.software = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
               name.find("swrast") != std::string::npos;
  return l;
}

Result<void> checkFrameLimits(int width, int height, const FrameLimits& l) {
  struct Check {
    const char* side;
    int value;
    const char* limit;
    int max;
  };
  const Check checks[] = {
      {"width", width, "GL_MAX_TEXTURE_SIZE", l.maxTextureSize},
      {"height", height, "GL_MAX_TEXTURE_SIZE", l.maxTextureSize},
      {"width", width, "GL_MAX_FRAMEBUFFER_WIDTH", l.maxFramebufferWidth},
      {"height", height, "GL_MAX_FRAMEBUFFER_HEIGHT", l.maxFramebufferHeight},
      {"width", width, "GL_MAX_VIEWPORT_DIMS[0]", l.maxViewportWidth},
      {"height", height, "GL_MAX_VIEWPORT_DIMS[1]", l.maxViewportHeight},
  };
  for (const Check& c : checks)
    if (c.value > c.max)
      return Error{std::string(c.side) + " " + std::to_string(c.value) + " exceeds " + c.limit + " = " +
                   std::to_string(c.max)};
  return {};
}

}  // namespace tandem::gl
