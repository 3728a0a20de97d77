// The Renderer: the frame, top to bottom, in Renderer::render. The GL objects (GpuScene, the passes)
// and the Embree scene are caches of the Scene held here, rebuilt or patched only in the prepare stage. The
// rest of the API (creation, the scene's mutators, tracePixel): RendererApi.cpp.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include "render/RendererImpl.h"
#include "render/StageTime.h"

namespace tandem {

namespace {

std::string frameError(const FrameSettings& s, const std::string& why) {
  return "frame " + std::to_string(s.width) + "x" + std::to_string(s.height) + ": " + why;
}

// The ray grid's channels as the shade pass takes them (gl/RayChannels.h), from the ray pass's outputs: a
// channel the frame's rays did not fill (or filled at another size) has no texels.
gl::RayGrid rayGridData(const rt::RayOutputs& rays) {
  gl::RayGrid grid;
  const std::size_t n = static_cast<std::size_t>(rays.width) * static_cast<std::size_t>(rays.height);
  if (n == 0) return grid;
  using Id = gl::RayChannelId;
  if (rays.lightMask.size() == n) {
    gl::setRayGrid<Id::LightMask>(grid, rays.lightMask);
    if (rays.areaLights > 0 && rays.areaSamples.size() == static_cast<std::size_t>(rays.areaLights) * n)
      gl::setRayGrid<Id::AreaSamples>(grid, rays.areaSamples, rays.areaLights);
  }
  if (rays.reflected.size() == n)
    gl::setRayGrid<Id::Reflected>(grid, rays.reflected, 1, {rays.reflectedTiles, rays.tileSize});
  if (rays.transmitted.size() == n)
    gl::setRayGrid<Id::Transmitted>(grid, rays.transmitted, 1, {rays.transmittedTiles, rays.tileSize});
  return grid;
}

}  // namespace

// The frame, top to bottom: plan → prepare (targets, caches) → raster → readback → rays → upload →
// shade (composite and output) → present. Each stage is one call below, timed into FrameStats. In throughput
// mode (FrameSettings::pipelined) the same stages run across two calls: renderPipelined.
FrameStats Renderer::render(const Camera& camera, const FrameSettings& requested) {
  Impl& r = *impl_;
  ++r.calls;
  FrameStats stats = r.renderFrame(camera, requested);
  stats.intervalMs = r.sinceLastCall ? r.sinceLastCall->ms() : 0.0;
  r.sinceLastCall.emplace();
  return stats;
}

FrameStats Renderer::Impl::renderFrame(const Camera& camera, const FrameSettings& requested) {
  FrameStats stats;
  const SceneChanges pending = changes;  // applied by startFrame
  FrameClock clock = startFrame(stats);
  // With a frame-time budget, the settings this frame can afford; otherwise the requested ones.
  FramePlan plan = timed(stats.planMs, [&] {
    SceneFacts facts = sceneFacts(scene, camera);
    facts.softwareGl = limits.software;
    return denoisePlan(planFrame(facts, budget.choose(requested.resolved(), facts)), facts);
  });
  const FrameSettings& s = plan.settings;
  const bool sampled = s.aa != AntiAlias::Off || s.accumulate > 1;
  // Throughput mode takes frames of one sample whose GL copy holds still while their rays run (no open
  // shutter, no radiosity solution to upload) and that trace something. A new size is drawn in latency mode:
  // the targets the frame in flight would be shown in are made again at the new size.
  const bool resized = inFlight && (inFlight->plan.settings.width != s.width || inFlight->plan.settings.height != s.height);
  if (s.pipelined && !plan.reference && plan.rayPass && !(camera.shutter > 0.0f) && !s.radiosity && !resized) {
    if (!sampled) return renderPipelined(clock, plan, denoiseSample(plan, camera), stats, pending, false);
    // Accumulation (without anti-aliasing) starting again, as it does every frame while things move: its one
    // sample is shown as drawn (drawSampled's single sample), a plain frame from the sample's camera. The
    // frames that go on adding samples are drawn in latency mode, the first of them reading this one's
    // linear frame once it is shown.
    if (s.aa == AntiAlias::Off &&
        accum.step(camera, s, {clock.lastDrawn, last.sceneChanged, caches.probesCurrent()}) == Accumulation::Step::Restart) {
      timed(stats.accumulateMs, [&] { accum.restart(camera, s, firstDenoiseSample(plan), plan.denoise); });
      const Camera sampleCamera = accum.nextSample(camera);
      FramePlan samplePlan = accum.samplePlan(plan);
      accum.firstShown(plan.denoise);  // a filtered frame is not a sample to sum
      accum.frameDone();
      stats.accumulated = 1;
      return renderPipelined(clock, samplePlan, sampleCamera, stats, pending, true);
    }
  }
  // Latency mode: the frame in flight first (shown, then drawn over), so that nothing below races its rays.
  if (std::optional<FrameStats> done = drain(); done && !done->error.empty()) clock.lastDrawn = false;
  if (!timed(stats.prepareMs, [&] { return prepare(plan, camera, stats, true, true); })) return finishFrame(clock, stats);
  if (!s.pipelined && (rayHeld || spareVisibility)) releasePipeline();  // cost follows the settings
  if (!sampled && accum.active()) timed(stats.accumulateMs, [&] { accum.release(); });  // cost follows the settings
  const bool drawn = sampled ? drawSampled(plan, camera, stats, clock.lastDrawn)
                             : drawSample(plan, denoiseSample(plan, camera), stats, clock.lastDrawn, nullptr);
  if (drawn) timed(stats.presentMs, [&] { present(); });
  return finishFrame(clock, stats);
}

Renderer::Impl::FrameClock Renderer::Impl::startFrame(FrameStats& stats) {
  FrameClock clock;
  clock.compiledBefore = gl::programsBuilt();
  timed(stats.bookkeepingMs, [&] { applyChanges(); });
  clock.lastDrawn = last.drawn;
  last.drawn = false;  // until this frame is drawn
  return clock;
}

FrameStats Renderer::Impl::finishFrame(const FrameClock& clock, FrameStats& stats) {
  Timer book;
  // Every stage ended with glFinish, but for the timestamp queries issued after it: finishing them costs
  // microseconds and gives this frame's GPU times now (a pipelined frame would read them a frame later).
  glFinish();
  stats.gpu = gpuTimers.endFrame();
  stats.shaderCompiles = static_cast<int>(gl::programsBuilt() - clock.compiledBefore);
  stats.budget = budget.stats();
  // The budget learns from the frame's total as it stands here; its own few microseconds join the total after.
  stats.totalMs = clock.total.ms();
  budget.observe(stats);
  stats.bookkeepingMs += book.ms();
  stats.totalMs = clock.total.ms();
  return stats;
}

bool Renderer::Impl::drawSample(const FramePlan& plan, const Camera& sampleCamera, FrameStats& stats, bool lastDrawn,
                                const std::vector<std::uint8_t>* only) {
  FrameStats sample;
  // A thin lens is drawn one lens point at a time: the hybrid frame as the pinhole at that point (every pass
  // sees an ordinary camera); the reference traces lens rays itself, a lens point per pixel sample.
  const Camera camera =
      plan.reference ? sampleCamera : sampleCamera.lensPinhole({plan.settings.width, plan.settings.height});
  // Motion blur: the GL copy's moving instances where this sample's shutter time puts them (the rays of the
  // sample run at that time too).
  if (!plan.reference)
    timed(sample.syncMs, [&] { caches.syncGpu(scene, plan.settings.shadingOverride, camera.shutter, camera.timeU,
                                                 plan.settings.probeLimit); });
  // The GL passes see the camera in render space, the space of the GL copy (core/RenderSpace.h).
  const Camera glCamera = toRenderSpace(camera, caches.gpu().anchor());
  gl::ShadeInputs in;
  in.lightSamples = plan.settings.lightSamples;
  in.sampleIndex = camera.sampleIndex;
  raster(plan, camera, glCamera, in, sample);
  // Nothing the rays depend on changed since the last frame drawn: its ids and ray results still hold.
  const bool reuse = last.reusesRays(plan, camera, lastDrawn, only != nullptr);
  if (reuse) reuseRays(plan, sample);
  else traceSample(plan, camera, sample, lastDrawn, only);
  const bool uploaded = timed(sample.uploadMs, [&] {
    gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Upload);
    return upload(plan, in, sample, reuse, visibilityPass);
  });
  if (uploaded)
    timed(sample.compositeMs, [&] {
      gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Composite);
      shade(plan, glCamera, in, visibilityPass, sample);
    });
  if (uploaded) timed(sample.bookkeepingMs, [&] { remember(plan, camera, in); });
  stats.addSample(sample);
  if (!uploaded) {
    stats.error = sample.error;
    return false;
  }
  return true;
}

