#include "gl/ShadePass.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "core/Shading.h"
#include "gl/FeedbackLoop.h"
#include "gl/FrameLimits.h"
#include "tandem/Log.h"

namespace tandem::gl {

namespace {

// The tile's action: send its texels, zero it in the texture, or leave it.
enum class TileUpload { Keep, Clear, Send };

// Sends only the tiles that hold something and zeroes the ones that held something last time, so the
// texture ends equal to `data` (every other tile is zero in both). `resident` remembers, per tile, whether
// the texture may hold a non-zero value there (empty for a new texture, whose contents are undefined: it is
// cleared first). Without tile flags it sends everything.
void sendTiles(const Texture& texture, GridResidency& resident, ChannelFormat channel, int width, int height,
               const glm::vec4* data, const GridTiles& tiles) {
  const int tilesX = tiles.size > 0 ? (width + tiles.size - 1) / tiles.size : 0;
  const int tilesY = tiles.size > 0 ? (height + tiles.size - 1) / tiles.size : 0;
  const std::size_t count = static_cast<std::size_t>(tilesX) * static_cast<std::size_t>(tilesY);
  if (tiles.nonZero.size() != count || count == 0) {
    glTextureSubImage2D(texture.id(), 0, 0, 0, width, height, channel.transfer, channel.type, data);
    resident.mayBeNonZero.assign(count, 1);
    resident.size = tiles.size;
    return;
  }
  if (resident.mayBeNonZero.size() != count || resident.size != tiles.size) {
    glClearTexImage(texture.id(), 0, channel.transfer, channel.type, nullptr);
    resident.mayBeNonZero.assign(count, 0);
    resident.size = tiles.size;
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, width);
  for (int ty = 0; ty < tilesY; ++ty) {
    const std::size_t row = static_cast<std::size_t>(ty) * static_cast<std::size_t>(tilesX);
    auto action = [&](int tx) {
      const std::size_t i = row + static_cast<std::size_t>(tx);
      return tiles.nonZero[i] ? TileUpload::Send : resident.mayBeNonZero[i] ? TileUpload::Clear : TileUpload::Keep;
    };
    // Runs of neighbouring tiles with the same action: one call each.
    for (int tx = 0; tx < tilesX;) {
      const TileUpload a = action(tx);
      int end = tx + 1;
      while (end < tilesX && action(end) == a) ++end;
      const int x0 = tx * tiles.size, x1 = std::min(end * tiles.size, width);
      const int y0 = ty * tiles.size, y1 = std::min(y0 + tiles.size, height);
      if (a == TileUpload::Send)
        glTextureSubImage2D(texture.id(), 0, x0, y0, x1 - x0, y1 - y0, channel.transfer, channel.type,
                            data + static_cast<std::size_t>(y0) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x0));
      else if (a == TileUpload::Clear)
        glClearTexSubImage(texture.id(), 0, x0, y0, 0, x1 - x0, y1 - y0, 1, channel.transfer, channel.type, nullptr);
      tx = end;
    }
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  resident.mayBeNonZero.assign(tiles.nonZero.begin(), tiles.nonZero.end());
}

}  // namespace

Result<ShadePass> ShadePass::create() {
  // The variant with every feature on: proves shade.frag compiles, so later variants cannot fail on
  // anything but a driver bug.
  auto shade = buildProgram("shade (all features)", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                                     {GL_FRAGMENT_SHADER, "shaders/shade.frag"}});
  if (!shade) return shade.error();
  ShadePass pass;
  auto sky = buildProgram("sky", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "shaders/sky.frag"}});
  if (!sky) return sky.error();
  pass.sky_ = std::move(*sky);
  pass.emptyVao_ = createVertexArray("full-screen triangle (shade)");
  pass.depthSkipsSky_ = queryFrameLimits().software;
  return pass;
}

// shade.frag's light loop and the shadow-mask pass call each light by a constant index, 0 to 7.
static_assert(TD_MAX_LIGHTS == 8, "shade.frag calls each of the 8 direct lights by a constant index");

