// Throughput mode (FrameSettings::pipelined, docs/pipeline.md): the frame's stages across two render() calls,
// each frame's ray pass on a thread of its own while the next frame is rasterized and the one before is
// composited. Renderer.cpp's renderFrame hands a frame here when the pipeline takes it.
#include <cassert>
#include <thread>

#include "render/RendererImpl.h"
#include "render/StageTime.h"

namespace tandem {

// Throughput mode (docs/pipeline.md): the same stages as a latency frame's, in this order across two calls.
//   call N:   plan N → instances N → raster N → read-back N   (N−1's rays running meanwhile)
//             → land N−1 (wait for its rays, upload) → launch N's rays → composite + present N−1
//             → lights, raster effects N (shadow maps, probes) → return N−1's stats
//   call N+1: ... raster N+1 while N's rays run ... composite N ...
// The frame in flight is composited with the GL state it was drawn with: its own visibility buffer (the
// next frame draws into the spare one), its instance records (the GL copy's other slot), the lights and
// raster effects as they were (the next frame's are made after the composite). Its ray pass owns what it
// reads and writes until it lands: rayScene (the scene as the frame saw it), the tracer, visibility, rays, the
// kept answers and resolved; the next frame's GL work touches none of them (its ids go to stagedVisibility)
// and the scene's mutators write `scene`. A new scene, other settings, proofs in the GL or a camera that moves
// the render anchor (the floating origin, core/RenderSpace.h) complete the frame in flight first (a drain).
FrameStats Renderer::Impl::renderPipelined(const FrameClock& clock, FramePlan& plan, const Camera& camera,
                                           FrameStats& stats, const SceneChanges& changed, bool accumulating) {
  const FrameSettings& s = plan.settings;
  bool lastDrawn = clock.lastDrawn;
  std::optional<FrameStats> shown;
  if (!accumulating && accum.active()) timed(stats.accumulateMs, [&] { accum.release(); });  // cost follows the settings
  // This frame's camera as its one sample draws it (drawSample: a thin lens's point by the sample index).
  const Camera sampleCamera = camera.lensPinhole({s.width, s.height});
  if (!plan.glShadowProofs) releaseGlProofs();  // as proveShadows does for a latency frame without them
  // Overlap unless the GL copy is made again (a new scene), the settings differ (the size, the GL copy's
  // variant, the raster effects asked for), the shutter time differs, or the proofs are the GL's (their maps
  // are the tracer's, busy with the rays in flight).
  bool overlap = inFlight && !changed.replaced && inFlight->plan.settings == s &&
                 inFlight->camera.timeU == sampleCamera.timeU && !plan.glShadowProofs && !caches.anchorDue(camera);
  if (overlap && !spareVisibility) {
    if (auto made = gl::VisibilityPass::create()) spareVisibility = std::move(*made);
    else overlap = false;
  }
  if (overlap && (spareVisibility->width() != s.width || spareVisibility->height() != s.height) &&
      !spareVisibility->resize(s.width, s.height)) {
    spareVisibility.reset();  // the GL could not hold a second one: this frame drains
    overlap = false;
  }
  if (inFlight && !overlap) {
    shown = completeInFlight(visibilityPass);
    shown->pipelineDrained = true;
    if (!shown->error.empty()) lastDrawn = false;
  }
  // Without a frame in flight the GL copy is brought up to date here, as in latency mode (the anchor moved first
  // where due: a frame in flight was drained for it); with one, only its instance records now (into the slot
  // the frame in flight does not use), the rest after its composite.
  if (!timed(stats.prepareMs, [&] { return prepare(plan, camera, stats, !inFlight, false); })) {
    if (inFlight) shown = completeInFlight(visibilityPass);  // not reached (the same size cannot fail)
    return finishFrame(clock, stats);
  }
  if (inFlight) timed(stats.prepareMs, [&] { caches.syncGpuInstances(scene, 1 - inFlight->slot); });
  if (overlap) std::swap(visibilityPass, *spareVisibility);  // the frame in flight's buffer is the spare now

  // This frame's raster (drawSample's GL part, the raster effects left for later).
  FrameStats sample;
  const Camera glCamera = toRenderSpace(sampleCamera, caches.gpu().anchor());
  gl::ShadeInputs in;
  in.lightSamples = s.lightSamples;
  in.sampleIndex = sampleCamera.sampleIndex;
  localInputs(plan, in);
  rasterVisibility(plan, glCamera, sample);
  // Whether it reuses the last frame's rays whole is known now (the last frame was remembered by the call
  // before); read its ids back while the rays in flight run.
  bool reuse = last.reusesRays(plan, sampleCamera, lastDrawn, false);
  // The copy starts here and is read out once the frame in flight has landed: on a GPU it runs while this
  // call waits for those rays (gl/PixelReadback.h).
  bool readBack = false, reading = false;
  if (!reuse && !plan.glShadowProofs) {
    stagedVisibility.proofs.clear();
    reading = plan.readsIds();
    if (reading) timed(sample.readbackMs, [&] { visibilityPass.startReadIds(); });
    readBack = true;
  }
  // The frame in flight lands (rays waited for, uploaded); it is composited once this frame's rays run.
  std::optional<Landed> landed;
  if (inFlight) {
    landed = landInFlight(*spareVisibility);
    if (!landed->uploaded) lastDrawn = false;
  }
  if (reading)
    timed(sample.readbackMs, [&] {
      stagedVisibility.width = s.width;
      stagedVisibility.height = s.height;
      visibilityPass.finishReadIds(stagedVisibility.ids);
    });
  // The frame before could not be drawn after all (its upload failed): its rays are no longer on show.
  if (reuse && !lastDrawn) reuse = false;
  if (!reuse && !readBack) {
    // The proofs' maps are made from the Embree scene, which must be this frame's first (no rays in flight
    // now: a frame with proofs in the GL drains, and the one before has landed).
    const bool proved = timed(sample.raysMs, [&] { return syncRayScene(camera); }) &&
                        proveShadows(plan, sampleCamera, sample);
    timed(sample.readbackMs, [&] { readback(plan, proved, stagedVisibility); });
  }

  // Launch: the ray pass's scene and Embree brought to this frame, the answers it keeps, its ids in place,
  // its rays on their own thread.
  inFlight.emplace();
  InFlight& f = *inFlight;
  try {
    f.since = clock.total;
    f.camera = sampleCamera;
    f.glCamera = glCamera;
    f.slot = caches.gpu().instanceSlot();
    bool traces = !reuse;
    if (traces && !timed(sample.raysMs, [&] { return syncRayScene(camera); })) {
      plan.withoutRays();  // Embree refused the scene: this frame is drawn without rays, as prepare would
      traces = false;
    }
    f.plan = plan;
    f.reused = reuse;
    if (reuse) {
      reuseRays(plan, sample);
    } else if (traces) {
      f.keeps = keepAnswers(plan, sampleCamera, sample, lastDrawn, false, f.kept, rayScene);
      std::swap(visibility, stagedVisibility);
    }
    f.sample = sample;
    if (traces)
      f.rays = std::thread([this] {
        InFlight& job = *inFlight;
        try {
          traceVisible(job.plan, job.camera, job.sample, job.keeps ? &job.kept : nullptr, {}, rayScene);
        } catch (...) {
          job.failure = std::current_exception();
        }
      });
  } catch (...) {
    inFlight.reset();  // nothing was launched: no frame is in flight (the one that landed is not shown)
    throw;
  }

  // The frame before, composited with its own instance records and presented while this one's rays run.
  if (landed) {
    caches.gpu().setInstanceSlot(landed->slot);
    shown = showLanded(*landed, *spareVisibility);
    caches.gpu().setInstanceSlot(f.slot);
  }
  // This frame's GL copy (lights, materials) and raster effects, now that nothing shown needs the old ones.
  FrameStats effects;
  timed(effects.prepareMs, [&] { caches.syncGpu(scene, s.shadingOverride, sampleCamera.shutter, sampleCamera.timeU, s.probeLimit); });
  caches.syncRasterEffects(scene, plan, sampleCamera, visibilityPass, shadePass, in, effects, &gpuTimers);
  viewInputs(plan, sampleCamera, in);
  f.in = in;
  timed(effects.bookkeepingMs, [&] { remember(plan, sampleCamera, in); });

  // The call's result: the frame it showed, or none (the pipeline filling).
  FrameStats result;
  if (shown) {
    result = *shown;
  } else {
    result.pipelined = true;
    result.pipelineFilling = true;
    result.samples = 0;
  }
  Timer book;
  glFinish();  // the timestamp queries of this call's GL work (as finishFrame)
  result.gpu = gpuTimers.endFrame();
  result.shaderCompiles = static_cast<int>(gl::programsBuilt() - clock.compiledBefore);
  // This frame's budget choice goes with it; the budget learns from the frame shown (by its own stages, not its
  // latency: observeShown) and what the player gets by the interval up to now (Renderer::render sets the
  // call's own).
  stats.budget = budget.stats();
  if (shown) budget.observeShown(result, sinceLastCall ? sinceLastCall->ms() : 0.0);
  stats.prepareMs += effects.prepareMs;
  stats.shadowsMs += effects.shadowsMs;
  stats.probesMs += effects.probesMs;
  stats.bookkeepingMs += effects.bookkeepingMs + book.ms();
  f.stats = stats;
  return result;
}

// The ray pass's own copy of the scene brought to this frame's (a whole copy after a new scene or a latency
// frame, else the instances and lights that changed), then Embree from it. False when Embree refused it.
bool Renderer::Impl::syncRayScene(const Camera& camera) {
  if (!rayHeld || rayPending.replaced) {
    rayScene = scene;
  } else {
    if (rayPending.instancesMoved()) rayScene.instances = scene.instances;
    if (rayPending.lights) rayScene.lights = scene.lights;
  }
  rayHeld = true;
  rayPending = {};
  return caches.syncRays(rayScene, camera.shutter, *tracer);
}

// The frame in flight, landed: its rays waited for and uploaded (with its exact solids' pixels into its
// visibility buffer, `pass`); from then on nothing of it is the ray pass's, and the next frame's rays may run
// while it is composited (showLanded).
Renderer::Impl::Landed Renderer::Impl::landInFlight(gl::VisibilityPass& pass) {
  assert(inFlight && "landInFlight: no frame in flight");
  InFlight& f = *inFlight;
  Timer wait;
  waitRays();
  if (f.failure) {
    // What latency mode would have thrown from render(), thrown from the call that lands the frame.
    const std::exception_ptr thrown = f.failure;
    inFlight.reset();
    std::rethrow_exception(thrown);
  }
  Landed l;
  l.waitedMs = wait.ms();
  l.uploaded = timed(f.sample.uploadMs, [&] {
    gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Upload);
    return upload(f.plan, f.in, f.sample, f.reused, pass);
  });
  // `last` is this frame until the next one is launched: one that could not be drawn is not on show.
  if (!l.uploaded) last.drawn = false;
  l.plan = std::move(f.plan);
  l.slot = f.slot;
  l.glCamera = f.glCamera;
  l.in = f.in;
  l.stats = f.stats;
  l.sample = f.sample;
  l.since = f.since;
  inFlight.reset();
  return l;
}

// The landed frame composited with its visibility buffer and presented, as drawSample does for a latency
// frame: its stats (pipelined; its latency in totalMs).
FrameStats Renderer::Impl::showLanded(Landed& l, const gl::VisibilityPass& pass) {
  if (l.uploaded)
    timed(l.sample.compositeMs, [&] {
      gl::GpuStage gpu(&gpuTimers, gl::GpuTimers::Composite);
      shade(l.plan, l.glCamera, l.in, pass, l.sample);
    });
  FrameStats out = l.stats;
  out.addSample(l.sample);
  if (l.uploaded) timed(out.presentMs, [&] { present(); });
  else out.error = l.sample.error;
  out.pipelined = true;
  out.raysWaitMs = l.waitedMs;
  out.totalMs = l.since.ms();
  return out;
}

FrameStats Renderer::Impl::completeInFlight(gl::VisibilityPass& pass) {
  Landed l = landInFlight(pass);
  return showLanded(l, pass);
}

std::optional<FrameStats> Renderer::Impl::drain() {
  if (!inFlight) return std::nullopt;
  FrameStats done = completeInFlight(visibilityPass);
  glFinish();
  return done;
}

}  // namespace tandem