// readback → rays for one sample: the ids read back, the exact solids resolved, the ray pass traced, keeping
// the last frame's shadow answers where only some things changed (FrameHistory::keepsSome) and, in an adaptive
// round, tracing only the pixels it refines.
void Renderer::Impl::traceSample(const FramePlan& plan, const Camera& camera, FrameStats& sample, bool lastDrawn,
                                 const std::vector<std::uint8_t>* only) {
  rt::RayReuse kept;
  const bool keeps = keepAnswers(plan, camera, sample, lastDrawn, only != nullptr, kept, scene);
  const bool proved = proveShadows(plan, camera, sample);
  timed(sample.readbackMs, [&] { readback(plan, proved, visibility); });
  // An adaptive round traces only the pixels it refines (the ray pass takes the others as background).
  std::span<const std::uint8_t> selection;
  if (only != nullptr && visibility.ids.size() == only->size()) selection = *only;
  traceVisible(plan, camera, sample, keeps ? &kept : nullptr, selection, scene);
}

// The camera still but something moved: the rays clear of it keep their answers (the history's part of the
// frame: bookkeeping).
bool Renderer::Impl::keepAnswers(const FramePlan& plan, const Camera& camera, FrameStats& sample, bool lastDrawn,
                                 bool partial, rt::RayReuse& kept, const Scene& seen) {
  return timed(sample.bookkeepingMs, [&] {
    FrameHistory::Changes since;
    const bool some = !partial && last.keepsSome(plan, camera, seen, lastDrawn, !rays.lightMask.empty(), since);
    kept.moved = std::move(since.moved);
    kept.changedLights = since.changedLights;
    if (!plan.settings.reuseRays && !keptVisibility.ids.empty()) releaseKept();
    if (some) {
      std::swap(visibility, keptVisibility);
      std::swap(rays, keptRays);
      kept.ids = &keptVisibility;
      kept.rays = &keptRays;
    }
    return some;
  });
}

