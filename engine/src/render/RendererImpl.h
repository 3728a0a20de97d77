#pragma once
// The Renderer's state (Renderer::Impl), shared by the frame (Renderer.cpp: render and its stages, top to
// bottom; PipelinedFrame.cpp: the same stages in throughput mode) and the rest of the API (RendererApi.cpp:
// creation, the frame's targets, the scene's mutators, tracePixel, output). Internal: only those files include it.
#include <cassert>
#include <cstdint>
#include <exception>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/RenderSpace.h"
#include "core/Sampling.h"
#include "core/Shading.h"
#include "core/Timer.h"
#include "gl/FrameLimits.h"
#include "gl/Gl.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/DenoisePass.h"
#include "gl/GpuTimers.h"
#include "gl/OutputPass.h"
#include "gl/Program.h"
#include "gl/RasterEffects.h"
#include "gl/ShadePass.h"
#include "gl/ShadowProofPass.h"
#include "gl/VisibilityPass.h"
#include "render/Accumulation.h"
#include "render/FrameBudget.h"
#include "render/FrameHistory.h"
#include "render/FramePlan.h"
#include "render/RadiosityJob.h"
#include "render/SceneCaches.h"
#include "render/SceneChanges.h"
#include "rt/EmbreeScene.h"
#include "rt/RayReuse.h"
#include "rt/RayTracer.h"
#include "tandem/Log.h"
#include "tandem/Renderer.h"

namespace tandem {

// Throughput mode (FrameSettings::pipelined, docs/pipeline.md): the frame in flight (Renderer::Impl::inFlight) and
// the frame landed (its rays done and uploaded, to be composited): defined out of Impl so that std::optional
// can construct them while Impl is still being defined.
struct InFlightFrame {
  FramePlan plan;
  Camera camera;
  Camera glCamera;
  gl::ShadeInputs in;
  FrameStats stats;   // the frame's plan and prepare; `sample` holds the rest
  FrameStats sample;  // its raster and read-back (the call that began it), its rays (the job), upload and composite
  rt::RayReuse kept;  // the answers it keeps from the frame before (keepsSome), read by the job
  bool keeps = false;
  bool reused = false;  // the last frame's rays whole: no job
  int slot = 0;         // the GL copy's instance records it was drawn with (GpuScene::instanceSlot)
  Timer since;          // from the start of the call that began it
  std::thread rays;     // joinable while the ray pass runs
  std::exception_ptr failure;  // what the ray pass threw (bad_alloc): rethrown when the frame lands
};
struct LandedFrame {
  FramePlan plan;
  Camera glCamera;
  gl::ShadeInputs in;
  FrameStats stats, sample;
  int slot = 0;
  bool uploaded = false;
  double waitedMs = 0;
  Timer since;
};

struct Renderer::Impl {
  GlContext* context = nullptr;
  std::unique_ptr<rt::RayTracer> tracer;
  gl::VisibilityPass visibilityPass;
  gl::ShadePass shadePass;
  gl::OutputPass outputPass;
  // Hybrid shadows proved in the GL (FramePlan::glShadowProofs): made on first use.
  std::optional<gl::ShadowProofPass> proofPass;
  bool proofFailed = false;  // its program did not build: the ray pass proves on the CPU from then on
  ProofRoute proofRoute;  // the GL proofs' route under Auto: the maps' history (FramePlan.h)
  SceneCaches caches;  // the GL copy, the raster effects and the Embree scene, with what they miss
  RadiosityJob radiosity;  // FrameSettings::radiosity: the solution, solved from the scene as it is
  FrameBudget budget;  // FrameSettings::targetMs: what each frame is drawn with
  gl::GpuTimers gpuTimers;  // the GL stages' GPU time (FrameStats::gpu)
  Scene scene;

  rt::VisibilityBuffer visibility;
  rt::RayOutputs rays;
  // Exact solids: what the resolve step found at the pixels of their proxies (drawn into the GL's visibility
  // buffer by upload), kept with the frame's rays since a frame that reuses them needs it drawn again.
  std::vector<ResolvedPixel> resolved;
  ImageF reference;
  // The frame before's ids and rays, swapped out of `visibility` and `rays` by a frame that keeps some of
  // its answers (the camera still, something moved: rt/RayReuse.h).
  rt::VisibilityBuffer keptVisibility;
  rt::RayOutputs keptRays;

  // The frame's GL targets: the size they have, or the size they could not have and why (render() does
  // not try that size again; resize() does).
  gl::FrameLimits limits;
  int targetWidth = 0, targetHeight = 0;
  int failedWidth = 0, failedHeight = 0;
  std::string failure;

  // The last frame drawn, as the next frame's decisions and tracePixel need it (render/FrameHistory.h).
  FrameHistory last;

