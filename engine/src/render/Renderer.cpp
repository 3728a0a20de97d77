// The Renderer: the frame, top to bottom, in Renderer::render. The GL objects (GpuScene, the passes)
// and the Embree scene are caches of the Scene held here, rebuilt or patched only in the prepare stage.
#include "tandem/Renderer.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/RenderSpace.h"
#include "core/Timer.h"
#include "gl/CompositePass.h"
#include "gl/FrameLimits.h"
#include "gl/Gl.h"
#include "gl/GpuScene.h"
#include "gl/RasterEffects.h"
#include "gl/VisibilityPass.h"
#include "gl/GlObjects.h"
#include "rt/EmbreeScene.h"
#include "rt/RayTracer.h"
#include "rt/Whitted.h"
#include "tandem/Log.h"

namespace tandem {

struct Renderer::Impl {
  GlContext* context = nullptr;
  std::unique_ptr<rt::RayTracer> tracer;
  gl::VisibilityPass visibilityPass;
  gl::CompositePass compositePass;
  gl::GpuScene gpu;
  gl::ShadowMaps shadowMaps;
  gl::ReflectionProbes probes;
  std::vector<gl::Bounds> meshBounds;  // object space, per mesh: recomputed with each upload
  Scene scene;

  // What the caches are missing. The GL copy is synced every frame; the Embree scene only on frames
  // whose ray pass runs, so raster-only use never builds a BVH.
  bool gpuStale = true;
  bool gpuInstancesStale = false;
  bool gpuLightsStale = false;
  bool rtSceneStale = true;
  bool rtTransformsStale = false;
  bool rtBroken = false;  // Embree refused this scene (logged once); ray effects are off until the next one
  // Raster effects are re-rendered only when the GL copy changed since they were made (gpuVersion counts
  // its changes) or, for probes, when the shading they were made with differs.
  std::uint64_t gpuVersion = 1;
  std::uint64_t shadowVersion = 0, probeVersion = 0;
  bool probesShadowed = false;

  rt::VisibilityBuffer visibility;
  rt::RayOutputs rays;
  ImageF reference;

  // The frame's GL targets: the size they have, or the size they could not have and why (render() does
  // not try that size again; resize() does).
  gl::FrameLimits limits;
  int targetWidth = 0, targetHeight = 0;
  int failedWidth = 0, failedHeight = 0;
  std::string failure;

  // The last frame drawn, as tracePixel re-runs it: what it was rendered with and which parts the GL made.
  struct LastFrame {
    bool drawn = false;
    bool sceneChanged = false;  // setScene, setInstanceTransform or setLight since: its ids are stale
    Camera camera;
    FrameSettings settings;     // resolved
    FrameSettings raySettings;  // what the ray pass was given
    bool rayPass = false;
    bool reference = false;
    bool shadowMaps = false;    // primary hits' lights by the shadow maps
    int probeEffects = 0;       // gl::kProbeReflect / kProbeRefract in use
  } last;