// Exact solids first: the ray pass starts from the hits the resolve step finds (every pixel's, since the GL
// shades them all). Its time and rays are the rays stage's, with the ray pass's.
void Renderer::Impl::traceVisible(const FramePlan& plan, const Camera& camera, FrameStats& sample,
                                  const rt::RayReuse* kept, std::span<const std::uint8_t> only, const Scene& seen) {
  double resolveMs = 0;
  const std::uint64_t resolvedRays = timed(resolveMs, [&] { return resolveExact(plan, camera, seen); });
  timed(sample.raysMs, [&] { traceRays(plan, camera, sample, kept, only, seen); });
  sample.raysMs += resolveMs;
  sample.rays.resolved = resolvedRays;
}

bool Renderer::Impl::drawSampled(const FramePlan& plan, const Camera& camera, FrameStats& stats, bool lastDrawn) {
  const FrameSettings& s = plan.settings;
  const Accumulation::Step step = accum.step(camera, s, {lastDrawn, last.sceneChanged, caches.probesCurrent()});
  auto converged = [&] {  // the mean is in the output targets already
    last.drawn = true;
    stats.rayWidth = plan.reference ? reference.width : rays.width;
    stats.rayHeight = plan.reference ? reference.height : rays.height;
    stats.threads = tracer->threads();
    stats.accumulated = accum.mostSamples();
    return true;
  };
  stats.samples = 0;
  if (step == Accumulation::Step::Converged) return converged();
  if (step == Accumulation::Step::Restart)
    timed(stats.accumulateMs, [&] { accum.restart(camera, s, firstDenoiseSample(plan), plan.denoise); });
  // The linear frame's read-back and the sums are the accumulation's time.
  auto addLinear = [&](const std::vector<std::uint8_t>* only) {
    timed(stats.accumulateMs, [&] {
      if (plan.reference) accum.add(reference, only);
      else accum.add(outputPass.readLinear(), only);
    });
  };
  if (accum.firstUnread) {
    // Still in the linear target (or the reference image): nothing drew since.
    addLinear(nullptr);
    accum.firstUnread = false;
  }
  const bool adaptive = s.aa == AntiAlias::Adaptive;
  const bool single = accum.singleSample(s);
  const int perFrame = s.aa == AntiAlias::Off ? 1 : s.aaSamples;
  // Adaptive: the pixels a round samples, and the wider set whose rays it traces (Accumulation::nextRound).
  std::vector<std::uint8_t> refine, traced;
  bool drawnOnce = lastDrawn;
  auto addSample = [&](const std::vector<std::uint8_t>* only, const std::vector<std::uint8_t>* rayPixels) {
    const Camera jittered = accum.nextSample(camera);
    if (!drawSample(accum.samplePlan(plan), jittered, stats, drawnOnce, rayPixels)) {
      accum.release();  // a sample is missing: the sums no longer stand for these settings
      last.drawn = false;  // and `last` describes the sample before it, not what the buffers hold
      return false;
    }
    drawnOnce = true;
    ++stats.samples;
    if (single) accum.firstShown(plan.denoise);  // a filtered frame is not a sample to sum
    else addLinear(only);
    if (only != nullptr)
      timed(stats.accumulateMs, [&] {
        stats.refinedPixels += static_cast<std::uint64_t>(std::count(only->begin(), only->end(), 1));
      });
    return true;
  };
  if (!adaptive) {
    for (int k = 0; k < perFrame; ++k)
      if (!addSample(nullptr, nullptr)) return false;
  } else {
    int drawn = 0;
    if (accum.frames() == 0) {
      // Every pixel first gets a few samples, enough to see whether they disagree.
      for (; drawn < std::min(4, perFrame); ++drawn)
        if (!addSample(nullptr, nullptr)) return false;
    }
    while (drawn < perFrame && timed(stats.accumulateMs, [&] { return accum.nextRound(refine, traced); })) {
      for (int k = 0; k < std::min(4, perFrame - drawn); ++k)
        if (!addSample(&refine, &traced)) return false;
      drawn += std::min(4, perFrame - drawn);
    }
    if (stats.samples == 0) {
      // Nothing disagrees any more: the accumulation has converged early.
      accum.convergedEarly();
      return converged();
    }
  }
  accum.frameDone();
  if (single) {
    // The one sample is on show as the shade pass (or the reference's output) drew it.
    stats.accumulated = 1;
    return true;
  }
  // Show the mean: the output pass tone-maps it as it does a reference frame (the accumulation's time).
  timed(stats.accumulateMs, [&] {
    stats.accumulated = accum.mostSamples();
    gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Accumulate);
    outputPass.uploadLinear(accum.shown());
    stats.denoised = accum.handingOver();  // the filtered frame still blended in: a reconstruction
    outputPass.output(s.exposure, s.toneMap, s.debugView);
    glFinish();
  });
  return true;
}