Result<int> ShadePass::uploadRays(int width, int height, const RayGrid& grid) {
  int held = 0;
  for (const RayChannel& c : kRayChannels) {
    const RayGridData& d = grid[static_cast<std::size_t>(c.id)];
    if (d.texels == nullptr || d.layers < 1) continue;
    GridTexture& g = rayGrid_[static_cast<std::size_t>(c.id)];
    const int layers = c.perAreaLight ? d.layers : 1;
    // Made again only when the grid's size (or the area lights' count) changes: in practice, never in play.
    if (!g.texture || g.width != width || g.height != height || g.layers != layers) {
      g = GridTexture{};  // its residency too: a new texture holds nothing known
      auto made = c.perAreaLight ? tryCreateTexture2DArray(c.label, c.format.internal, width, height, layers)
                                 : tryCreateTexture2D(c.label, c.format.internal, width, height);
      if (!made) return made.error();
      g.texture = std::move(*made);
      setSampling(g.texture, GL_NEAREST, GL_NEAREST);
      g.width = width;
      g.height = height;
      g.layers = layers;
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows tightly packed, whatever the texel size
    if (c.tiled)
      sendTiles(g.texture, g.resident, c.format, width, height, static_cast<const glm::vec4*>(d.texels), d.tiles);
    else if (c.perAreaLight)
      glTextureSubImage3D(g.texture.id(), 0, 0, 0, 0, width, height, layers, c.format.transfer, c.format.type, d.texels);
    else
      glTextureSubImage2D(g.texture.id(), 0, 0, 0, width, height, c.format.transfer, c.format.type, d.texels);
    held |= c.input;
  }
  return held;
}

bool ShadePass::samplesDepth(const SceneFeatures& features, DebugView view) {
  // Toon outlines test depth in every view the variant compiles them into; the depth view shows it.
  return features.toon || view == DebugView::Depth;
}

Result<void> ShadePass::reserveSampledDepth(int width, int height) {
  assert(width > 0 && height > 0 && "reserveSampledDepth: empty frame");
  if (sampledDepth_) {
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(sampledDepth_.id(), 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(sampledDepth_.id(), 0, GL_TEXTURE_HEIGHT, &h);
    if (w == width && h == height) return {};
    sampledDepth_.reset();
  }
  auto made = tryCreateTexture2D("gbuffer depth (sampled copy)", kChannelDepth.internal, width, height);
  if (!made) return made.error();
  sampledDepth_ = std::move(*made);
  setSampling(sampledDepth_, GL_NEAREST, GL_NEAREST);
  return {};
}

void ShadePass::releaseFrame() { sampledDepth_.reset(); }

const Program& ShadePass::variant(const SceneFeatures& f, const ShadeInputs& in, Role role) {
  // The pass that reads the maps: the frame's (per pixel) or the shadow-mask pass (whose inputs have no
  // view, rays, probes or display: drawShadowMask). The frame's pass after a mask reads the mask instead.
  const bool maps = in.shadowMaps != nullptr && role != Role::ShadeWithMask;
  const bool mask = role == Role::ShadowMask;
  ShadeVariant v;
  v.debugView = in.debugView;
  v.shadowMaskPass = mask;
  v.shadowMask = role == Role::ShadeWithMask;
  v.rayInputs = in.rayChannels;
  v.rayScaled = in.rayScale > 1;
  v.gouraud = f.gouraud;
  v.toon = f.toon;
  v.uvs = f.uvs;
  v.kdTextures = f.kdTextures;
  v.colors = f.colors;
  v.normalMaps = f.normalMaps;
  v.emissive = f.emissiveTextures;
  v.alphaBlend = f.alphaBlend;
  v.lightCount = f.lightCount;
  // The map kinds matter only with shadow maps: without them a spot whose cone crosses kMaxSpotMapDeg
  // must not compile another variant.
  v.lightKinds = maps ? f.lightKinds : f.lightKinds & 0x33333333u;
  v.areaLights = f.areaLights;
  v.uniformMaterials = f.uniformMaterials;
  v.shadowMaps = maps;
  v.softShadows = maps && in.softShadows;
  v.probes = in.probeCubes ? in.probeEffects : 0;
  v.fresnelSchlick = in.fresnel == FresnelMode::Schlick;
  v.fresnelWeighted = in.fresnelWeighted;
  v.fusedOutput = in.fusedOutput;
  v.denoiseGuides = in.denoiseGuides;
  v.radiosity = in.radiosity;
  v.exact = f.exact;
  v.procedural = f.procedural;
  v.environment = f.environment;
  v.environmentAmbient = f.environmentAmbient;
  v.distanceAlpha = in.distanceInAlpha;
  auto found = variants_.find(v);
  if (found != variants_.end()) return found->second;
  auto built = buildProgram("shade", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                      {GL_FRAGMENT_SHADER, "shaders/shade.frag"}}, v.defines());
  // create() compiled the superset of every variant; a variant that fails is a shader bug.
  assert(built.ok() && "shade.frag variant failed to compile");
  if (!built) {
    logError(built.error().message);
    return variants_.emplace(v, Program()).first->second;
  }
  return variants_.emplace(v, std::move(*built)).first->second;
}

void ShadePass::shade(GLuint framebuffer, const GpuScene& scene, const VisibilityPass& visibility,
                      const Camera& camera, const ShadeInputs& in) {
  ShadeInputs frame = in;
  frame.exactHits = visibility.exactHits() ? &visibility.exactHits() : nullptr;
  Role role = Role::Shade;
  if (frame.shadowMaps && frame.rayScale > 1) {
    // The ray grid (rt/RayTracer.h): ceil(W/s) × ceil(H/s), the rays' own when there are any.
    const int gw = (visibility.width() + frame.rayScale - 1) / frame.rayScale;
    const int gh = (visibility.height() + frame.rayScale - 1) / frame.rayScale;
    assert((frame.rayWidth == 0 || (frame.rayWidth == gw && frame.rayHeight == gh)) && "shade: a ray grid of another size");
    if (drawShadowMask(scene, visibility, camera, frame, gw, gh)) {
      role = Role::ShadeWithMask;
      frame.rayWidth = gw;
      frame.rayHeight = gh;
    }
  }
  draw(framebuffer, visibility.width(), visibility.height(), scene, visibility.ids(), visibility.depth(),
       sampledDepth_ ? &sampledDepth_ : nullptr, camera, frame, role);
}

bool ShadePass::drawShadowMask(const GpuScene& scene, const VisibilityPass& visibility, const Camera& camera,
                               const ShadeInputs& in, int gridWidth, int gridHeight) {
  if (!shadowMask_ || maskWidth_ != gridWidth || maskHeight_ != gridHeight) {
    shadowMask_.reset();
    shadowMaskFbo_.reset();
    maskWidth_ = maskHeight_ = 0;
    auto made = tryCreateTexture2DArray("raster shadow mask", kChannelShadowMask.internal, gridWidth, gridHeight, 2);
    if (!made) {
      logError(made.error().message);  // the frame falls back to a lookup per pixel: slower, the same shadows
      return false;
    }
    shadowMask_ = std::move(*made);
    setSampling(shadowMask_, GL_NEAREST, GL_NEAREST);
    shadowMaskFbo_ = createFramebuffer("raster shadow mask");
    glNamedFramebufferTextureLayer(shadowMaskFbo_.id(), GL_COLOR_ATTACHMENT0, shadowMask_.id(), 0, 0);
    glNamedFramebufferTextureLayer(shadowMaskFbo_.id(), GL_COLOR_ATTACHMENT1, shadowMask_.id(), 0, 1);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(shadowMaskFbo_.id(), 2, buffers);
    if (auto complete = checkFramebufferComplete(shadowMaskFbo_, "raster shadow mask"); !complete) {
      logError(complete.error().message);
      shadowMask_.reset();
      shadowMaskFbo_.reset();
      return false;
    }
    maskWidth_ = gridWidth;
    maskHeight_ = gridHeight;
  }
  // Every grid pixel is written (the sky's as visible): no depth test, no clear.
  glBindFramebuffer(GL_FRAMEBUFFER, shadowMaskFbo_.id());
  glViewport(0, 0, gridWidth, gridHeight);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  // The mask pass draws visibility only: no view, rays, probes, radiosity or display in its variant.
  ShadeInputs grid = in;
  grid.rayWidth = gridWidth;
  grid.rayHeight = gridHeight;
  grid.rayChannels = grid.rayInputs = 0;
  grid.debugView = DebugView::Final;
  grid.probeCubes = nullptr;
  grid.probeEffects = 0;
  grid.radiosity = false;
  grid.fusedOutput = false;
  grid.denoiseGuides = false;
  GLuint p = variant(scene.features(), grid, Role::ShadowMask).id();
  setUp(p, visibility.width(), visibility.height(), scene, visibility.ids(), camera, grid);
  in.shadowMaps->bind(placeholders_);
  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("shadow mask");
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return true;
}

void ShadePass::shadeInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids,
                          const Texture& depth, const Texture* sampledDepth, const Camera& camera,
                          const ShadeInputs& in) {
  draw(framebuffer, width, height, scene, ids, depth, sampledDepth, camera, in, Role::Shade);
}

