#include "gl/PixelReadback.h"

#include <cassert>
#include <string>

#include "tandem/Log.h"

namespace tandem::gl {

PixelReadback& PixelReadback::operator=(PixelReadback&& other) noexcept {
  if (this != &other) {
    drop();
    buffer_ = std::move(other.buffer_);
    mapped_ = std::exchange(other.mapped_, nullptr);
    bytes_ = std::exchange(other.bytes_, 0);
    fallback_ = std::move(other.fallback_);
    fence_ = std::exchange(other.fence_, nullptr);
    pending_ = std::exchange(other.pending_, false);
    width_ = other.width_;
    height_ = other.height_;
    texelBytes_ = other.texelBytes_;
  }
  return *this;
}

void PixelReadback::cancel() {
  if (fence_) glDeleteSync(fence_);
  fence_ = nullptr;
  pending_ = false;
}

void PixelReadback::drop() {
  cancel();
  if (buffer_ && mapped_) glUnmapNamedBuffer(buffer_.id());
  mapped_ = nullptr;
  buffer_.reset();
  bytes_ = 0;
  fallback_ = {};
  refused_ = 0;
}

bool PixelReadback::makeBuffer(std::size_t bytes) {
  // Mapped once for good (persistent), coherent so that what the GL wrote is visible once its fence is
  // passed; client storage: the CPU reads it, the GPU only writes it. Errors pending from elsewhere are not
  // this buffer's: logged and cleared first (as tryCreateTexture2D does).
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError())
    logError("GL error before the read-back buffer: " + glErrorName(e));
  GLuint id = 0;
  glCreateBuffers(1, &id);
  const std::string name = "pixel read-back";
  glObjectLabel(GL_BUFFER, id, static_cast<GLsizei>(name.size()), name.data());
  constexpr GLbitfield kMap = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), nullptr, kMap | GL_CLIENT_STORAGE_BIT);
  buffer_ = Buffer(id);
  const GLenum stored = glGetError();
  mapped_ = stored == GL_NO_ERROR ? glMapNamedBufferRange(id, 0, static_cast<GLsizeiptr>(bytes), kMap) : nullptr;
  if (!mapped_) {
    logWarning("the read-back buffer (" + formatBytes(bytes) + ") was refused (" +
               glErrorName(stored != GL_NO_ERROR ? stored : glGetError()) + "): reading into client memory");
    buffer_.reset();
    return false;
  }
  bytes_ = bytes;
  return true;
}

void PixelReadback::start(const Framebuffer& fbo, const ChannelFormat& channel, int width, int height) {
  assert(width > 0 && height > 0 && "PixelReadback::start: an empty target");
  cancel();
  texelBytes_ = texelBytes(channel.internal);
  width_ = width;
  height_ = height;
  const std::size_t need = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * texelBytes_;
  // Made again larger on need, and smaller where a frame needs under a quarter of it (a frame made much smaller
  // does not keep the largest one's memory: cost follows the settings).
  if (need > bytes_ || need < bytes_ / 4) {
    // A buffer once refused at this size or less is not asked for again until drop() or retry().
    bool made = false;
    if (refused_ == 0 || need < refused_) {
      drop();
      made = makeBuffer(need);
      if (!made) refused_ = need;
    }
    if (!made) {
      pending_ = true;
      fallback_.resize(need);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo.id());
      glPixelStorei(GL_PACK_ALIGNMENT, 4);
      glReadPixels(0, 0, width, height, channel.transfer, channel.type, fallback_.data());
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      return;
    }
  }
  pending_ = true;
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo.id());
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, channel.transfer, channel.type, nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  fence_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // the copy goes to the GPU now, to run while the caller waits for other things
}

void PixelReadback::wait() {
  pending_ = false;
  if (!fence_) return;  // read at once into client memory
  // As long as it takes (the copy is the frame's own: there is nothing else to do meanwhile).
  GLenum status = glClientWaitSync(fence_, GL_SYNC_FLUSH_COMMANDS_BIT, 0);
  while (status == GL_TIMEOUT_EXPIRED) status = glClientWaitSync(fence_, 0, 1'000'000'000);
  glDeleteSync(fence_);
  fence_ = nullptr;
  if (status == GL_WAIT_FAILED) {
    // Not expected from a valid fence; the whole GL finished instead, after which the coherent mapping
    // holds the copy.
    logError("the read-back's fence wait failed: " + glErrorName(glGetError()) + "; waiting for the whole GL");
    glFinish();
  }
}

}  // namespace tandem::gl