  Accumulation accum;  // anti-aliasing and progressive accumulation: the samples so far (render/Accumulation.h)

  // What the mutators changed since the last frame: recorded here, applied to everything derived from the
  // scene by applyChanges at the start of the next frame or trace (render/SceneChanges.h).
  SceneChanges changes;
  void applyChanges() {
    if (!changes.any()) return;
    rayPending |= changes;
    caches.apply(changes, scene);
    radiosity.apply(changes);
    last.apply(changes);
    if (changes.replaced) {
      ++sceneGeneration;  // the motion view's last frame showed another scene
      waitRays();      // a frame in flight may be reading the kept answers released here
      releaseKept();   // the second copy is the old scene's
      budget.reset();  // what the old scene cost says nothing of the new one
    }
    changes = {};
  }
  // The floating origin (core/RenderSpace.h): a camera farther from the render anchor than anchorReach moves it
  // to itself before anything of the frame is synced or drawn (no frame in flight: its records and rays are of
  // the old anchor). Nothing of the last frame's rays is kept (its hits lie in the old render space); the motion
  // and the filter's histories are held in world space and go on (motionInputs).
  void followCamera(const Camera& camera) {
    if (caches.follow(camera)) last.sceneChanged = last.sceneReplaced = true;
  }

  // Throughput mode (FrameSettings::pipelined, docs/pipeline.md): the frame whose ray pass runs on its own
  // thread while render() returns, and what the next call needs to complete it. Everything the ray pass reads
  // or writes (rayScene, tracer, visibility, rays, kept*, resolved) is the job's until waitRays(); the GL
  // state it is composited with (its visibility buffer, instance slot, lights, raster effects) stays as it
  // was drawn.
  using InFlight = InFlightFrame;
  std::optional<InFlight> inFlight;
  // What the ray pass of a frame in flight reads for the scene: a copy made at each launch (the instances and
  // lights that changed since, the whole scene after a new one), so that the scene's mutators can change
  // `scene` for the next frame while it runs. Held only in throughput mode (rayHeld).
  Scene rayScene;
  bool rayHeld = false;
  SceneChanges rayPending;  // changes since rayScene was last brought up to date
  bool syncRayScene(const Camera& camera);
  // Throughput mode's own memory (cost follows the settings: a frame whose settings do not ask for it frees
  // it; latency-mode frames drawn while they do keep it, so that the next pipelined frame has nothing to make
  // again): the ray pass's scene copy, the second visibility buffer and id read-back, the GL copy's second
  // instance slot. Only with no frame in flight.
  void releasePipeline() {
    assert(!inFlight && "releasePipeline: a frame is in flight");
    rayScene = Scene{};
    rayHeld = false;
    rayPending = {};
    spareVisibility.reset();
    stagedVisibility = {};
    caches.gpu().dropOtherInstanceSlot();
  }
  // The frame in flight's visibility buffer while the next frame is rasterized (swapped with visibilityPass),
  // and the next frame's ids read back while the one in flight traces. Made by the first frame that overlaps.
  std::optional<gl::VisibilityPass> spareVisibility;
  rt::VisibilityBuffer stagedVisibility;
  // FrameStats::intervalMs: when the last render() call returned.
  std::optional<Timer> sinceLastCall;

  // The ray pass of the frame in flight finished (joined): what landing it and the destructor wait for. No-op
  // without one.
  void waitRays() {
    if (inFlight && inFlight->rays.joinable()) inFlight->rays.join();
  }
  // The frame in flight completed: its rays waited for, uploaded and composited with its own visibility buffer
  // (`pass`), presented. Its stats (pipelined, latency in totalMs); error set when it could not be drawn.
  // In two halves, so that the next frame's rays can run while it is composited: landInFlight (wait, upload;
  // the frame leaves `inFlight`) and showLanded (composite, present, stats).
  using Landed = LandedFrame;
  Landed landInFlight(gl::VisibilityPass& pass);
  FrameStats showLanded(Landed& landed, const gl::VisibilityPass& pass);
  FrameStats completeInFlight(gl::VisibilityPass& pass);
  // The frame in flight completed before anything else is drawn (a latency frame, resize, tracePixel,
  // finish): its stats, or nullopt when none was in flight.
  std::optional<FrameStats> drain();
  ~Impl() { waitRays(); }

