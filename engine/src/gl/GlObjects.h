#pragma once
// Move-only owners of GL objects. This file and GlObjects.cpp are the only place GL objects are created
// (glCreate*) or deleted; everything else holds one of these. Every object gets a label, so debuggers
// (apitrace, RenderDoc) and KHR_debug messages name it.
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gl/Bindings.h"
#include "gl/Gl.h"
#include "tandem/Result.h"

namespace tandem::gl {

/// GL objects alive now, across all kinds: the soak test checks it stays flat over scene reloads.
std::size_t liveObjectCount();
namespace detail {
void countObject(int delta);
}

template <class Traits>
class Object {
 public:
  Object() = default;
  explicit Object(GLuint id) : id_(id) {
    if (id_ != 0) detail::countObject(+1);
  }
  ~Object() { reset(); }
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  Object(Object&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Object& operator=(Object&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_ != 0) {
      Traits::destroy(id_);
      detail::countObject(-1);
    }
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

struct BufferTraits { static void destroy(GLuint id); };
struct TextureTraits { static void destroy(GLuint id); };
struct FramebufferTraits { static void destroy(GLuint id); };
struct VertexArrayTraits { static void destroy(GLuint id); };
struct ShaderTraits { static void destroy(GLuint id); };
struct ProgramTraits { static void destroy(GLuint id); };
struct SamplerTraits { static void destroy(GLuint id); };

using Buffer = Object<BufferTraits>;
using Texture = Object<TextureTraits>;
using Framebuffer = Object<FramebufferTraits>;
using VertexArray = Object<VertexArrayTraits>;
using Shader = Object<ShaderTraits>;
using Program = Object<ProgramTraits>;
using Sampler = Object<SamplerTraits>;

/// Immutable-size buffer (glNamedBufferStorage) with GL_DYNAMIC_STORAGE_BIT, so glNamedBufferSubData
/// can update it; `data` may be null. A zero size allocates 16 bytes: GL refuses empty storage and
/// shaders may still declare the binding.
Buffer createBuffer(std::string_view label, std::size_t bytes, const void* data);
/// Texture with immutable storage of `levels` × width × height (× layers for arrays).
Texture createTexture2D(std::string_view label, GLenum internalFormat, int width, int height, int levels = 1);
/// createTexture2D (one level) for storage that may not fit: frame-size targets. The driver may refuse the
/// storage (GL_OUT_OF_MEMORY; llvmpipe refuses any texture over 2 GiB) and GL would carry on with an
/// empty texture, so the GL error is read right after the allocation: the error names the texture, its
/// size, format and bytes, and the GL error. Errors already pending are logged and cleared first, so
/// they are not taken for this one.
Result<Texture> tryCreateTexture2D(std::string_view label, GLenum internalFormat, int width, int height);
/// Bytes per texel of the formats tryCreateTexture2D takes (0 for others).
constexpr std::size_t texelBytes(GLenum internalFormat) {
  switch (internalFormat) {
    case GL_RGBA32F: case GL_RGBA32UI: return 16;
    case GL_RG32UI: case GL_RGBA16F: return 8;
    case GL_RGBA8: case GL_R32UI: case GL_DEPTH_COMPONENT32F: return 4;
    case GL_R8UI: return 1;
    default: return 0;  // not a format of the frame's targets
  }
}
// Every frame channel's format is one the frame-size check (targetBytes) can count.
// (The ray grid's: gl/RayChannels.h.)
static_assert(texelBytes(kChannelIds.internal) > 0 && texelBytes(kChannelDepth.internal) > 0 &&
              texelBytes(kChannelLinear.internal) > 0 &&
              texelBytes(kChannelDisplay.internal) > 0 && texelBytes(kChannelProbes.internal) > 0 &&
              texelBytes(kChannelShadowMaps.internal) > 0,
              "texelBytes: a frame channel's format is missing");
/// Bytes per texel of a CPU copy in `format`'s pixel transfer format and type (0 for a pair no channel uses).
constexpr std::size_t transferBytes(ChannelFormat format) {
  std::size_t components = 0, bytes = 0;
  switch (format.transfer) {
    case GL_RED: case GL_RED_INTEGER: case GL_DEPTH_COMPONENT: components = 1; break;
    case GL_RG: case GL_RG_INTEGER: components = 2; break;
    case GL_RGBA: case GL_RGBA_INTEGER: components = 4; break;
    default: return 0;
  }
  switch (format.type) {
    case GL_UNSIGNED_BYTE: bytes = 1; break;
    case GL_UNSIGNED_SHORT: case GL_HALF_FLOAT: bytes = 2; break;
    case GL_UNSIGNED_INT: case GL_FLOAT: bytes = 4; break;
    default: return 0;
  }
  return components * bytes;
}
/// Completeness of a framebuffer whose attachments are made: an error naming `label` and the status.
Result<void> checkFramebufferComplete(const Framebuffer& framebuffer, std::string_view label);
/// "GL_OUT_OF_MEMORY", ..., or the value in hex for an error GL 4.5 does not define.
std::string glErrorName(GLenum error);
/// The label GL object `id` of `kind` (GL_TEXTURE, GL_FRAMEBUFFER, ...) was given, empty without one.
std::string objectLabel(GLenum kind, GLuint id);
/// "2048.1 MiB": memory sizes in messages.
std::string formatBytes(std::size_t bytes);
Texture createTexture2DArray(std::string_view label, GLenum internalFormat, int width, int height, int layers,
                             int levels);
/// createTexture2DArray (one level) for frame-size storage that may not fit, checked as tryCreateTexture2D.
Result<Texture> tryCreateTexture2DArray(std::string_view label, GLenum internalFormat, int width, int height, int layers);
/// Cube map (or cube map array of `layers` cubes when layers > 0) with immutable storage.
Texture createTextureCube(std::string_view label, GLenum internalFormat, int size, int layers = 0, int levels = 1);
/// A buffer texture viewing all of `buffer` as texels of `internalFormat` (no copy): shaders gather
/// from it with texelFetch, which llvmpipe vectorizes, where an SSBO read becomes a per-lane loop.
Texture createBufferTexture(std::string_view label, GLenum internalFormat, const Buffer& buffer);
Framebuffer createFramebuffer(std::string_view label);
VertexArray createVertexArray(std::string_view label);
Shader createShader(std::string_view label, GLenum stage);
Program createProgram(std::string_view label);

/// Reverses the order of the `height` rows of `pixels` (`width` each) in place: GL reads rows bottom-up, the
/// ray pass wants row 0 at the top.
template <class T>
void flipRows(std::vector<T>& pixels, int width, int height) {
  const auto row = static_cast<std::ptrdiff_t>(width);
  for (std::ptrdiff_t y = 0; y < height / 2; ++y)
    std::swap_ranges(pixels.begin() + y * row, pixels.begin() + (y + 1) * row, pixels.begin() + (height - 1 - y) * row);
}

/// Reads the `width` × `height` colour target of `fbo` as `channel` gives it (one T per texel, tightly
/// packed) into `pixels`, row 0 at the top: the ray pass's read-backs of the ids and the shadow proofs.
template <class T>
void readTopDown(const Framebuffer& fbo, const ChannelFormat& channel, int width, int height, std::vector<T>& pixels) {
  assert(sizeof(T) == texelBytes(channel.internal) && "readTopDown: one T per texel of the channel");
  pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, channel.transfer, channel.type, pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  flipRows(pixels, width, height);
}

/// Nearest or linear sampling with clamp-to-edge, set on the texture itself (no sampler objects).
void setSampling(const Texture& texture, GLenum minFilter, GLenum magFilter);

}  // namespace tandem::gl
