#include "gl/VisibilityPass.h"

#include <algorithm>
#include <cassert>

#include <glm/gtc/type_ptr.hpp>

#include "gl/Bindings.h"
#include "gl/FeedbackLoop.h"
#include "gl/Program.h"

namespace tandem::gl {

Result<VisibilityPass> VisibilityPass::create() {
  auto program = buildProgram("visibility", {{GL_VERTEX_SHADER, "shaders/visibility.vert"},
                                             {GL_FRAGMENT_SHADER, "shaders/visibility.frag"}});
  if (!program) return program.error();
  auto masked = buildProgram("visibility (alpha mask)", {{GL_VERTEX_SHADER, "shaders/visibility.vert"},
                                                         {GL_FRAGMENT_SHADER, "shaders/visibility.frag"}},
                             "#define TD_ALPHA_MASK 1\n");
  if (!masked) return masked.error();
  VisibilityPass pass;
  pass.program_ = std::move(*program);
  pass.maskProgram_ = std::move(*masked);
  return pass;
}

Result<void> VisibilityPass::resize(int width, int height) {
  assert(width > 0 && height > 0 && "VisibilityPass::resize: empty frame");
  if (width == width_ && height == height_) return {};
  releaseTargets();  // the old targets first: they may be what keeps the new ones from fitting
  auto ids = tryCreateTexture2D("gbuffer ids", kChannelIds.internal, width, height);
  if (!ids) return ids.error();
  auto depth = tryCreateTexture2D("gbuffer depth", kChannelDepth.internal, width, height);
  if (!depth) return depth.error();
  setSampling(*ids, GL_NEAREST, GL_NEAREST);
  setSampling(*depth, GL_NEAREST, GL_NEAREST);
  Framebuffer fbo = createFramebuffer("gbuffer");
  glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, ids->id(), 0);
  glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
  glNamedFramebufferDrawBuffer(fbo.id(), GL_COLOR_ATTACHMENT0);
  glNamedFramebufferReadBuffer(fbo.id(), GL_COLOR_ATTACHMENT0);
  if (auto complete = checkFramebufferComplete(fbo, "gbuffer"); !complete) return complete;
  ids_ = std::move(*ids);
  depth_ = std::move(*depth);
  fbo_ = std::move(fbo);
  width_ = width;
  height_ = height;
  return {};
}

void VisibilityPass::release() {
  idReadback_.drop();
  releaseTargets();
}

void VisibilityPass::releaseTargets() {
  idReadback_.cancel();
  idReadback_.retry();
  resolveFbo_.reset();
  exactHits_.reset();
  fbo_.reset();
  ids_.reset();
  depth_.reset();
  width_ = height_ = 0;
}

std::size_t VisibilityPass::targetBytes(int width, int height) {
  return (texelBytes(kChannelIds.internal) + texelBytes(kChannelDepth.internal)) * static_cast<std::size_t>(width) *
         static_cast<std::size_t>(height);
}

void VisibilityPass::render(const GpuScene& scene, const Camera& camera) {
  assert(width_ > 0 && "VisibilityPass::render before resize");
  renderInto(fbo_.id(), width_, height_, scene, camera);
}

