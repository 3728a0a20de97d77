#include "gl/GlObjects.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cstdio>
#include <string>

#include "tandem/Log.h"

namespace tandem::gl {

namespace {
std::atomic<long long> gLiveObjects{0};
}
void detail::countObject(int delta) { gLiveObjects += delta; }
std::size_t liveObjectCount() { return static_cast<std::size_t>(std::max<long long>(0, gLiveObjects.load())); }

void BufferTraits::destroy(GLuint id) { glDeleteBuffers(1, &id); }
void TextureTraits::destroy(GLuint id) { glDeleteTextures(1, &id); }
void SamplerTraits::destroy(GLuint id) { glDeleteSamplers(1, &id); }
void FramebufferTraits::destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
void VertexArrayTraits::destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
void ShaderTraits::destroy(GLuint id) { glDeleteShader(id); }
void ProgramTraits::destroy(GLuint id) { glDeleteProgram(id); }

namespace {
void label(GLenum kind, GLuint id, std::string_view name) {
  glObjectLabel(kind, id, static_cast<GLsizei>(name.size()), name.data());
}
}  // namespace

Buffer createBuffer(std::string_view name, std::size_t bytes, const void* data) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  label(GL_BUFFER, id, name);
  // Storage is at least 16 bytes (zero-size buffers cannot be bound, and a vec4 read must stay inside);
  // GL copies the whole storage size from `data`, so a smaller source goes in through a sub-data upload
  // (AddressSanitizer caught llvmpipe reading past a 4-byte index vector).
  std::size_t storage = std::max<std::size_t>(bytes, 16);
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(storage), storage == bytes ? data : nullptr,
                       GL_DYNAMIC_STORAGE_BIT);
  if (storage != bytes && bytes > 0 && data)
    glNamedBufferSubData(id, 0, static_cast<GLsizeiptr>(bytes), data);
  return Buffer(id);
}

Texture createTexture2D(std::string_view name, GLenum internalFormat, int width, int height, int levels) {
  assert(width > 0 && height > 0 && levels > 0 && "createTexture2D: empty texture");
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  label(GL_TEXTURE, id, name);
  glTextureStorage2D(id, levels, internalFormat, width, height);
  return Texture(id);
}

namespace {

std::string hexValue(unsigned value) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%04X", value);
  return buf;
}

const char* formatName(GLenum internalFormat) {
  switch (internalFormat) {
    case GL_RGBA32F: return "GL_RGBA32F";
    case GL_RGBA8: return "GL_RGBA8";
    case GL_RG32UI: return "GL_RG32UI";
    case GL_R32UI: return "GL_R32UI";
    case GL_DEPTH_COMPONENT32F: return "GL_DEPTH_COMPONENT32F";
    case GL_RGBA16F: return "GL_RGBA16F";
    default: return "?";
  }
}

}  // namespace

std::string glErrorName(GLenum error) {
  switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "GL error " + hexValue(error);
  }
}

std::string formatBytes(std::size_t bytes) {
  // MiB throughout, one decimal: a texture just over a driver's cap (2048.1 MiB) must not read as at it.
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  return buf;
}

Result<Texture> tryCreateTexture2D(std::string_view name, GLenum internalFormat, int width, int height) {
  assert(width > 0 && height > 0 && "tryCreateTexture2D: empty texture");
  // Bounded: a lost context may keep reporting itself.
  for (int i = 0; i < 16; ++i) {
    GLenum pending = glGetError();
    if (pending == GL_NO_ERROR) break;
    logWarning("GL: " + glErrorName(pending) + " was pending before allocating '" + std::string(name) + "'");
  }
  Texture texture = createTexture2D(name, internalFormat, width, height);
  GLenum error = glGetError();
  if (error == GL_NO_ERROR) return texture;
  std::size_t bytes = texelBytes(internalFormat) * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  return Error{"GL texture '" + std::string(name) + "' (" + std::to_string(width) + "x" + std::to_string(height) + " " +
               formatName(internalFormat) + ", " + formatBytes(bytes) + "): glTextureStorage2D failed with " +
               glErrorName(error)};
}