  // Renderer::render but for its interval: the frame in latency mode, or its part in throughput mode.
  FrameStats renderFrame(const Camera& camera, const FrameSettings& requested);
  Result<void> allocateFrame(int width, int height);
  // One sample of the frame: raster → readback → rays → upload → shade with `camera` (jittered by the
  // caller when anti-aliasing), its times and rays added to `stats`. `only`: the pixels whose rays are
  // traced (adaptive rounds; nullptr: all). False when it could not be drawn (stats.error says why).
  bool drawSample(const FramePlan& plan, const Camera& camera, FrameStats& stats, bool lastDrawn,
                  const std::vector<std::uint8_t>* only);
  // readback → rays of one sample that does not reuse the last frame's rays whole.
  void traceSample(const FramePlan& plan, const Camera& camera, FrameStats& sample, bool lastDrawn,
                   const std::vector<std::uint8_t>* only);
  // Before a sample's ray pass: whether it keeps some of the last frame's shadow answers (then `visibility`
  // and `rays` are swapped into keptVisibility and keptRays, and `kept` points at them).
  // `seen`: the scene the rays see (`scene`, or rayScene in throughput mode).
  bool keepAnswers(const FramePlan& plan, const Camera& camera, FrameStats& sample, bool lastDrawn, bool partial,
                   rt::RayReuse& kept, const Scene& seen);
  // The ray pass proper, from the ids in `visibility`: the exact solids' resolve step, then the rays.
  void traceVisible(const FramePlan& plan, const Camera& camera, FrameStats& sample, const rt::RayReuse* kept,
                    std::span<const std::uint8_t> only, const Scene& seen);
  // The frame as a mean of samples (aa or accumulate): draws this frame's samples into `accum` and shows
  // their mean. False when a sample could not be drawn.
  bool drawSampled(const FramePlan& plan, const Camera& camera, FrameStats& stats, bool lastDrawn);

  // The frame's start and end around its stages: the scene's recorded changes applied, whether the last
  // frame was drawn, the shader compiles and the total time counted; at the end the GPU's times, the budget's
  // view of the frame and its total.
  struct FrameClock {
    Timer total;
    std::uint64_t compiledBefore = 0;
    bool lastDrawn = false;
  };
  FrameClock startFrame(FrameStats& stats);
  FrameStats finishFrame(const FrameClock& clock, FrameStats& stats);
  // render() in throughput mode for a frame the pipeline takes (FrameSettings::pipelined's conditions).
  // `changed`: what the scene's mutators changed since the last call; `accumulating`: the frame is an
  // accumulation's first sample (`camera` already the sample's).
  FrameStats renderPipelined(const FrameClock& clock, FramePlan& plan, const Camera& camera, FrameStats& stats,
                             const SceneChanges& changed, bool accumulating);

  // The frame's stages (Renderer::render calls them in order). A stage that cannot go on sets
  // stats.error and returns false: the frame is then not drawn.
  // `syncGl`, `syncEmbree`: whether it brings the GL copy and the Embree scene up to date (throughput mode
  // does either at another point of the frame).
  bool prepare(FramePlan& plan, const Camera& camera, FrameStats& stats, bool syncGl, bool syncEmbree);
  // raster: the raster effects' maps (their own stages, shadows and probes), then the visibility pass.
  // (`camera`: the sample's in world space; `glCamera`: the same in render space, as the GL passes draw it)
  void raster(const FramePlan& plan, const Camera& camera, const Camera& glCamera, gl::ShadeInputs& in,
              FrameStats& stats);
  // Its parts, which throughput mode runs apart: the shade inputs of local shading, those of the view (not
  // the probes'), the visibility pass.
  void localInputs(const FramePlan& plan, gl::ShadeInputs& in) const;
  void viewInputs(const FramePlan& plan, const Camera& camera, gl::ShadeInputs& in);

