#include "gl/DenoisePass.h"

#include <algorithm>
#include <cassert>
#include <string>
#include <tuple>

#include <glm/gtc/type_ptr.hpp>

#include "gl/Bindings.h"
#include "gl/FeedbackLoop.h"
#include "gl/ShadePass.h"

namespace tandem::gl {

namespace {

constexpr ChannelFormat kNoisy{TD_CHANNEL_DENOISE_NOISY}, kExact{TD_CHANNEL_DENOISE_EXACT},
                        kGuide{TD_CHANNEL_DENOISE_GUIDE}, kMotion{TD_CHANNEL_DENOISE_MOTION},
                        kTexel{TD_CHANNEL_DENOISE_TEXEL}, kMoments{TD_CHANNEL_DENOISE_MOMENTS},
                        kRadiance{TD_CHANNEL_DENOISE_RADIANCE};
static_assert(texelBytes(kNoisy.internal) > 0 && texelBytes(kExact.internal) > 0 && texelBytes(kGuide.internal) > 0 &&
                  texelBytes(kMotion.internal) > 0 && texelBytes(kTexel.internal) > 0 &&
                  texelBytes(kMoments.internal) > 0 && texelBytes(kRadiance.internal) > 0,
              "targetBytes: a filter channel's format is missing");

Result<Program> stage(const char* label, int stage, bool moved = true) {
  return buildProgram(label, {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "shaders/denoise.frag"}},
                      "#define TD_DENOISE_STAGE " + std::to_string(stage) + "\n#define TD_DENOISE_MOVED " +
                          (moved ? "1" : "0") + "\n");
}

// A framebuffer of `colours` (attachment index, texture) and, when given, `depth`: complete, or why not.
Result<Framebuffer> framebuffer(const char* label, std::initializer_list<std::pair<int, GLuint>> colours,
                                const Texture* depth) {
  Framebuffer fbo = createFramebuffer(label);
  if (depth != nullptr) glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth->id(), 0);
  GLenum buffers[5] = {GL_NONE, GL_NONE, GL_NONE, GL_NONE, GL_NONE};
  int count = 0;
  for (const auto& [index, texture] : colours) {
    assert(index >= 0 && index < 5 && "DenoisePass: an attachment past the five it draws");
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(index), texture, 0);
    buffers[index] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(index);
    count = std::max(count, index + 1);
  }
  glNamedFramebufferDrawBuffers(fbo.id(), count, buffers);
  if (auto complete = checkFramebufferComplete(fbo, label); !complete) return complete.error();
  return fbo;
}

}  // namespace

Result<DenoisePass> DenoisePass::create() {
  DenoisePass pass;
  const std::array<std::tuple<Program*, const char*, int, bool>, 6> stages{{
      {&pass.temporal_, "denoise: temporal", 0, true},
      {&pass.temporalStill_, "denoise: temporal, nothing moved", 0, false},
      {&pass.atrous_, "denoise: a-trous", 1, true},
      {&pass.compose_, "denoise: compose", 2, true},
      {&pass.antiAlias_, "denoise: anti-aliasing", 3, true},
      {&pass.upsample_, "denoise: upsampling", 4, true},
  }};
  for (const auto& [program, label, index, moved] : stages) {
    auto built = stage(label, index, moved);
    if (!built) return built.error();
    *program = std::move(*built);
  }
  pass.emptyVao_ = createVertexArray("full-screen triangle (denoise)");
  return pass;
}

namespace {
// The ray grid's size along a side of `frame` pixels (rt/RayTracer.h: ceil(frame / scale)).
int gridSide(int frame, int scale) { return (frame + scale - 1) / scale; }
}  // namespace

std::size_t DenoisePass::targetBytes(int width, int height, int gridScale) {
  const std::size_t perPixel = texelBytes(kNoisy.internal) + texelBytes(kExact.internal) +
                               texelBytes(kGuide.internal) + texelBytes(kMotion.internal) +
                               3 * texelBytes(kRadiance.internal);
  const std::size_t perGridPixel = 2 * texelBytes(kTexel.internal) + texelBytes(kChannelDepth.internal) +
                                   2 * (texelBytes(kTexel.internal) + texelBytes(kMoments.internal));
  return perPixel * static_cast<std::size_t>(width) * static_cast<std::size_t>(height) +
         perGridPixel * static_cast<std::size_t>(gridSide(width, gridScale)) *
             static_cast<std::size_t>(gridSide(height, gridScale));
}