Result<Texture> tryCreateTexture2DArray(std::string_view name, GLenum internalFormat, int width, int height, int layers) {
  assert(width > 0 && height > 0 && layers > 0 && "tryCreateTexture2DArray: empty texture");
  for (int i = 0; i < 16; ++i) {
    GLenum pending = glGetError();
    if (pending == GL_NO_ERROR) break;
    logWarning("GL: " + glErrorName(pending) + " was pending before allocating '" + std::string(name) + "'");
  }
  Texture texture = createTexture2DArray(name, internalFormat, width, height, layers, 1);
  GLenum error = glGetError();
  if (error == GL_NO_ERROR) return texture;
  std::size_t bytes = texelBytes(internalFormat) * static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                      static_cast<std::size_t>(layers);
  return Error{"GL texture '" + std::string(name) + "' (" + std::to_string(width) + "x" + std::to_string(height) + "x" +
               std::to_string(layers) + " " + formatName(internalFormat) + ", " + formatBytes(bytes) +
               "): glTextureStorage3D failed with " + glErrorName(error)};
}

Result<void> checkFramebufferComplete(const Framebuffer& framebuffer, std::string_view name) {
  GLenum status = glCheckNamedFramebufferStatus(framebuffer.id(), GL_FRAMEBUFFER);
  if (status == GL_FRAMEBUFFER_COMPLETE) return {};
  std::string what;
  switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: what = "GL_FRAMEBUFFER_UNDEFINED"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: what = "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: what = "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: what = "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: what = "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER"; break;
    case GL_FRAMEBUFFER_UNSUPPORTED: what = "GL_FRAMEBUFFER_UNSUPPORTED"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: what = "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE"; break;
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS: what = "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS"; break;
    case 0: what = "no status: glCheckNamedFramebufferStatus failed with " + glErrorName(glGetError()); break;
    default: what = "status " + hexValue(status); break;
  }
  return Error{"GL framebuffer '" + std::string(name) + "' is incomplete: " + what};
}

Texture createTexture2DArray(std::string_view name, GLenum internalFormat, int width, int height, int layers,
                             int levels) {
  assert(width > 0 && height > 0 && layers > 0 && levels > 0 && "createTexture2DArray: empty texture");
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  label(GL_TEXTURE, id, name);
  glTextureStorage3D(id, levels, internalFormat, width, height, layers);
  return Texture(id);
}

Texture createTextureCube(std::string_view name, GLenum internalFormat, int size, int layers, int levels) {
  assert(size > 0 && layers >= 0 && levels >= 1 && "createTextureCube: empty texture");
  GLuint id = 0;
  glCreateTextures(layers > 0 ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_CUBE_MAP, 1, &id);
  label(GL_TEXTURE, id, name);
  if (layers > 0) glTextureStorage3D(id, levels, internalFormat, size, size, 6 * layers);
  else glTextureStorage2D(id, levels, internalFormat, size, size);
  return Texture(id);
}

Texture createBufferTexture(std::string_view name, GLenum internalFormat, const Buffer& buffer) {
  assert(buffer && "createBufferTexture: no buffer");
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
  label(GL_TEXTURE, id, name);
  glTextureBuffer(id, internalFormat, buffer.id());
  return Texture(id);
}

Framebuffer createFramebuffer(std::string_view name) {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  label(GL_FRAMEBUFFER, id, name);
  return Framebuffer(id);
}

VertexArray createVertexArray(std::string_view name) {
  GLuint id = 0;
  glCreateVertexArrays(1, &id);
  label(GL_VERTEX_ARRAY, id, name);
  return VertexArray(id);
}

Shader createShader(std::string_view name, GLenum stage) {
  GLuint id = glCreateShader(stage);
  label(GL_SHADER, id, name);
  return Shader(id);
}

Program createProgram(std::string_view name) {
  GLuint id = glCreateProgram();
  label(GL_PROGRAM, id, name);
  return Program(id);
}

void setSampling(const Texture& texture, GLenum minFilter, GLenum magFilter) {
  glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, static_cast<GLint>(minFilter));
  glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, static_cast<GLint>(magFilter));
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

std::string objectLabel(GLenum kind, GLuint id) {
  char buf[256] = {};
  GLsizei length = 0;
  glGetObjectLabel(kind, id, sizeof buf, &length, buf);
  return std::string(buf, static_cast<std::size_t>(std::max(length, 0)));
}

}  // namespace tandem::gl