CameraVectors cameraVectors(int width, int height, const Camera& camera) {
  float aspect = float(width) / float(height);
  glm::vec3 forward = glm::normalize(camera.targetW - camera.posW);
  glm::vec3 right = glm::normalize(glm::cross(forward, camera.upW));
  glm::vec3 up = glm::cross(right, forward);
  float halfH = camera.orthographic ? camera.orthoHeight * 0.5f : std::tan(glm::radians(camera.yFovDeg) * 0.5f);
  glm::vec3 rightScaled = right * (halfH * aspect);
  glm::vec3 upScaled = up * halfH;
  // The camera's sub-pixel jitter shifts every pixel's image-plane point by the same amount: folded into
  // the forward vector (perspective) or the origin (orthographic), so cameraRay itself stays as it is.
  const glm::vec3 jitterShift = rightScaled * (2.0f * camera.jitterPx.x / float(width)) -
                                upScaled * (2.0f * camera.jitterPx.y / float(height));
  CameraVectors v;
  v.origin = camera.orthographic ? camera.posW + jitterShift : camera.posW;
  v.forward = camera.orthographic ? forward : forward + jitterShift;
  v.right = rightScaled;
  v.up = upScaled;
  return v;
}

void setCameraUniforms(GLuint p, int width, int height, const Camera& camera) {
  const CameraVectors v = cameraVectors(width, height, camera);
  glProgramUniform3fv(p, TD_LOC_CAMERA_POS, 1, glm::value_ptr(v.origin));
  glProgramUniform3fv(p, TD_LOC_CAMERA_FORWARD, 1, glm::value_ptr(v.forward));
  glProgramUniform3fv(p, TD_LOC_CAMERA_RIGHT, 1, glm::value_ptr(v.right));
  glProgramUniform3fv(p, TD_LOC_CAMERA_UP, 1, glm::value_ptr(v.up));
  glProgramUniform1i(p, TD_LOC_ORTHOGRAPHIC, camera.orthographic ? 1 : 0);
  glProgramUniform2i(p, TD_LOC_FRAME_SIZE, width, height);
}