  // The motion view (DebugView::Motion, docs/motion.md; render/Motion.cpp): what a frame knows of the one
  // before it. motionInputs (with the view inputs) gives the frame each instance's previous-from-current
  // transform against the last frame composited, and notes this frame's transforms and camera as pending;
  // rememberMotion (after the composite, in either mode) makes the pending frame the last one and copies its
  // ids and depth. All of it goes when the view is off (cost follows the settings).
  struct MotionFrame {
    bool held = false;
    std::uint64_t call = 0;  // the render() call that drew it (a frame of several samples draws several)
    std::uint64_t sceneGeneration = 0;
    glm::vec3 anchor{0.0f};  // the render space it was drawn in
    int width = 0, height = 0;
    // Its camera in world space (the sample's as the GL drew it: its lens point and sub-pixel offset in): a later
    // frame takes it to its own render space, which the floating origin may have moved since (core/RenderSpace.h).
    Camera camera;
    FrameSettings shading;  // the filter: its settings as they shape the light (shadingSettings)
    std::vector<glm::dmat4> worldFromObject;
    std::vector<Light> lights;  // the area lights: the filter's history does not outlive a change of one
    std::vector<Light> otherLights;  // the rest: a change of one changes what glossy lobes gather
  };
  // last: the frame the motion is measured against (an earlier call's); next: the last one composited, made
  // `last` by the first frame of a later call; pending: the frame being drawn.
  MotionFrame motionLast, motionNext, motionPending;
  std::uint64_t sceneGeneration = 0;
  std::uint64_t calls = 0;  // render() calls so far
  gl::Buffer motionBuffer;
  gl::Texture motionTexture, previousIds, previousDepth, nextIds, nextDepth;
  std::size_t motionBufferBytes = 0;
  void motionInputs(const FramePlan& plan, const Camera& camera, gl::ShadeInputs& in);
  // The filter's part of them: whether its history holds, and the boxes of what moved.
  void denoiseInputs(const MotionFrame& before, const MotionFrame& now, gl::ShadeInputs& in) const;
  static FrameSettings shadingSettings(const FrameSettings& s);
  void rememberMotion(const FramePlan& plan, const gl::VisibilityPass& pass);
  void rasterVisibility(const FramePlan& plan, const Camera& glCamera, FrameStats& stats);
  // Before the read-back: the GL's shadow proofs (FramePlan::glShadowProofs); true when it drew them.
  bool proveShadows(const FramePlan& plan, const Camera& camera, FrameStats& stats);
  // A frame without them frees the GL's copy of the maps (~82 MB per point light), made again when asked.
  void releaseGlProofs() {
    if (proofPass && proofPass->generation() != 0) proofPass->release();
  }
  void readback(const FramePlan& plan, bool proved, rt::VisibilityBuffer& into);
  // rays, first step: the exact solids' proxy pixels by camera rays (FramePlan::resolve); the rays traced.
  std::uint64_t resolveExact(const FramePlan& plan, const Camera& camera, const Scene& seen);
  void traceRays(const FramePlan& plan, const Camera& camera, FrameStats& stats, const rt::RayReuse* reuse,
                 std::span<const std::uint8_t> only, const Scene& seen);
  void reuseRays(const FramePlan& plan, FrameStats& stats);
  // Cost follows the settings: the second copy goes when reuse is off or the scene is replaced.
  void releaseKept() {
    keptVisibility = {};
    keptRays = {};
  }
  // `pass`: the visibility buffer the frame was rasterized into (visibilityPass, or in throughput mode the
  // spare one while the next frame's is drawn).
  bool upload(const FramePlan& plan, gl::ShadeInputs& in, FrameStats& stats, bool reused, gl::VisibilityPass& pass);
  void shade(const FramePlan& plan, const Camera& glCamera, const gl::ShadeInputs& in, const gl::VisibilityPass& pass,
             FrameStats& sample);

  // The spatiotemporal filter (FrameSettings::denoise, docs/denoise.md; render/Denoise.cpp): made on first use,
  // released when the setting is off (cost follows the settings; its programs stay while a frame-time budget
  // may take it again: leaveDenoise). Each filtered frame draws the next sample of
  // one sequence (denoiseSample; an accumulation's first frame starts there: firstDenoiseSample), so the
  // history gathers new samples. shadeDenoised shades the frame into the filter's target and filters it into
  // the output; false when the frame is not filtered (then shaded as usual).
  std::optional<gl::DenoisePass> denoisePass;
  bool denoiseFailed = false;  // its programs did not build: frames are drawn without it from then on
  bool denoiseLensWarned = false;  // a camera its motion vectors do not model was said once
  // The plan as the filter takes it: without it once its programs failed (the rays then draw lightSamples at
  // every point); the filter on a camera its motion vectors do not model logged (once).
  FramePlan denoisePlan(FramePlan plan, const SceneFacts& facts);
  FilteredSequence denoiseSamples;
  Camera denoiseSample(const FramePlan& plan, const Camera& camera) {
    return plan.denoise ? denoiseSamples.next(camera, {plan.settings.width, plan.settings.height}) : camera;
  }
  std::uint32_t firstDenoiseSample(const FramePlan& plan) { return plan.denoise ? denoiseSamples.take() : 0u; }
  bool shadeDenoised(const FramePlan& plan, const Camera& glCamera, const gl::ShadeInputs& in,
                     const gl::VisibilityPass& pass, FrameStats& sample);
  /// A frame without the filter (FrameSettings::denoise off): its targets go, and its programs unless a
  /// frame-time budget may take it again.
  void leaveDenoise();
  void present();
  // What tracePixel re-runs: the frame as it was drawn.
  void remember(const FramePlan& plan, const Camera& camera, const gl::ShadeInputs& in) {
    last.remember(plan, camera, scene, in.shadowMaps != nullptr, in.probeCubes ? in.probeEffects : 0);
  }
};

}  // namespace tandem
