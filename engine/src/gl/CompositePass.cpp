#include "gl/CompositePass.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "gl/FeedbackLoop.h"
#include "gl/Program.h"
#include "tandem/Log.h"

namespace tandem::gl {

namespace {

// Recreates `texture` only when the size changes: the ray grid is the same every frame in practice.
Result<void> uploadGrid(Texture& texture, const char* label, GLenum internalFormat, int width, int height,
                        GLenum format, GLenum type, const void* data) {
  GLint w = 0, h = 0;
  if (texture) {
    glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_HEIGHT, &h);
  }
  if (!texture || w != width || h != height) {
    texture.reset();
    auto made = tryCreateTexture2D(label, internalFormat, width, height);
    if (!made) return made.error();
    texture = std::move(*made);
    setSampling(texture, GL_NEAREST, GL_NEAREST);
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(texture.id(), 0, 0, 0, width, height, format, type, data);
  return {};
}

}  // namespace

Result<CompositePass> CompositePass::create() {
  // The variant with every feature on: proves shade.frag compiles, so later variants cannot fail on
  // anything but a driver bug.
  auto shade = buildProgram("shade (all features)", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                                     {GL_FRAGMENT_SHADER, "shaders/shade.frag"}});
  if (!shade) return shade.error();
  auto toneMap = buildProgram("tonemap", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                          {GL_FRAGMENT_SHADER, "shaders/tonemap.frag"}});
  if (!toneMap) return toneMap.error();
  CompositePass pass;
  pass.toneMap_ = std::move(*toneMap);
  pass.emptyVao_ = createVertexArray("full-screen triangle");
  return pass;
}

Result<void> CompositePass::resize(int width, int height) {
  assert(width > 0 && height > 0 && "CompositePass::resize: empty frame");
  if (width == width_ && height == height_) return {};
  release();  // the old targets first: they may be what keeps the new ones from fitting
  auto linear = tryCreateTexture2D("linear radiance", GL_RGBA32F, width, height);
  if (!linear) return linear.error();
  auto display = tryCreateTexture2D("display", GL_RGBA8, width, height);
  if (!display) return display.error();
  setSampling(*linear, GL_NEAREST, GL_NEAREST);
  setSampling(*display, GL_LINEAR, GL_LINEAR);
  Framebuffer linearFbo = createFramebuffer("linear radiance");
  glNamedFramebufferTexture(linearFbo.id(), GL_COLOR_ATTACHMENT0, linear->id(), 0);
  if (auto complete = checkFramebufferComplete(linearFbo, "linear radiance"); !complete) return complete;
  Framebuffer displayFbo = createFramebuffer("display");
  glNamedFramebufferTexture(displayFbo.id(), GL_COLOR_ATTACHMENT0, display->id(), 0);
  if (auto complete = checkFramebufferComplete(displayFbo, "display"); !complete) return complete;
  linear_ = std::move(*linear);
  display_ = std::move(*display);
  linearFbo_ = std::move(linearFbo);
  displayFbo_ = std::move(displayFbo);
  width_ = width;
  height_ = height;
  return {};
}

void CompositePass::release() {
  linearFbo_.reset();
  displayFbo_.reset();
  linear_.reset();
  display_.reset();
  sampledDepth_.reset();  // made again at the new size by the first frame that needs it
  width_ = height_ = 0;
}

std::size_t CompositePass::targetBytes(int width, int height) {
  return (texelBytes(GL_RGBA32F) + texelBytes(GL_RGBA8)) * static_cast<std::size_t>(width) *
         static_cast<std::size_t>(height);
}

Result<void> CompositePass::uploadLightMask(int width, int height, const std::uint32_t* mask) {
  return uploadGrid(lightMask_, "ray light mask", GL_R32UI, width, height, GL_RED_INTEGER, GL_UNSIGNED_INT, mask);
}

Result<void> CompositePass::uploadReflected(int width, int height, const glm::vec4* rgba) {
  return uploadGrid(reflected_, "ray reflected", GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, rgba);
}

Result<void> CompositePass::uploadTransmitted(int width, int height, const glm::vec4* rgba) {
  return uploadGrid(transmitted_, "ray transmitted", GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, rgba);
}

