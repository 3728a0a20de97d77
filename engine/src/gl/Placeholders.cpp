#include "gl/Placeholders.h"

namespace tandem::gl {

GLuint Placeholders::get(Kind kind) {
  Texture& t = textures_[kind];
  if (t) return t.id();
  switch (kind) {
    case Float2D: t = createTexture2D("placeholder float", GL_RGBA32F, 1, 1); break;
    case Uint2D: t = createTexture2D("placeholder uint", GL_R32UI, 1, 1); break;
    case Uint2DArray: t = createTexture2DArray("placeholder uint array", GL_R32UI, 1, 1, 1, 1); break;
    case FloatCubeArray: t = createTextureCube("placeholder cube array", GL_RGBA16F, 1, 1); break;
    case Depth2DArrayCompare: t = createTexture2DArray("placeholder shadow maps", GL_DEPTH_COMPONENT32F, 1, 1, 1, 1); break;
    case DepthCubeArrayCompare: t = createTextureCube("placeholder shadow cubes", GL_DEPTH_COMPONENT32F, 1, 1); break;
    case DepthCubeArray: t = createTextureCube("placeholder shadow cube depths", GL_DEPTH_COMPONENT32F, 1, 1); break;
    case kKinds: return 0;
  }
  // Integer textures must be sampled nearest to be complete; every placeholder is, and holds zeros.
  setSampling(t, GL_NEAREST, GL_NEAREST);
  if (kind == Depth2DArrayCompare || kind == DepthCubeArrayCompare) {
    glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL);
  }
  return t.id();
}

void Placeholders::release() {
  for (Texture& t : textures_) t.reset();
}

}  // namespace tandem::gl
