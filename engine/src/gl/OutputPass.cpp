#include "gl/OutputPass.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include "gl/Bindings.h"
#include "gl/FeedbackLoop.h"

namespace tandem::gl {

Result<OutputPass> OutputPass::create() {
  auto toneMap = buildProgram("tonemap", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                          {GL_FRAGMENT_SHADER, "shaders/tonemap.frag"}});
  if (!toneMap) return toneMap.error();
  OutputPass pass;
  pass.toneMap_ = std::move(*toneMap);
  pass.emptyVao_ = createVertexArray("full-screen triangle (output)");
  return pass;
}

Result<void> OutputPass::resize(int width, int height) {
  assert(width > 0 && height > 0 && "OutputPass::resize: empty frame");
  if (width == width_ && height == height_) return {};
  release();  // the old targets first: they may be what keeps the new ones from fitting
  auto linear = tryCreateTexture2D("linear radiance", kChannelLinear.internal, width, height);
  if (!linear) return linear.error();
  auto display = tryCreateTexture2D("display", kChannelDisplay.internal, width, height);
  if (!display) return display.error();
  setSampling(*linear, GL_NEAREST, GL_NEAREST);
  setSampling(*display, GL_LINEAR, GL_LINEAR);
  Framebuffer linearFbo = createFramebuffer("linear radiance");
  glNamedFramebufferTexture(linearFbo.id(), GL_COLOR_ATTACHMENT0, linear->id(), 0);
  if (auto complete = checkFramebufferComplete(linearFbo, "linear radiance"); !complete) return complete;
  Framebuffer displayFbo = createFramebuffer("display");
  glNamedFramebufferTexture(displayFbo.id(), GL_COLOR_ATTACHMENT0, display->id(), 0);
  if (auto complete = checkFramebufferComplete(displayFbo, "display"); !complete) return complete;
  Framebuffer fusedFbo = createFramebuffer("linear radiance + display");
  glNamedFramebufferTexture(fusedFbo.id(), GL_COLOR_ATTACHMENT0, linear->id(), 0);
  glNamedFramebufferTexture(fusedFbo.id(), GL_COLOR_ATTACHMENT1, display->id(), 0);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fusedFbo.id(), 2, both);
  if (auto complete = checkFramebufferComplete(fusedFbo, "linear radiance + display"); !complete) return complete;
  linear_ = std::move(*linear);
  display_ = std::move(*display);
  linearFbo_ = std::move(linearFbo);
  displayFbo_ = std::move(displayFbo);
  fusedFbo_ = std::move(fusedFbo);
  width_ = width;
  height_ = height;
  return {};
}

void OutputPass::release() {
  linearFbo_.reset();
  displayFbo_.reset();
  fusedFbo_.reset();
  linear_.reset();
  display_.reset();
  width_ = height_ = 0;
}

std::size_t OutputPass::targetBytes(int width, int height) {
  return (texelBytes(kChannelLinear.internal) + texelBytes(kChannelDisplay.internal)) * static_cast<std::size_t>(width) *
         static_cast<std::size_t>(height);
}

void OutputPass::uploadLinear(const ImageF& image) {
  assert(image.width == width_ && image.height == height_ && "uploadLinear: size differs from the frame");
  // GL rows run bottom-up: upload each image row to its flipped place in one call per row's worth of data.
  std::vector<glm::vec4> rgba(static_cast<std::size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      rgba[static_cast<std::size_t>(height_ - 1 - y) * width_ + x] = glm::vec4(image.at(x, y), 1.0f);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(linear_.id(), 0, 0, 0, width_, height_, kChannelLinear.transfer, kChannelLinear.type, rgba.data());
}

void OutputPass::output(float exposure, ToneMap toneMap, DebugView view) {
  const bool radiance = isRadianceView(view);
  glBindFramebuffer(GL_FRAMEBUFFER, displayFbo_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  GLuint p = toneMap_.id();
  glProgramUniform1f(p, TD_LOC_EXPOSURE, exposure);
  glProgramUniform1i(p, TD_LOC_TONE_MAP, static_cast<int>(toneMap));
  glProgramUniform1i(p, TD_LOC_PASS_THROUGH, radiance ? 0 : 1);
  glBindTextureUnit(kUnitLinear, linear_.id());
  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("output");
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// The CPU side of the output channels is what their transfer format and type say (bindings.glsl).
static_assert(kChannelDisplay.transfer == GL_RGBA && kChannelDisplay.type == GL_UNSIGNED_BYTE,
              "the display travels as Image's 4 bytes per pixel");
static_assert(kChannelLinear.transfer == GL_RGBA && kChannelLinear.type == GL_FLOAT,
              "linear radiance travels as one glm::vec4 per pixel");

Image OutputPass::readImage() const {
  Image image;
  image.width = width_;
  image.height = height_;
  image.rgba.resize(static_cast<std::size_t>(width_) * height_ * 4);
  if (width_ == 0) return image;
  std::vector<std::uint8_t> rows(image.rgba.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, displayFbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, kChannelDisplay.transfer, kChannelDisplay.type, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  std::size_t stride = static_cast<std::size_t>(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>((height_ - 1 - y) * stride), stride,
                image.rgba.begin() + static_cast<std::ptrdiff_t>(y * stride));
  return image;
}

ImageF OutputPass::readLinear() const {
  ImageF image;
  image.width = width_;
  image.height = height_;
  image.rgb.resize(static_cast<std::size_t>(width_) * height_);
  if (width_ == 0) return image;
  std::vector<glm::vec4> rows(image.rgb.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, linearFbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, kChannelLinear.transfer, kChannelLinear.type, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      image.at(x, y) = glm::vec3(rows[static_cast<std::size_t>(height_ - 1 - y) * width_ + x]);
  return image;
}

void OutputPass::present(int framebufferWidth, int framebufferHeight) const {
  if (framebufferWidth <= 0 || framebufferHeight <= 0 || width_ == 0) return;  // minimised
  float scale = std::min(float(framebufferWidth) / float(width_), float(framebufferHeight) / float(height_));
  int w = std::max(1, static_cast<int>(std::lround(float(width_) * scale)));
  int h = std::max(1, static_cast<int>(std::lround(float(height_) * scale)));
  int x0 = (framebufferWidth - w) / 2, y0 = (framebufferHeight - h) / 2;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, framebufferWidth, framebufferHeight);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glBlitNamedFramebuffer(displayFbo_.id(), 0, 0, 0, width_, height_, x0, y0, x0 + w, y0 + h, GL_COLOR_BUFFER_BIT,
                         GL_LINEAR);
}

}  // namespace tandem::gl