void CompositePass::uploadLinear(const ImageF& image) {
  assert(image.width == width_ && image.height == height_ && "uploadLinear: size differs from the frame");
  // GL rows run bottom-up: upload each image row to its flipped place in one call per row's worth of data.
  std::vector<glm::vec4> rgba(static_cast<std::size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      rgba[static_cast<std::size_t>(height_ - 1 - y) * width_ + x] = glm::vec4(image.at(x, y), 1.0f);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(linear_.id(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba.data());
}

bool CompositePass::samplesDepth(const SceneFeatures& features, DebugView view) {
  // Toon outlines test depth in every view the variant compiles them into; the depth view shows it.
  return features.toon || view == DebugView::Depth;
}

Result<void> CompositePass::reserveSampledDepth() {
  assert(width_ > 0 && "reserveSampledDepth before resize");
  if (sampledDepth_) return {};
  auto made = tryCreateTexture2D("gbuffer depth (sampled copy)", GL_DEPTH_COMPONENT32F, width_, height_);
  if (!made) return made.error();
  sampledDepth_ = std::move(*made);
  setSampling(sampledDepth_, GL_NEAREST, GL_NEAREST);
  return {};
}

const Program& CompositePass::shadeVariant(const SceneFeatures& f, const ShadeInputs& in) {
  std::string defines = "#define TD_DEBUG_VIEW " + std::to_string(static_cast<int>(in.debugView)) +
                        "\n#define TD_RAY_INPUTS " + std::to_string(in.rayInputs) +
                        "\n#define TD_RAY_SCALED " + std::to_string(in.rayScale > 1 ? 1 : 0) +
                        "\n#define TD_USE_GOURAUD " + std::to_string(f.gouraud) +
                        "\n#define TD_USE_TOON " + std::to_string(f.toon) +
                        "\n#define TD_USE_UVS " + std::to_string(f.uvs) +
                        "\n#define TD_USE_KD_TEXTURES " + std::to_string(f.kdTextures) +
                        "\n#define TD_USE_COLORS " + std::to_string(f.colors) +
                        "\n#define TD_USE_NORMAL_MAPS " + std::to_string(f.normalMaps) +
                        "\n#define TD_USE_EMISSIVE " + std::to_string(f.emissiveTextures) +
                        "\n#define TD_USE_ALPHA_BLEND " + std::to_string(f.alphaBlend) +
                        "\n#define TD_LIGHT_COUNT " + std::to_string(f.lightCount) +
                        "\n#define TD_UNIFORM_MATERIALS " + std::to_string(f.uniformMaterials) +
                        "\n#define TD_SHADOW_MAPS " + std::to_string(in.shadowMaps ? 1 : 0) +
                        "\n#define TD_PROBES " + std::to_string(in.probes ? in.probeEffects : 0) +
                        "\n#define TD_FRESNEL_SCHLICK " + std::to_string(in.fresnel == FresnelMode::Schlick ? 1 : 0) +
                        "\n#define TD_FRESNEL_WEIGHTED " + std::to_string(in.fresnelWeighted ? 1 : 0) + "\n";
  auto found = shadeVariants_.find(defines);
  if (found != shadeVariants_.end()) return found->second;
  auto built = buildProgram("shade", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                      {GL_FRAGMENT_SHADER, "shaders/shade.frag"}}, defines);
  // create() compiled the superset of every variant; a variant that fails is a shader bug.
  assert(built.ok() && "shade.frag variant failed to compile");
  if (!built) {
    logError(built.error().message);
    return shadeVariants_.emplace(defines, Program()).first->second;
  }
  return shadeVariants_.emplace(defines, std::move(*built)).first->second;
}

void CompositePass::shade(const GpuScene& scene, const VisibilityPass& visibility, const Camera& camera,
                          const ShadeInputs& in) {
  assert(visibility.width() == width_ && visibility.height() == height_);
  shadeInto(linearFbo_.id(), width_, height_, scene, visibility.ids(), visibility.depth(),
            sampledDepth_ ? &sampledDepth_ : nullptr, camera, in);
}

void CompositePass::shadeInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids,
                              const Texture& depth, const Texture* sampledDepth, const Camera& camera,
                              const ShadeInputs& in) {
  // Background pixels never run the shader: the visibility depth is attached (read-only) and the
  // full-screen triangle at depth 0 passes only where something was drawn (reversed-Z: cleared = 0), so
  // llvmpipe's early depth test skips whole sky blocks; the clear gives them their colour. Attached
  // every call: a resized visibility pass may get its old texture name back for a new texture.
  glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth.id(), 0);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);  // fullscreen.vert's z = 0 must land on depth 0
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glm::vec4 clear(in.debugView == DebugView::Final ? in.background : glm::vec3(0.0f), 1.0f);
  glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, glm::value_ptr(clear));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);

  GLuint p = shadeVariant(scene.features(), in).id();
  float aspect = float(width) / float(height);
  glm::vec3 forward = glm::normalize(camera.targetW - camera.posW);
  glm::vec3 right = glm::normalize(glm::cross(forward, camera.upW));
  glm::vec3 up = glm::cross(right, forward);
  float halfH = camera.orthographic ? camera.orthoHeight * 0.5f : std::tan(glm::radians(camera.yFovDeg) * 0.5f);
  glm::vec3 rightScaled = right * (halfH * aspect);
  glm::vec3 upScaled = up * halfH;
  glProgramUniform3fv(p, 0, 1, glm::value_ptr(camera.posW));
  glProgramUniform3fv(p, 1, 1, glm::value_ptr(forward));
  glProgramUniform3fv(p, 2, 1, glm::value_ptr(rightScaled));
  glProgramUniform3fv(p, 3, 1, glm::value_ptr(upScaled));
  glProgramUniform1i(p, 4, camera.orthographic ? 1 : 0);
  glProgramUniform2i(p, 5, width, height);
  glProgramUniform3fv(p, 6, 1, glm::value_ptr(in.background));
  glProgramUniform3fv(p, 7, 1, glm::value_ptr(in.ambient));
  glProgramUniform1i(p, 11, in.rayScale);
  glProgramUniform2i(p, 12, std::max(in.rayWidth, 1), std::max(in.rayHeight, 1));

  scene.bind(kUnitKd, kUnitRamps);
  scene.bindShading();
  glBindTextureUnit(kUnitIds, ids.id());
  // The shader never reads the attached depth: that is a feedback loop, undefined even with depth writes
  // off (a GPU that compresses or tiles depth may hand the sampler stale or compressed data). Frames that
  // need depth read a copy; the others bind nothing there.
  const bool readsDepth = samplesDepth(scene.features(), in.debugView);
  assert((!readsDepth || sampledDepth) && "shadeInto: this variant samples depth and has no copy to read");
  if (readsDepth)
    glCopyImageSubData(depth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, sampledDepth->id(), GL_TEXTURE_2D, 0, 0, 0, 0, width,
                       height, 1);
  glBindTextureUnit(kUnitDepth, readsDepth ? sampledDepth->id() : 0);
  if (in.shadowMaps) in.shadowMaps->bind();
  if (in.probes && in.probeEffects != 0) in.probes->bind();
  glBindTextureUnit(kUnitLightMask, (in.rayInputs & kRayLightMask) ? lightMask_.id() : 0);
  glBindTextureUnit(kUnitReflected, (in.rayInputs & kRayReflected) ? reflected_.id() : 0);
  glBindTextureUnit(kUnitTransmitted, (in.rayInputs & kRayTransmitted) ? transmitted_.id() : 0);

  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("shade");
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void CompositePass::output(float exposure, ToneMap toneMap, DebugView view) {
  bool radiance = view == DebugView::Final || view == DebugView::Reflection || view == DebugView::Transmission;
  glBindFramebuffer(GL_FRAMEBUFFER, displayFbo_.id());
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  GLuint p = toneMap_.id();
  glProgramUniform1f(p, 0, exposure);
  glProgramUniform1i(p, 1, static_cast<int>(toneMap));
  glProgramUniform1i(p, 2, radiance ? 0 : 1);
  glBindTextureUnit(0, linear_.id());
  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("output");
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

Image CompositePass::readImage() const {
  Image image;
  image.width = width_;
  image.height = height_;
  image.rgba.resize(static_cast<std::size_t>(width_) * height_ * 4);
  if (width_ == 0) return image;
  std::vector<std::uint8_t> rows(image.rgba.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, displayFbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  std::size_t stride = static_cast<std::size_t>(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>((height_ - 1 - y) * stride), stride,
                image.rgba.begin() + static_cast<std::ptrdiff_t>(y * stride));
  return image;
}

ImageF CompositePass::readLinear() const {
  ImageF image;
  image.width = width_;
  image.height = height_;
  image.rgb.resize(static_cast<std::size_t>(width_) * height_);
  if (width_ == 0) return image;
  std::vector<glm::vec4> rows(image.rgb.size());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, linearFbo_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, rows.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      image.at(x, y) = glm::vec3(rows[static_cast<std::size_t>(height_ - 1 - y) * width_ + x]);
  return image;
}

void CompositePass::present(int framebufferWidth, int framebufferHeight) const {
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