void VisibilityPass::renderInto(GLuint framebuffer, int width, int height, const GpuScene& scene,
                                const Camera& camera, std::optional<std::uint32_t> excluded,
                                GpuScene::Instances which, bool clear,
                                const std::vector<std::uint8_t>* seen, const Texture* peelBehind) const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  // Reversed-Z: near → 1, far → 0 with [0, 1] clip depth, so float depth keeps its precision far away.
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);  // faces culled by the material's sidedness, in GpuScene::draw
  if (clear) {
    const GLuint zeroIds[4] = {0, 0, 0, 0};
    const GLfloat farDepth = 0.0f;
    glClearNamedFramebufferuiv(framebuffer, GL_COLOR, 0, zeroIds);  // no effect on a depth-only target
    glClearNamedFramebufferfv(framebuffer, GL_DEPTH, 0, &farDepth);
  }

  glm::mat4 viewFromWorld = camera.viewFromWorld();
  // The rotation part of viewFromWorld applied to camera-relative positions equals viewFromWorld.
  glm::mat4 viewRotation = glm::mat4(glm::mat3(viewFromWorld));
  glm::mat4 clipFromWorldRelative = camera.clipFromView(glm::ivec2(width, height)) * viewRotation;
  // Scenes with MASK materials get the variant that discards; others keep early depth testing.
  GLuint program = scene.features().alphaMask ? maskProgram_.id() : program_.id();
  if (peelBehind) {
    Program& peel = peelPrograms_[scene.features().alphaMask ? 1 : 0];
    if (!peel) {
      auto built = buildProgram("visibility (peel)", {{GL_VERTEX_SHADER, "shaders/visibility.vert"},
                                                      {GL_FRAGMENT_SHADER, "shaders/visibility.frag"}},
                                scene.features().alphaMask ? "#define TD_PEEL 1\n#define TD_ALPHA_MASK 1\n"
                                                           : "#define TD_PEEL 1\n");
      // create() compiled the same source without it; a variant that fails is a shader bug.
      assert(built.ok() && "visibility.frag's peel variant failed to compile");
      if (built) peel = std::move(*built);
    }
    program = peel.id();
    glBindTextureUnit(kUnitPeelDepth, peelBehind->id());
  }
  glUseProgram(program);
  glProgramUniformMatrix4fv(program, TD_LOC_CLIP_FROM_WORLD_RELATIVE, 1, GL_FALSE, glm::value_ptr(clipFromWorldRelative));
  glProgramUniform3fv(program, TD_LOC_VISIBILITY_CAMERA_POS, 1, glm::value_ptr(camera.posW));
  glProgramUniform1ui(program, TD_LOC_EXCLUDED_PLUS_ONE, excluded ? *excluded + 1u : 0u);
  scene.bind(2, 3);
  assertNoFeedbackLoop("visibility");
  scene.draw(which, seen);
  if (peelBehind) glBindTextureUnit(kUnitPeelDepth, 0);  // it is drawn into next: no feedback loop left bound
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

static_assert(TD_EXACT_TRIANGLE == kExactTriangle, "bindings.glsl and core/ResolvedPixel.h name one marker");

Result<void> VisibilityPass::patch(std::span<const ResolvedPixel> pixels) {
  assert(width_ > 0 && "VisibilityPass::patch before resize");
  if (pixels.empty()) return {};
  if (!resolveProgram_) {
    auto program = buildProgram("resolve patch", {{GL_VERTEX_SHADER, "shaders/resolve.vert"},
                                                  {GL_FRAGMENT_SHADER, "shaders/resolve.frag"}});
    if (!program) return program.error();
    resolveProgram_ = std::move(*program);
    emptyVao_ = createVertexArray("resolve patch");
  }
  if (!resolveFbo_) {
    auto hits = tryCreateTexture2D("gbuffer exact hits", kChannelExactHits.internal, width_, height_);
    if (!hits) return hits.error();
    setSampling(*hits, GL_NEAREST, GL_NEAREST);
    Framebuffer fbo = createFramebuffer("gbuffer resolve");
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, ids_.id(), 0);
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT1, hits->id(), 0);
    glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(fbo.id(), 2, buffers);
    if (auto complete = checkFramebufferComplete(fbo, "gbuffer resolve"); !complete) return complete;
    exactHits_ = std::move(*hits);
    resolveFbo_ = std::move(fbo);
  }
  const std::size_t bytes = pixels.size_bytes();
  if (bytes > resolvedCapacity_) {
    // Grown by half again, so a view that slowly shows more of a solid does not reallocate every frame.
    resolvedCapacity_ = std::max(bytes, resolvedCapacity_ + resolvedCapacity_ / 2);
    resolved_ = createBuffer("resolved pixels", resolvedCapacity_, nullptr);
  }
  glNamedBufferSubData(resolved_.id(), 0, static_cast<GLsizeiptr>(bytes), pixels.data());
  glBindFramebuffer(GL_FRAMEBUFFER, resolveFbo_.id());
  glViewport(0, 0, width_, height_);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  // Depth writes need the test on; every point replaces what the raster left there.
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glPointSize(1.0f);
  glUseProgram(resolveProgram_.id());
  glProgramUniform2i(resolveProgram_.id(), TD_LOC_RESOLVE_FRAME_SIZE, width_, height_);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindResolved, resolved_.id());
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("resolve patch");
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(pixels.size()));
  glBindVertexArray(0);
  glUseProgram(0);
  glDepthFunc(GL_GREATER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return {};
}

static_assert(kChannelIds.transfer == GL_RG_INTEGER && kChannelIds.type == GL_UNSIGNED_INT,
              "ids travel as one glm::uvec2 per pixel (rt::VisibilityBuffer)");


}  // namespace tandem::gl