// prepare: the frame's GL targets, the GL copy, and (when rays run) the Embree scene — the only place
// Embree commits. Without an Embree scene the plan loses its rays.
bool Renderer::Impl::prepare(FramePlan& plan, const Camera& camera, FrameStats& stats, bool syncGl, bool syncEmbree) {
  const FrameSettings& s = plan.settings;
  // A size the GL cannot hold: nothing to draw into. Reported, not drawn black.
  if (auto targets = allocateFrame(s.width, s.height); !targets) {
    stats.error = frameError(s, targets.error().message);
    return false;
  }
  if (!s.denoise) leaveDenoise();  // cost follows the settings
  // The GL copy's time is each sample's (drawSample): here only the shutter, leaving the time as it is; a camera
  // far from the render anchor moves it first (followCamera: nothing is in flight where the GL copy syncs here).
  if (syncGl) followCamera(camera), caches.syncGpu(scene, s.shadingOverride, camera.shutter, caches.gpuTime(), s.probeLimit);
  if (syncEmbree && plan.needsRayScene() && !caches.syncRays(scene, camera.shutter, *tracer)) plan.withoutRays();
  // The radiosity solution (docs/radiosity.md): solved here, or the background solve's latest. A new one
  // changes every point the frame shades: nothing of the last frame's rays or samples is kept.
  if (s.radiosity) {
    if (radiosity.sync(scene, s, tracer->threads())) last.sceneChanged = true;
    caches.gpu().uploadRadiosity(radiosity.field().get());
    tracer->setRadiosity(radiosity.field());
    stats.radiosity = radiosity.stats();
  } else if (radiosity.holds()) {
    radiosity.release();
    caches.gpu().uploadRadiosity(nullptr);
    tracer->setRadiosity(nullptr);
  }
  if (!plan.reference && gl::ShadePass::samplesDepth(caches.gpu().features(), s.debugView)) {
    if (auto copy = shadePass.reserveSampledDepth(s.width, s.height); !copy) {
      stats.error = frameError(s, copy.error().message);
      return false;
    }
  }
  return true;
}