void DenoisePass::release() {
  targets_ = {};
  width_ = height_ = gridWidth_ = gridHeight_ = 0;
  gridScale_ = 1;
  current_ = 0;
  historyHeld_ = false;
}

Result<void> DenoisePass::reserve(int width, int height, int gridScale) {
  assert(width > 0 && height > 0 && gridScale >= 1 && "DenoisePass::reserve: empty frame");
  if (width == width_ && height == height_ && gridScale == gridScale_) return {};
  // Everything old first (it may be what keeps the new targets from fitting); a new size has no past.
  targets_ = {};
  width_ = height_ = gridWidth_ = gridHeight_ = 0;
  historyHeld_ = false;
  Targets t;
  const int gw = gridSide(width, gridScale), gh = gridSide(height, gridScale);
  struct Target {
    Texture* texture;
    ChannelFormat format;
    const char* label;
    bool grid;  // of the grid's size, else the frame's
  };
  const std::array<Target, 14> all{{
      {&t.skip, kChannelDepth, "denoise: pixels the a-trous iterations filter", true},
      {&t.noisy, kNoisy, "denoise: noisy illumination", false},
      {&t.exact, kExact, "denoise: radiance past the filter", false},
      {&t.guide, kGuide, "denoise: guide", false},
      {&t.motion, kMotion, "denoise: motion", false},
      {&t.scratchA, kTexel, "denoise: a-trous A", true},
      {&t.scratchB, kTexel, "denoise: a-trous B", true},
      {&t.filtered, kRadiance, "denoise: filtered radiance", false},
      {&t.history[0], kTexel, "denoise: history 0", true},
      {&t.history[1], kTexel, "denoise: history 1", true},
      {&t.moments[0], kMoments, "denoise: moments 0", true},
      {&t.moments[1], kMoments, "denoise: moments 1", true},
      {&t.antiAliased[0], kRadiance, "denoise: anti-aliased 0", false},
      {&t.antiAliased[1], kRadiance, "denoise: anti-aliased 1", false},
  }};
  for (const auto& [texture, format, label, grid] : all) {
    auto made = tryCreateTexture2D(label, format.internal, grid ? gw : width, grid ? gh : height);
    if (!made) return made.error();
    *texture = std::move(*made);
    setSampling(*texture, GL_NEAREST, GL_NEAREST);
    glClearTexImage(texture->id(), 0, format.transfer, format.type, nullptr);  // nothing reads what was never written
  }
  // The anti-aliasing stage reprojects its history between texels.
  for (Texture& a : t.antiAliased) {
    setSampling(a, GL_LINEAR, GL_LINEAR);
    glTextureParameteri(a.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(a.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  auto make = [&](Framebuffer& into, const char* label, std::initializer_list<std::pair<int, GLuint>> colours,
                  const Texture* depth) -> Result<void> {
    auto made = framebuffer(label, colours, depth);
    if (!made) return made.error();
    into = std::move(*made);
    return {};
  };
  // (The shade pass attaches the visibility depth itself.)
  if (auto ok = make(t.shadeFbo, "denoise: shade pass's target",
                     {{0, t.noisy.id()}, {2, t.guide.id()}, {3, t.motion.id()}, {4, t.exact.id()}}, nullptr);
      !ok)
    return ok.error();
  for (int k = 0; k < 2; ++k) {
    if (auto ok = make(t.temporalFbo[k], "denoise: temporal",
                       {{0, t.scratchA.id()}, {1, t.moments[k].id()}, {2, t.scratchB.id()}, {3, t.history[k].id()}},
                       &t.skip);
        !ok)
      return ok.error();
    if (auto ok = make(t.historyFbo[k], "denoise: history", {{0, t.history[k].id()}}, &t.skip); !ok) return ok.error();
  }
  if (auto ok = make(t.scratchAFbo, "denoise: a-trous A", {{0, t.scratchA.id()}}, &t.skip); !ok) return ok.error();
  if (auto ok = make(t.scratchBFbo, "denoise: a-trous B", {{0, t.scratchB.id()}}, &t.skip); !ok) return ok.error();
  if (auto ok = make(t.filteredFbo, "denoise: filtered", {{0, t.filtered.id()}}, nullptr); !ok) return ok.error();
  for (Framebuffer& fbo : t.outputFbo) fbo = createFramebuffer("denoise: the frame's output");
  targets_ = std::move(t);
  width_ = width;
  height_ = height;
  gridScale_ = gridScale;
  gridWidth_ = gw;
  gridHeight_ = gh;
  return {};
}

void DenoisePass::filter(const Texture& linear, const Texture& display, const Texture& ids, const Camera& camera,
                         bool history, const MovedInstances& moved, float exposure, ToneMap toneMap,
                         int maxHistory) {
  assert(holds() && "DenoisePass::filter: no targets (reserve first)");
  Targets& t = targets_;
  const int now = current_, before = 1 - current_;
  // The output's targets beside this pass's anti-aliased history, attached every frame (a texture the output
  // made again may have the old one's name).
  const GLuint out = t.outputFbo[now].id();
  glNamedFramebufferTexture(out, GL_COLOR_ATTACHMENT0, linear.id(), 0);
  glNamedFramebufferTexture(out, GL_COLOR_ATTACHMENT1, display.id(), 0);
  glNamedFramebufferTexture(out, GL_COLOR_ATTACHMENT2, t.antiAliased[now].id(), 0);
  const GLenum outputs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glNamedFramebufferDrawBuffers(out, 3, outputs);
  // Textures of the frame's size in formats the frame's passes draw into: only a driver bug refuses them.
  assert(glCheckNamedFramebufferStatus(out, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE &&
         "DenoisePass: the output's framebuffer is incomplete");
  const bool past = history && historyHeld_;
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);  // fullscreen.vert's z = 0 lands on depth 0
  glBindVertexArray(emptyVao_.id());
  // The temporal stage writes every pixel and, as depth, whether the a-trous iterations filter it (1) or it
  // has settled (0); they then run only where the depth test (0 < stored) passes; the compose (or upsampling)
  // and anti-aliasing stages run everywhere (they write the frame).
  enum class Depth { Write, Test, Off };
  const CameraVectors axes = cameraVectors(width_, height_, camera);
  // (unjittered: the jitter tilts axes.forward, not the axis the guide's depth is measured along)
  const glm::vec3 axis = glm::normalize(glm::cross(axes.up, axes.right));
  // Every unit a stage's samplers name holds a texture of their type that its framebuffer does not attach:
  // where a stage reads no iteration's input, the last frame's history; the filtered frame only for the
  // anti-aliasing stage (the stages before write it).
  auto draw = [&](const Program& program, GLuint framebuffer, int step, const Texture* input, Depth depth,
                  const char* what) {
    const bool antiAliasing = &program == &antiAlias_;
    // The temporal stage and the iterations that write filter texels run on the grid, the rest on the frame.
    const bool onGrid = &program == &temporal_ || &program == &temporalStill_ || &program == &atrous_;
    glViewport(0, 0, onGrid ? gridWidth_ : width_, onGrid ? gridHeight_ : height_);
    if (depth == Depth::Off) {
      glDisable(GL_DEPTH_TEST);
    } else {
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(depth == Depth::Write ? GL_ALWAYS : GL_LESS);
      glDepthMask(depth == Depth::Write ? GL_TRUE : GL_FALSE);
    }
    const GLuint p = program.id();
    glProgramUniform3fv(p, TD_LOC_CAMERA_RIGHT, 1, glm::value_ptr(axes.right));
    glProgramUniform3fv(p, TD_LOC_CAMERA_UP, 1, glm::value_ptr(axes.up));
    glProgramUniform3fv(p, TD_LOC_DENOISE_AXIS, 1, glm::value_ptr(axis));
    glProgramUniform1i(p, TD_LOC_ORTHOGRAPHIC, camera.orthographic ? 1 : 0);
    glProgramUniform2i(p, TD_LOC_FRAME_SIZE, width_, height_);
    glProgramUniform1i(p, TD_LOC_DENOISE_STEP, step);
    glProgramUniform1i(p, TD_LOC_DENOISE_HISTORY, past ? 1 : 0);
    glProgramUniform1f(p, TD_LOC_DENOISE_MAX_HISTORY, static_cast<float>(maxHistory));
    glProgramUniform1f(p, TD_LOC_DENOISE_EXPOSURE, exposure);
    glProgramUniform1i(p, TD_LOC_DENOISE_TONE_MAP, static_cast<int>(toneMap));
    glProgramUniform1i(p, TD_LOC_DENOISE_GRID_SCALE, gridScale_);
    glProgramUniform2i(p, TD_LOC_DENOISE_GRID_SIZE, gridWidth_, gridHeight_);
    glBindTextureUnit(TD_UNIT_DENOISE_NOISY, t.noisy.id());
    glBindTextureUnit(TD_UNIT_DENOISE_GUIDE, t.guide.id());
    glBindTextureUnit(TD_UNIT_DENOISE_MOTION, t.motion.id());
    glBindTextureUnit(TD_UNIT_DENOISE_EXACT, t.exact.id());
    glBindTextureUnit(TD_UNIT_DENOISE_HISTORY, t.history[before].id());
    glBindTextureUnit(TD_UNIT_DENOISE_MOMENTS, t.moments[before].id());
    glBindTextureUnit(TD_UNIT_DENOISE_INPUT, (input != nullptr ? *input : t.history[before]).id());
    glBindTextureUnit(TD_UNIT_DENOISE_FILTERED, (antiAliasing ? t.filtered : t.antiAliased[before]).id());
    glBindTextureUnit(TD_UNIT_DENOISE_TAA_HISTORY, t.antiAliased[before].id());
    glBindTextureUnit(TD_UNIT_DENOISE_IDS, ids.id());
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glUseProgram(p);
    assertNoFeedbackLoop(what);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  };
  // Temporal: into A (and B and the history: see above) and this frame's moments. Then the a-trous
  // iterations; the first one's result is the history the next frame reprojects (SVGF: one iteration smooths
  // it enough to reproject without carrying single-sample noise forward, more would blur it frame after
  // frame). The last iteration writes texels too (back into A: where it skips a settled pixel, A holds the
  // temporal stage's value, which is what every iteration left there), and the compose stage (or on a coarser
  // grid the upsampling) takes them to the frame: the iteration's 9 taps run only where the depth test lets
  // them. Then the anti-aliasing, into the frame.
  // The temporal stage's test of what moved (mayHaveChanged): the boxes against the area lights and the glossy
  // lobes; without boxes or anything to test them against, the variant without the test.
  const bool anyMoved = moved.boxCount > 0 && (moved.areaLightCount > 0 || moved.lobes);
  const GLuint tp = temporal_.id();
  if (anyMoved) {
    glProgramUniform3fv(tp, TD_LOC_DENOISE_CAMERA_POS, 1, glm::value_ptr(camera.posW));
    glProgramUniform2i(tp, TD_LOC_DENOISE_MOVED_COUNTS, moved.boxCount, moved.areaLightCount);
    glProgramUniform4fv(tp, TD_LOC_DENOISE_MOVED_BOXES, 2 * TD_MAX_MOVED_BOXES, glm::value_ptr(moved.boxes[0].first));
    glProgramUniform4fv(tp, TD_LOC_DENOISE_AREA_LIGHTS, kMaxLights, glm::value_ptr(moved.areaLights[0]));
    glProgramUniform1f(tp, TD_LOC_DENOISE_MOVED_REACH, moved.reach);
  }
  for (const Program* temporal : {&temporal_, &temporalStill_})
    glProgramUniform1i(temporal->id(), TD_LOC_DENOISE_LOBES_STALE, moved.lobesStale ? 1 : 0);
  draw(anyMoved ? temporal_ : temporalStill_, t.temporalFbo[now].id(), 0, nullptr, Depth::Write, "denoise: temporal");
  draw(atrous_, t.historyFbo[now].id(), 1, &t.scratchA, Depth::Test, "denoise: a-trous 1");
  draw(atrous_, t.scratchBFbo.id(), 2, &t.history[now], Depth::Test, "denoise: a-trous 2");
  draw(atrous_, t.scratchAFbo.id(), 4, &t.scratchB, Depth::Test, "denoise: a-trous 4");
  if (gridScale_ == 1) draw(compose_, t.filteredFbo.id(), 0, &t.scratchA, Depth::Off, "denoise: compose");
  else draw(upsample_, t.filteredFbo.id(), 0, &t.scratchA, Depth::Off, "denoise: upsampling");
  // (the rasterizer's offset: x right, y down; the anti-aliasing's pixels are GL rows)
  glProgramUniform2f(antiAlias_.id(), TD_LOC_DENOISE_JITTER, camera.jitterPx.x, -camera.jitterPx.y);
  draw(antiAlias_, out, 0, nullptr, Depth::Off, "denoise: anti-aliasing");
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(0);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  current_ = before;
  historyHeld_ = true;
}

}  // namespace tandem::gl
