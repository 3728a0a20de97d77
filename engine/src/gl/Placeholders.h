#pragma once
// What a pass binds where its shader declares a sampler the frame gives nothing for (no ray result this
// frame, no directional shadow map, no solid): a 1×1 texture of the sampler's type and format. GL 4.5
// leaves a sampler reading an empty unit undefined (NVIDIA's driver reports "undefined behavior" for a
// shadow sampler there), and the passes' own check before each draw (gl/FeedbackLoop.h) fails tests on it.
// The placeholders are never read: the shader's uniforms (rayInputs, light kinds) keep it away from them.
#include "gl/GlObjects.h"

namespace tandem::gl {

class Placeholders {
 public:
  enum Kind {
    Float2D,             // sampler2D: RGBA32F
    Uint2D,              // usampler2D: R32UI
    Uint2DArray,         // usampler2DArray: R32UI, one layer
    FloatCubeArray,      // samplerCubeArray: RGBA16F, one cube
    Depth2DArrayCompare, // sampler2DArrayShadow: depth, comparison on
    DepthCubeArrayCompare, // samplerCubeArrayShadow
    DepthCubeArray,      // samplerCubeArray reading depths: comparison off
    kKinds
  };
  /// The texture of `kind`, made the first time it is asked for (with the context current).
  GLuint get(Kind kind);
  /// Binds `texture` to `unit`, or the placeholder of `kind` when `texture` is 0.
  void bindOr(GLuint unit, GLuint texture, Kind kind) { glBindTextureUnit(unit, texture != 0 ? texture : get(kind)); }
  void release();

 private:
  Texture textures_[kKinds];
};

}  // namespace tandem::gl