// raster: the raster effects' maps when the scene changed (shadow maps, then the probes, which are shaded
// with them), then the visibility G-buffer (instance + 1, triangle) over reversed-Z depth.
void Renderer::Impl::raster(const FramePlan& plan, const Camera& camera, const Camera& glCamera, gl::ShadeInputs& in,
                            FrameStats& stats) {
  localInputs(plan, in);
  // The probes are shaded from these inputs as they stand: the final view of local shading.
  caches.syncRasterEffects(scene, plan, camera, visibilityPass, shadePass, in, stats, &gpuTimers);
  viewInputs(plan, camera, in);
  rasterVisibility(plan, glCamera, stats);
}

// The shade pass's inputs of local shading, from the scene and the settings.
void Renderer::Impl::localInputs(const FramePlan& plan, gl::ShadeInputs& in) const {
  const FrameSettings& s = plan.settings;
  in.background = scene.background;
  // The radiosity solution replaces the ambient term where it covers a surface.
  in.radiosity = s.radiosity && caches.gpu().hasRadiosity();
  in.ambient = scene.ambientIntensity();
  if (in.radiosity) {
    in.radiosityAmbient = radiosity.field()->ambient;
    in.radiosityInstances = static_cast<int>(radiosity.field()->instanceCount);
  }
  in.fresnel = s.fresnel;
  in.fresnelWeighted = s.fresnelWeighted;
}

// What the frame's view adds to them (not the probes': they show local shading).
void Renderer::Impl::viewInputs(const FramePlan& plan, const Camera& camera, gl::ShadeInputs& in) {
  in.debugView = plan.settings.debugView;
  in.rayScale = plan.settings.rayScale;
  motionInputs(plan, camera, in);
}

void Renderer::Impl::rasterVisibility(const FramePlan& plan, const Camera& glCamera, FrameStats& stats) {
  if (!plan.reference)
    timed(stats.rasterMs, [&] {
      gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Raster);
      visibilityPass.render(caches.gpu(), glCamera);
      glFinish();
    });
}

// readback: the ids channel, top row first, only for the ray pass and the resolve step; the shadow proofs
// beside them when the GL drew them (else none: a frame's proofs never outlive its ids).
void Renderer::Impl::readback(const FramePlan& plan, bool proved, rt::VisibilityBuffer& into) {
  into.proofs.clear();
  if (!plan.readsIds()) return;
  into.width = plan.settings.width;
  into.height = plan.settings.height;
  visibilityPass.readIds(into.ids);
  if (proved) proofPass->read(into.proofs);
}

// rays, first: each pixel of an exact solid's proxy by its camera ray, the ids changed to what it found.
std::uint64_t Renderer::Impl::resolveExact(const FramePlan& plan, const Camera& camera, const Scene& seen) {
  resolved.clear();
  if (!plan.resolve) return 0;
  RayCounts counts;
  tracer->resolveExact(seen, camera, visibility, resolved, counts);
  return counts.resolved;
}