void ShadePass::setEnvironment(GLuint p, const GpuScene& scene, const ShadeInputs& in) {
  glProgramUniform3fv(p, TD_LOC_BACKGROUND, 1, glm::value_ptr(in.background));
  const EnvironmentLookup& env = scene.environment();
  glProgramUniform1i(p, TD_LOC_ENV_KIND, env.kind());
  glProgramUniform4f(p, TD_LOC_ENV_PARAMS, env.turn().x, env.turn().y, env.mapScale(), env.lightsAmbient() ? 1.0f : 0.0f);
  glProgramUniform3fv(p, TD_LOC_ENV_SKY, 3, glm::value_ptr(env.sky()[0]));
  glProgramUniform3fv(p, TD_LOC_ENV_SH, 9, glm::value_ptr(env.ambientSh()[0]));
  placeholders_.bindOr(kUnitEnvironment, scene.environmentMap(), Placeholders::Float2D);
}

void ShadePass::setUp(GLuint p, int width, int height, const GpuScene& scene, const Texture& ids, const Camera& camera,
                      const ShadeInputs& in) {
  setCameraUniforms(p, width, height, camera);
  glProgramUniform3fv(p, TD_LOC_AMBIENT, 1, glm::value_ptr(in.ambient));
  setEnvironment(p, scene, in);
  const int lightSamples = std::clamp(in.lightSamples, 1, TD_MAX_LIGHT_SAMPLES);
  glProgramUniform1i(p, TD_LOC_LIGHT_SAMPLES, lightSamples);
  glProgramUniform1ui(p, TD_LOC_SAMPLE_BASE, in.sampleIndex * static_cast<std::uint32_t>(lightSamples));
  glProgramUniform1i(p, TD_LOC_RAY_SCALE, in.rayScale);
  glProgramUniform3fv(p, TD_LOC_RENDER_ANCHOR, 1, glm::value_ptr(scene.anchor()));
  glProgramUniform2i(p, TD_LOC_RAY_GRID_SIZE, std::max(in.rayWidth, 1), std::max(in.rayHeight, 1));
  assert((in.rayInputs & ~in.rayChannels) == 0 && "shade: a ray result the variant was not compiled for");
  glProgramUniform1i(p, TD_LOC_RAY_PRESENT, in.rayInputs & in.rayChannels);
  if (in.radiosity) {
    glProgramUniform3fv(p, TD_LOC_RADIOSITY_AMBIENT, 1, glm::value_ptr(in.radiosityAmbient));
    glProgramUniform1i(p, TD_LOC_RADIOSITY_INSTANCES, in.radiosityInstances);
  }
  scene.bind(kUnitKd, kUnitRamps);
  scene.bindShading();
  assert((!in.radiosity || scene.hasRadiosity()) && "shadeInto: radiosity asked for and none uploaded");
  if (in.radiosity) scene.bindRadiosity();
  glBindTextureUnit(kUnitIds, ids.id());
  // Every sampler the variant declares gets a texture of its type: the frame's, or a placeholder the shader
  // never reads (rayInputs and the light kinds keep it away), never an empty unit (gl/Placeholders.h).
  using P = Placeholders;
  for (const RayChannel& c : kRayChannels) {
    const bool held = (in.rayInputs & c.input) != 0 && (!c.perAreaLight || scene.features().areaLights);
    placeholders_.bindOr(c.unit, held ? rayGrid_[static_cast<std::size_t>(c.id)].texture.id() : 0, c.placeholder);
  }
  placeholders_.bindOr(kUnitExactHits, in.exactHits ? in.exactHits->id() : 0, P::Float2D);
  if (in.debugView == DebugView::Motion || in.denoiseGuides) {
    assert(in.motionInstances && "shade: motion without its instances' transforms");
    const glm::mat4 now = clipFromViewRotation(camera, width, height);
    glProgramUniformMatrix4fv(p, TD_LOC_CLIP_FROM_VIEW_ROTATION, 1, GL_FALSE, glm::value_ptr(now));
    glProgramUniformMatrix4fv(p, TD_LOC_PREVIOUS_CLIP_FROM_VIEW_ROTATION, 1, GL_FALSE,
                              glm::value_ptr(in.previousClipFromViewRotation));
    glProgramUniform3fv(p, TD_LOC_PREVIOUS_CAMERA_POS, 1, glm::value_ptr(in.previousCameraPos));
    glProgramUniform1i(p, TD_LOC_MOTION_HISTORY, in.motionHistory ? 1 : 0);
    glBindTextureUnit(kUnitMotionInstances, in.motionInstances ? in.motionInstances->id() : 0);
  }
  if (in.denoiseGuides) {
    glProgramUniform3fv(p, TD_LOC_PREVIOUS_CAMERA_FORWARD, 1, glm::value_ptr(in.previousCameraForward));
    // (the rasterizer's offset: x right, y down; gl_FragCoord's rows go up)
    glProgramUniform2f(p, TD_LOC_SAMPLE_OFFSET, camera.jitterPx.x, -camera.jitterPx.y);
  }
  if (in.debugView == DebugView::Motion) {
    placeholders_.bindOr(kUnitPreviousIds, in.previousIds ? in.previousIds->id() : 0, P::Uint2D);
    placeholders_.bindOr(kUnitPreviousDepth, in.previousDepth ? in.previousDepth->id() : 0, P::Float2D);
  }
}

