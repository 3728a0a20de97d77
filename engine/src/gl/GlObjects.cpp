#include <atomic>
#include <algorithm>
#include "gl/GlObjects.h"

#include <algorithm>
#include <cassert>
#include <string>

namespace tandem::gl {

namespace {
std::atomic<long long> gLiveObjects{0};
}
void detail::countObject(int delta) { gLiveObjects += delta; }
std::size_t liveObjectCount() { return static_cast<std::size_t>(std::max<long long>(0, gLiveObjects.load())); }

void BufferTraits::destroy(GLuint id) { glDeleteBuffers(1, &id); }
void TextureTraits::destroy(GLuint id) { glDeleteTextures(1, &id); }
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

Texture createTexture2DArray(std::string_view name, GLenum internalFormat, int width, int height, int layers,
                             int levels) {
  assert(width > 0 && height > 0 && layers > 0 && levels > 0 && "createTexture2DArray: empty texture");
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  label(GL_TEXTURE, id, name);
  glTextureStorage3D(id, levels, internalFormat, width, height, layers);
  return Texture(id);
}

Texture createTextureCube(std::string_view name, GLenum internalFormat, int size, int layers) {
  assert(size > 0 && layers >= 0 && "createTextureCube: empty texture");
  GLuint id = 0;
  glCreateTextures(layers > 0 ? GL_TEXTURE_CUBE_MAP_ARRAY : GL_TEXTURE_CUBE_MAP, 1, &id);
  label(GL_TEXTURE, id, name);
  if (layers > 0) glTextureStorage3D(id, 1, internalFormat, size, size, 6 * layers);
  else glTextureStorage2D(id, 1, internalFormat, size, size);
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

}  // namespace tandem::gl