// rays: the hybrid ray pass on the ray grid, or the whole reference frame.
void Renderer::Impl::traceRays(const FramePlan& plan, const Camera& camera, FrameStats& stats,
                               const rt::RayReuse* reuse, std::span<const std::uint8_t> only, const Scene& seen) {
  rays.lightMask.clear();
  rays.areaSamples.clear();
  rays.areaLights = 0;
  rays.areaLightBits = 0;
  rays.reflected.clear();
  rays.transmitted.clear();
  rays.reflectedTiles.clear();
  rays.transmittedTiles.clear();
  rays.counts = {};
  if (plan.rayPass) {
    tracer->trace(seen, camera, plan.raySettings, visibility, rays, reuse, only);
    stats.rays = rays.counts;
    if (plan.raySettings.hybridShadows) {
      stats.shadowMapsMs += tracer->lastShadowMapMs();
      stats.shadowMapBytes = tracer->shadowMapBytes();
    }
    stats.rayWidth = rays.width;
    stats.rayHeight = rays.height;
  } else if (plan.reference) {
    tracer->renderReference(seen, camera, plan.settings, reference, stats.rays);
    stats.rayWidth = reference.width;
    stats.rayHeight = reference.height;
  }
  stats.threads = tracer->threads();
}

// rays, again: the last frame's results, kept as they were (the frame traces nothing).
void Renderer::Impl::reuseRays(const FramePlan& plan, FrameStats& stats) {
  stats.raysReused = true;
  proofRoute.still();
  stats.rayWidth = plan.reference ? reference.width : rays.width;
  stats.rayHeight = plan.reference ? reference.height : rays.height;
  stats.threads = tracer->threads();
}

// upload: only the ray results that exist this frame. Reused results are in the ray textures already (only
// this stage writes them), so they are named as inputs without being sent again.
bool Renderer::Impl::upload(const FramePlan& plan, gl::ShadeInputs& in, FrameStats& stats, bool reused,
                            gl::VisibilityPass& pass) {
  // The resolved pixels into the visibility buffer the raster just drew (again, when the rays are reused).
  if (plan.resolve)
    if (auto patched = pass.patch(resolved); !patched) {
      stats.error = frameError(plan.settings, patched.error().message);
      return false;
    }
  if (plan.rayPass) {
    // The shade variant follows what the plan can produce, not what this frame's rays left non-empty.
    in.rayChannels = (plan.rays.primaryShadows ? gl::kRayLightMask : 0) | (plan.rays.reflections ? gl::kRayReflected : 0) |
                     (plan.rays.refraction ? gl::kRayTransmitted : 0);
    in.rayWidth = rays.width;
    in.rayHeight = rays.height;
    const gl::RayGrid grid = rayGridData(rays);
    int held = 0;
    for (const gl::RayChannel& c : gl::kRayChannels)
      if (grid[static_cast<std::size_t>(c.id)].texels != nullptr) held |= c.input;
    // Reused rays are in the textures already (FrameHistory::reusesRays).
    if (!reused)
      if (auto sent = shadePass.uploadRays(rays.width, rays.height, grid); !sent) {
        // A ray grid's texture the GL refused: the frame would miss an effect, so it is not drawn.
        stats.error = frameError(plan.settings, sent.error().message);
        return false;
      }
    in.rayInputs |= held;
  } else if (plan.reference) {
    outputPass.uploadLinear(reference);
  }
  glFinish();
  return true;
}

// shade: the visibility buffer shaded with the ray results added, then exposure + tone map + sRGB once.
void Renderer::Impl::shade(const FramePlan& plan, const Camera& glCamera, const gl::ShadeInputs& in,
                           const gl::VisibilityPass& pass, FrameStats& sample) {
  const FrameSettings& s = plan.settings;
  if (plan.reference) {
    outputPass.output(s.exposure, s.toneMap, s.debugView);  // the reference's linear frame was uploaded
  } else {
    // One pass writes the linear frame and its display values (the output pass's formula, tdDisplay).
    gl::ShadeInputs fused = in;
    fused.fusedOutput = true;
    fused.exposure = s.exposure;
    fused.toneMap = s.toneMap;
    if (!shadeDenoised(plan, glCamera, fused, pass, sample))
      shadePass.shade(outputPass.fusedFramebuffer(), caches.gpu(), pass, glCamera, fused);
  }
  rememberMotion(plan, pass);
  glFinish();
}

// present: a window gets the frame in its default framebuffer, ready for the application to draw its UI
// and swap; headless frames stay in the offscreen target until readImage() captures them.
void Renderer::Impl::present() {
  if (context->window() == nullptr) return;
  int w = 0, h = 0;
  context->framebufferSize(w, h);
  outputPass.present(w, h);
}

}  // namespace tandem