void ShadePass::draw(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids,
                     const Texture& depth, const Texture* sampledDepth, const Camera& camera, const ShadeInputs& in,
                     Role role) {
  // On a software GL background pixels never run the shader: the visibility depth is attached (read-only)
  // and the full-screen triangle at depth 0 passes only where something was drawn (reversed-Z: cleared =
  // 0), so llvmpipe's early depth test skips whole sky blocks; the clear gives them their colour. Attached
  // every call: a resized visibility pass may get its old texture name back for a new texture. A GPU runs
  // the shader everywhere (its id-0 branch writes what the clear would): NVIDIA's driver (580, H200) once
  // failed that test on every pixel of a throughput-mode frame whose depth texture alternates with the
  // spare visibility pass's, the values read back intact, and an early-out per pixel costs a GPU little.
  glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth.id(), 0);
  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);  // fullscreen.vert's z = 0 must land on depth 0
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glm::vec4 clear(in.debugView == DebugView::Final ? in.background : glm::vec3(0.0f),
                  in.distanceInAlpha ? static_cast<float>(TD_DISTANCE_FAR) : 1.0f);
  glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, glm::value_ptr(clear));
  const bool passThrough = !isRadianceView(in.debugView);
  if (in.fusedOutput) {
    // The sky's display value, by the shader's formula (its C++ twin): the pixels the shader skips.
    const glm::vec4 display(shading::tdDisplay(glm::vec3(clear), in.exposure, static_cast<int>(in.toneMap), passThrough),
                            1.0f);
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 1, glm::value_ptr(display));
  }
  if (in.denoiseGuides) {
    // The sky's guides (instance 0: never filtered; its motion's w -1 says so to the stages that read no
    // guide), and their radiance past the filter (the compose stage's background), as writeNoGuides has them.
    const glm::uvec4 none(0u);
    const glm::vec4 sky(0.0f, 0.0f, 0.0f, -1.0f), exact(glm::vec3(clear), 0.0f);
    glClearNamedFramebufferuiv(framebuffer, GL_COLOR, 2, glm::value_ptr(none));
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 3, glm::value_ptr(sky));
    glClearNamedFramebufferfv(framebuffer, GL_COLOR, 4, glm::value_ptr(exact));
  }
  if (depthSkipsSky_) glEnable(GL_DEPTH_TEST);
  else glDisable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);

  GLuint p = variant(scene.features(), in, role).id();
  setUp(p, width, height, scene, ids, camera, in);
  if (in.fusedOutput) {
    glProgramUniform1f(p, TD_LOC_FUSED_EXPOSURE, in.exposure);
    glProgramUniform1i(p, TD_LOC_FUSED_TONE_MAP, static_cast<int>(in.toneMap));
    glProgramUniform1i(p, TD_LOC_FUSED_PASS_THROUGH, passThrough ? 1 : 0);
  }
  // The shader never reads the attached depth: that is a feedback loop, undefined even with depth writes
  // off (a GPU that compresses or tiles depth may hand the sampler stale or compressed data). Frames that
  // need depth read a copy; the others bind nothing there.
  const bool readsDepth = samplesDepth(scene.features(), in.debugView);
  assert((!readsDepth || sampledDepth) && "shadeInto: this variant samples depth and has no copy to read");
  if (readsDepth)
    glCopyImageSubData(depth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, sampledDepth->id(), GL_TEXTURE_2D, 0, 0, 0, 0, width,
                       height, 1);
  glBindTextureUnit(kUnitDepth, readsDepth ? sampledDepth->id() : 0);
  if (in.shadowMaps && role == Role::Shade) in.shadowMaps->bind(placeholders_);
  if (role == Role::ShadeWithMask) glBindTextureUnit(kUnitShadowMask, shadowMask_.id());
  if (in.probeCubes && in.probeEffects != 0) glBindTextureUnit(kUnitProbes, in.probeCubes->id());
  assert((!in.probeCubes || !(in.probeEffects & kProbeBehind) || in.behindView) && "shade: kProbeBehind without its view");
  if (in.probeCubes && (in.probeEffects & kProbeBehind)) glBindTextureUnit(kUnitBehind, in.behindView->id());

  glUseProgram(p);
  glBindVertexArray(emptyVao_.id());
  assertNoFeedbackLoop("shade");
  glDrawArrays(GL_TRIANGLES, 0, 3);
  // The sky pixels the depth test kept the shader off, where the environment varies with direction: its own
  // small program, only there (reversed-Z: the clear, 0, equals the triangle's depth). Running shade.frag on
  // them instead cost llvmpipe ~100 ms a 1280x720 frame of sky: it runs both sides of a branch.
  if (depthSkipsSky_ && in.debugView == DebugView::Final && scene.environment().kind() != TD_ENV_BACKGROUND) {
    const GLuint sky = sky_.id();
    setCameraUniforms(sky, width, height, camera);
    setEnvironment(sky, scene, in);
    glProgramUniform1f(sky, TD_LOC_FUSED_EXPOSURE, in.exposure);
    glProgramUniform1i(sky, TD_LOC_FUSED_TONE_MAP, static_cast<int>(in.toneMap));
    glProgramUniform1i(sky, TD_LOC_FUSED_PASS_THROUGH, passThrough ? 1 : 0);
    glDepthFunc(GL_EQUAL);
    glUseProgram(sky);
    if (in.distanceInAlpha) glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);  // the clear's distance stays
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthFunc(GL_LESS);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace tandem::gl
