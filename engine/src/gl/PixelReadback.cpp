#include "gl/PixelReadback.h"

#include <cassert>
#include <string>

namespace tandem::gl {

PixelReadback& PixelReadback::operator=(PixelReadback&& other) noexcept {
  if (this != &other) {
    drop();
    buffer_ = std::move(other.buffer_);
    mapped_ = std::exchange(other.mapped_, nullptr);
    bytes_ = std::exchange(other.bytes_, 0);
    fence_ = std::exchange(other.fence_, nullptr);
    width_ = other.width_;
    height_ = other.height_;
    texelBytes_ = other.texelBytes_;
  }
  return *this;
}

void PixelReadback::drop() {
  if (fence_) glDeleteSync(fence_);
  fence_ = nullptr;
  if (buffer_ && mapped_) glUnmapNamedBuffer(buffer_.id());
  mapped_ = nullptr;
  buffer_.reset();
  bytes_ = 0;
}

void PixelReadback::start(const Framebuffer& fbo, const ChannelFormat& channel, int width, int height) {
  assert(width > 0 && height > 0 && "PixelReadback::start: an empty target");
  if (fence_) glDeleteSync(fence_);
  fence_ = nullptr;
  texelBytes_ = texelBytes(channel.internal);
  const std::size_t need = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * texelBytes_;
  if (need > bytes_) {
    // Mapped once for good (persistent), coherent so that what the GL wrote is visible once its fence is
    // passed; client storage: the CPU reads it, the GPU only writes it.
    drop();
    GLuint id = 0;
    glCreateBuffers(1, &id);
    const std::string name = "pixel read-back";
    glObjectLabel(GL_BUFFER, id, static_cast<GLsizei>(name.size()), name.data());
    constexpr GLbitfield kMap = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
    glNamedBufferStorage(id, static_cast<GLsizeiptr>(need), nullptr, kMap | GL_CLIENT_STORAGE_BIT);
    buffer_ = Buffer(id);
    mapped_ = glMapNamedBufferRange(id, 0, static_cast<GLsizeiptr>(need), kMap);
    assert(mapped_ && "PixelReadback: the GL refused to map the read-back buffer");
    bytes_ = need;
  }
  width_ = width;
  height_ = height;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo.id());
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, channel.transfer, channel.type, nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
}

void PixelReadback::wait() {
  // The first wait flushes the GL's commands so that the fence is reached; then as long as it takes (the
  // copy is the frame's own: there is nothing else to do meanwhile).
  GLenum status = glClientWaitSync(fence_, GL_SYNC_FLUSH_COMMANDS_BIT, 0);
  while (status == GL_TIMEOUT_EXPIRED) status = glClientWaitSync(fence_, 0, 1'000'000'000);
  assert(status != GL_WAIT_FAILED && "PixelReadback: the fence wait failed");
  glDeleteSync(fence_);
  fence_ = nullptr;
}

}  // namespace tandem::gl