  Result<void> allocateFrame(int width, int height);
  /// Brings the Embree scene up to date with `scene` (the only place it is built or committed); false when
  /// Embree refused the scene (logged once, ray effects off until the next scene).
  bool syncRayScene();
};

bool Renderer::Impl::syncRayScene() {
  if (rtBroken) return false;
  if (rtSceneStale) {
    auto built = tracer->setScene(scene);
    if (!built) {
      logError("Renderer: the ray pass cannot use this scene, ray effects are off: " + built.error().message);
      rtBroken = true;
    }
    rtSceneStale = rtTransformsStale = false;
  } else if (rtTransformsStale) {
    tracer->updateTransforms(scene);
    rtTransformsStale = false;
  }
  return !rtBroken;
}

Result<void> Renderer::Impl::allocateFrame(int width, int height) {
  if (width == targetWidth && height == targetHeight) return {};
  if (width == failedWidth && height == failedHeight) return Error{failure};
  targetWidth = targetHeight = 0;
  auto fail = [&](std::string why) -> Result<void> {
    compositePass.release();
    visibilityPass.release();
    failedWidth = width;
    failedHeight = height;
    failure = why;
    return Error{std::move(why)};
  };
  // The driver's limits first: they are what the hardware can do, and cost no allocation to check.
  if (auto within = gl::checkFrameLimits(width, height, limits); !within) return fail(within.error().message);
  if (width > kMaxFrameSide || height > kMaxFrameSide)
    return fail((width > kMaxFrameSide ? "width " + std::to_string(width) : "height " + std::to_string(height)) +
                " exceeds kMaxFrameSide = " + std::to_string(kMaxFrameSide));
  const std::string needs = "the frame's GL targets need " +
                            gl::formatBytes(gl::CompositePass::targetBytes(width, height) +
                                            gl::VisibilityPass::targetBytes(width, height)) +
                            "; ";
  // The composite pass first: its RGBA32F radiance is the largest texture, so a driver that cannot hold
  // the size refuses it before anything else is allocated.
  if (auto made = compositePass.resize(width, height); !made) return fail(needs + made.error().message);
  if (auto made = visibilityPass.resize(width, height); !made) return fail(needs + made.error().message);
  targetWidth = width;
  targetHeight = height;
  failedWidth = failedHeight = 0;
  failure.clear();
  return {};
}

namespace {

bool finiteMatrix(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

bool finiteVec(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What the ray pass does for an effect: Raster effects are the GL passes' (shadow maps, probes), not its.
EffectMode rayOnly(EffectMode m) { return m == EffectMode::Ray ? EffectMode::Ray : EffectMode::Off; }

}  // namespace

Result<std::unique_ptr<Renderer>> Renderer::create(GlContext& context, const RendererDesc& desc) {
  context.makeCurrent();
  auto impl = std::make_unique<Impl>();
  impl->context = &context;
  auto tracer = rt::RayTracer::create(desc.threads);
  if (!tracer) return Error{"Renderer: " + tracer.error().message};
  impl->tracer = std::move(*tracer);
  impl->tracer->setProgressCallback(desc.progress);
  auto visibility = gl::VisibilityPass::create();
  if (!visibility) return Error{"Renderer: " + visibility.error().message};
  impl->visibilityPass = std::move(*visibility);
  auto composite = gl::CompositePass::create();
  if (!composite) return Error{"Renderer: " + composite.error().message};
  impl->compositePass = std::move(*composite);
  impl->limits = gl::queryFrameLimits();
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;

Result<void> Renderer::setScene(Scene scene) {
  auto valid = validateScene(scene);
  if (!valid) return Error{"Renderer::setScene: " + valid.error().message + " (the previous scene stays)"};
  impl_->scene = std::move(scene);
  impl_->gpuStale = true;
  impl_->rtSceneStale = true;
  impl_->rtBroken = false;
  impl_->last.sceneChanged = true;
  return {};
}

const Scene& Renderer::scene() const { return impl_->scene; }

void Renderer::setInstanceTransform(std::uint32_t instance, const glm::mat4& worldFromObject) {
  Impl& r = *impl_;
  assert(instance < r.scene.instances.size() && "Renderer::setInstanceTransform: instance out of range");
  if (!finiteMatrix(worldFromObject)) {
    logWarning("Renderer::setInstanceTransform: instance " + std::to_string(instance) +
               " given a NaN or infinite transform; kept the previous one");
    return;
  }
  Instance& inst = r.scene.instances[instance];
  inst.worldFromObject = worldFromObject;
  r.gpuInstancesStale = true;
  // Static geometry lives in Embree's bottom level baked in place: moving it needs a rebuild.
  (inst.dynamic ? r.rtTransformsStale : r.rtSceneStale) = true;
  r.last.sceneChanged = true;
}

void Renderer::setLight(std::uint32_t light, const Light& value) {
  Impl& r = *impl_;
  assert(light < r.scene.lights.size() && "Renderer::setLight: light out of range");
  bool finite = finiteVec(value.color) && std::isfinite(value.intensity) && finiteVec(value.posW) &&
                finiteVec(value.dirW) && std::isfinite(value.range) && finiteVec(value.attenuation);
  int direct = 0;
  for (std::size_t i = 0; i < r.scene.lights.size(); ++i)
    direct += (i == light ? value.type : r.scene.lights[i].type) != LightType::Ambient ? 1 : 0;
  if (!finite || direct > kMaxLights) {
    logWarning("Renderer::setLight: light " + std::to_string(light) +
               (finite ? " would exceed the light limit" : " has a NaN or infinite value") + "; kept the previous one");
    return;
  }
  r.scene.lights[light] = value;
  r.gpuLightsStale = true;
  r.rtTransformsStale = true;
  r.last.sceneChanged = true;
}

Result<void> Renderer::resize(int width, int height) {
  Impl& r = *impl_;
  if (width < 1 || height < 1)
    return Error{"frame size " + std::to_string(width) + "x" + std::to_string(height) + ": must be at least 1x1"};
  r.failedWidth = r.failedHeight = 0;  // asked again: try again (memory may have been freed since)
  return r.allocateFrame(width, height);
}

FrameStats Renderer::render(const Camera& camera, const FrameSettings& requested) {
  Impl& r = *impl_;
  const Scene& scene = r.scene;
  FrameStats stats;
  Timer total;
  Timer clock;
  r.last.drawn = false;  // until this frame is drawn

  // ---------------------------------------------------------------------------------------------
  // prepare: resolve settings, decide which ray effects the scene needs, sync the GL buffers and
  // (when rays run) the Embree scene — the only place Embree commits.
  // ---------------------------------------------------------------------------------------------
  const FrameSettings s = requested.resolved();
  // A size the GL cannot hold: nothing to draw into. Reported, not drawn black.
  if (auto targets = r.allocateFrame(s.width, s.height); !targets) {
    stats.error = "frame " + std::to_string(s.width) + "x" + std::to_string(s.height) + ": " + targets.error().message;
    stats.prepareMs = stats.totalMs = total.ms();
    return stats;
  }
  FrameSettings raySettings = s;
  // Raster shadows stay "raster" for the ray pass: its primary points take the shadow map's answer, but
  // secondary hits have no map and trace shadow rays (TraceModes::hybrid).
  raySettings.reflections = rayOnly(s.reflections);
  raySettings.refraction = rayOnly(s.refraction);
  bool anyShadowLight = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
    return l.type != LightType::Ambient && l.castShadows;
  });
  // From the weights of the Whitted sum the composite uses: glass reflects by Fresnel without any kr.
  bool anyMirror = std::any_of(scene.materials.begin(), scene.materials.end(),
                               [&](const Material& m) { return rt::mayReflect(m, s.fresnelWeighted); });
  bool anyGlass = std::any_of(scene.materials.begin(), scene.materials.end(), rt::mayTransmit);
  if (!anyShadowLight) raySettings.shadows = EffectMode::Off;
  if (!anyMirror || s.maxDepth == 0) raySettings.reflections = EffectMode::Off;
  if (!anyGlass || s.maxDepth == 0) raySettings.refraction = EffectMode::Off;
  const bool wantsRays = raySettings.shadows == EffectMode::Ray || raySettings.reflections == EffectMode::Ray ||
                         raySettings.refraction == EffectMode::Ray;
  const bool wantsReference = s.reference && s.debugView == DebugView::Final;
  // Raster effects: only what the scene can show (a glass object reflects through its Fresnel term).
  const bool rasterShadows = s.shadows == EffectMode::Raster && anyShadowLight && !wantsReference;
  int probeEffects = 0;
  if (s.maxDepth > 0 && !wantsReference) {
    if (s.reflections == EffectMode::Raster && (anyMirror || anyGlass)) probeEffects |= gl::kProbeReflect;
    if (s.refraction == EffectMode::Raster && anyGlass) probeEffects |= gl::kProbeRefract;
  }

  if (r.gpuStale) {
    r.gpu.upload(scene, s.shadingOverride);
    r.meshBounds = gl::meshBounds(scene);
    r.gpuStale = r.gpuInstancesStale = r.gpuLightsStale = false;
    ++r.gpuVersion;
  }
  if (r.gpuInstancesStale) r.gpu.updateInstances(scene), ++r.gpuVersion;
  if (r.gpuLightsStale) r.gpu.updateLights(scene), ++r.gpuVersion;
  if (r.gpu.shadingOverride() != s.shadingOverride) r.gpu.updateMaterials(scene, s.shadingOverride), ++r.gpuVersion;
  r.gpuInstancesStale = r.gpuLightsStale = false;

  if (wantsRays || wantsReference) r.syncRayScene();
  const bool rayPass = wantsRays && !r.rtBroken && !wantsReference;
  const bool referenceFrame = wantsReference && !r.rtBroken;
  // The GL passes see the camera in render space, the space of the GL copy (core/RenderSpace.h).
  const Camera glCamera = toRenderSpace(camera, r.gpu.anchor());
  if (!referenceFrame && gl::CompositePass::samplesDepth(r.gpu.features(), s.debugView)) {
    if (auto copy = r.compositePass.reserveSampledDepth(); !copy) {
      stats.error = "frame " + std::to_string(s.width) + "x" + std::to_string(s.height) + ": " + copy.error().message;
      stats.prepareMs = stats.totalMs = total.ms();
      return stats;
    }
  }
  stats.prepareMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // raster: the raster effects' maps when the scene changed (shadow maps, then the probes, which are
  // shaded with them), then the visibility G-buffer (instance + 1, triangle) over reversed-Z depth.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  gl::ShadeInputs shadeIn;
  shadeIn.background = scene.background;
  shadeIn.ambient = scene.ambientIntensity();
  shadeIn.fresnel = s.fresnel;
  shadeIn.fresnelWeighted = s.fresnelWeighted;
  std::vector<gl::Bounds> instanceBounds;
  if (rasterShadows || probeEffects != 0) instanceBounds = gl::instanceBounds(scene, r.meshBounds, r.gpu.anchor());
  if (rasterShadows) {
    if (r.shadowVersion != r.gpuVersion) {
      gl::Bounds world;
      for (const gl::Bounds& b : instanceBounds) world.add(b);
      r.shadowMaps.update(scene, r.gpu, r.visibilityPass, world);
      r.shadowVersion = r.gpuVersion;
    }
    if (r.shadowMaps.mapCount() + r.shadowMaps.cubeCount() > 0) shadeIn.shadowMaps = &r.shadowMaps;
  } else if (r.shadowVersion != 0) {
    r.shadowMaps.release();  // cost follows the settings: no maps held while shadows are not raster
    r.shadowVersion = 0;
  }
  if (probeEffects != 0) {
    bool shadowed = shadeIn.shadowMaps != nullptr;
    if (r.probeVersion != r.gpuVersion || r.probesShadowed != shadowed) {
      // The probes see local shading only (no ray results, no probes): one bounce.
      gl::ShadeInputs local = shadeIn;
      r.probes.update(scene, r.gpu, r.visibilityPass, r.compositePass, local, instanceBounds);
      r.probeVersion = r.gpuVersion;
      r.probesShadowed = shadowed;
    }
    if (r.probes.probeCount() > 0) {
      shadeIn.probes = &r.probes;
      shadeIn.probeEffects = probeEffects;
    }
  } else if (r.probeVersion != 0) {
    r.probes.release();
    r.probeVersion = 0;
  }
  if (!referenceFrame) {
    r.visibilityPass.render(r.gpu, glCamera);
    glFinish();
  }
  stats.rasterMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // readback: the ids channel, top row first, only for the ray pass.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  if (rayPass) {
    r.visibility.width = s.width;
    r.visibility.height = s.height;
    r.visibilityPass.readIds(r.visibility.ids);
  }
  stats.readbackMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // rays: the hybrid ray pass on the ray grid, or the whole reference frame.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  r.rays.lightMask.clear();
  r.rays.reflected.clear();
  r.rays.transmitted.clear();
  r.rays.counts = {};
  if (rayPass) {
    r.tracer->trace(scene, camera, raySettings, r.visibility, r.rays);
    stats.rays = r.rays.counts;
    stats.rayWidth = r.rays.width;
    stats.rayHeight = r.rays.height;
  } else if (referenceFrame) {
    r.tracer->renderReference(scene, camera, s, r.reference, stats.rays);
    stats.rayWidth = r.reference.width;
    stats.rayHeight = r.reference.height;
  }
  stats.threads = r.tracer->threads();
  stats.raysMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // upload: only the ray results that exist this frame.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  shadeIn.debugView = s.debugView;
  shadeIn.rayScale = s.rayScale;
  if (rayPass) {
    std::size_t n = static_cast<std::size_t>(r.rays.width) * static_cast<std::size_t>(r.rays.height);
    shadeIn.rayWidth = r.rays.width;
    shadeIn.rayHeight = r.rays.height;
    std::string refused;
    auto take = [&](const Result<void>& uploaded, int input) {
      if (uploaded) shadeIn.rayInputs |= input;
      else if (refused.empty()) refused = uploaded.error().message;
    };
    if (r.rays.lightMask.size() == n && n > 0)
      take(r.compositePass.uploadLightMask(r.rays.width, r.rays.height, r.rays.lightMask.data()), gl::kRayLightMask);
    if (r.rays.reflected.size() == n && n > 0)
      take(r.compositePass.uploadReflected(r.rays.width, r.rays.height, r.rays.reflected.data()), gl::kRayReflected);
    if (r.rays.transmitted.size() == n && n > 0)
      take(r.compositePass.uploadTransmitted(r.rays.width, r.rays.height, r.rays.transmitted.data()),
           gl::kRayTransmitted);
    if (!refused.empty()) {
      // A ray grid's texture the GL refused: the frame would miss an effect, so it is not drawn.
      stats.error = "frame " + std::to_string(s.width) + "x" + std::to_string(s.height) + ": " + refused;
      stats.uploadMs = clock.ms();
      stats.totalMs = total.ms();
      return stats;
    }
  } else if (referenceFrame) {
    r.compositePass.uploadLinear(r.reference);
  }
  glFinish();
  stats.uploadMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // composite: shade the visibility buffer, add the ray results, then exposure + tone map + sRGB once.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  if (!referenceFrame) r.compositePass.shade(r.gpu, r.visibilityPass, glCamera, shadeIn);
  r.compositePass.output(s.exposure, s.toneMap, s.debugView);
  glFinish();
  stats.compositeMs = clock.ms();

  // ---------------------------------------------------------------------------------------------
  // present: a window gets the frame in its default framebuffer, ready for the application to draw its
  // UI and swap; headless frames stay in the offscreen target until readImage() captures them.
  // ---------------------------------------------------------------------------------------------
  clock.reset();
  if (r.context->window() != nullptr) {
    int w = 0, h = 0;
    r.context->framebufferSize(w, h);
    r.compositePass.present(w, h);
  }
  stats.presentMs = clock.ms();
  stats.totalMs = total.ms();
  r.last.drawn = true;
  r.last.sceneChanged = false;
  r.last.camera = camera;
  r.last.settings = s;
  r.last.raySettings = raySettings;
  r.last.rayPass = rayPass;
  r.last.reference = referenceFrame;
  r.last.shadowMaps = shadeIn.shadowMaps != nullptr;
  r.last.probeEffects = shadeIn.probes ? shadeIn.probeEffects : 0;
  return stats;
}

Result<PixelTrace> Renderer::tracePixel(int x, int y) {
  Impl& r = *impl_;
  const Impl::LastFrame& f = r.last;
  if (!f.drawn) return Error{"tracePixel: no frame to trace (none rendered yet, or the last one was not drawn)"};
  if (f.sceneChanged)
    return Error{"tracePixel: the scene changed since the last frame (setScene, setInstanceTransform or setLight); "
                 "render a frame, then trace it"};
  const int width = f.settings.width, height = f.settings.height;
  if (x < 0 || y < 0 || x >= width || y >= height)
    return Error{"tracePixel: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                 std::to_string(width) + "x" + std::to_string(height) + " frame"};
  // A frame without rays did not need the Embree scene; the trace does (the scene is the frame's: unchanged).
  if (!r.syncRayScene()) return Error{"tracePixel: the ray pass cannot use this scene (Embree refused it)"};

  PixelTrace trace;
  if (f.reference) {
    trace = r.tracer->tracePixelReference(r.scene, f.camera, f.settings, x, y);
  } else {
    // The ids the ray pass read back, or (a frame without a ray pass) the visibility pass's, still the frame's.
    rt::VisibilityBuffer idsNow;
    const rt::VisibilityBuffer* visibility = &r.visibility;
    if (!f.rayPass) {
      idsNow.width = width;
      idsNow.height = height;
      r.visibilityPass.readIds(idsNow.ids);
      visibility = &idsNow;
    }
    const int scale = std::max(1, f.raySettings.rayScale);
    trace = r.tracer->tracePixel(r.scene, f.camera, f.raySettings, *visibility, x / scale, y / scale);
    trace.x = x;
    trace.y = y;
  }
  trace.settings = f.settings;
  trace.rayPass = f.rayPass;

  // What the frame's pixel has that the rays do not: the GL's parts the trace names but does not recompute.
  const TraceNode* primary = trace.roots.empty() ? nullptr : &trace.nodes[static_cast<std::size_t>(trace.roots.front())];
  const bool onSurface = primary && primary->hit;
  if (f.settings.debugView != DebugView::Final)
    trace.notes.push_back("the frame shows the " + std::string(toString(f.settings.debugView)) +
                          " debug view, not this colour");
  if (!f.reference && trace.rayScale > 1)
    trace.notes.push_back("the ray pass ran at 1/" + std::to_string(trace.rayScale) +
                          " resolution: the frame shades its local term at (" + std::to_string(x) + ", " +
                          std::to_string(y) + ") and upsamples the grid's reflected and transmitted radiance there; "
                          "this trace is of the grid pixel's rays, at pixel (" + std::to_string(trace.tracedX) +
                          ", " + std::to_string(trace.tracedY) + ")");
  if (onSurface && f.shadowMaps)
    trace.notes.push_back("shadows are raster: the frame takes the primary hit's light visibility from the shadow "
                          "maps, which the trace does not model (its local term counts every light as visible)");
  if (onSurface && (f.probeEffects & gl::kProbeReflect))
    trace.notes.push_back("reflections are raster: the frame's primary hit reflects a probe, which the trace does not model");
  if (onSurface && (f.probeEffects & gl::kProbeRefract))
    trace.notes.push_back("refraction is raster: the frame's primary hit refracts a probe, which the trace does not model");
  if (onSurface && !f.reference) {
    const ShadingModel model = f.settings.shadingOverride.value_or(r.scene.materials[primary->material].shading);
    if (model == ShadingModel::Toon)
      trace.notes.push_back("toon shading: the frame may draw a silhouette outline over this pixel");
  }
  return trace;
}

void Renderer::present(int framebufferWidth, int framebufferHeight) {
  impl_->compositePass.present(framebufferWidth, framebufferHeight);
}

Image Renderer::readImage() { return impl_->compositePass.readImage(); }

ImageF Renderer::readLinear() { return impl_->compositePass.readLinear(); }

ResourceStats Renderer::resources() const {
  ResourceStats r;
  r.glObjects = gl::liveObjectCount();
  r.embreeBytes = impl_->tracer ? impl_->tracer->embreeBytes() : 0;
  r.embreeHandles = rt::liveEmbreeHandles();
  return r;
}

}  // namespace tandem
