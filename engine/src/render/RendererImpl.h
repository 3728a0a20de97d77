#pragma once
// The Renderer's state (Renderer::Impl), shared by the frame (Renderer.cpp: render and its stages, top to
// bottom) and the rest of the API (RendererApi.cpp: creation, the scene's mutators, tracePixel, output).
// Internal: only those two files include it.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/RenderSpace.h"
#include "core/Sampling.h"
#include "core/Shading.h"
#include "core/Timer.h"
#include "gl/FrameLimits.h"
#include "gl/Gl.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
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

struct Renderer::Impl {
  GlContext* context = nullptr;
  std::unique_ptr<rt::RayTracer> tracer;
  gl::VisibilityPass visibilityPass;
  gl::ShadePass shadePass;
  gl::OutputPass outputPass;
  // Hybrid shadows proved in the GL (FramePlan::glShadowProofs): made on first use.
  std::optional<gl::ShadowProofPass> proofPass;
  bool proofFailed = false;  // its program did not build: the ray pass proves on the CPU from then on
  std::uint64_t lastMapGeneration = 0;  // the maps' generation the last frame saw, and whether it was new
  bool mapsChangedBefore = false;
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
    caches.apply(changes);
    radiosity.apply(changes);
    last.apply(changes);
    if (changes.replaced) {
      releaseKept();   // the second copy is the old scene's
      budget.reset();  // what the old scene cost says nothing of the new one
    }
    changes = {};
  }

  Result<void> allocateFrame(int width, int height);
  // One sample of the frame: raster → readback → rays → upload → shade with `camera` (jittered by the
  // caller when anti-aliasing), its times and rays added to `stats`. `only`: the pixels whose rays are
  // traced (adaptive rounds; nullptr: all). False when it could not be drawn (stats.error says why).
  bool drawSample(const FramePlan& plan, const Camera& camera, FrameStats& stats, bool lastDrawn,
                  const std::vector<std::uint8_t>* only);
  // readback → rays of one sample that does not reuse the last frame's rays whole.
  void traceSample(const FramePlan& plan, const Camera& camera, FrameStats& sample, bool lastDrawn,
                   const std::vector<std::uint8_t>* only);
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

  // The frame's stages (Renderer::render calls them in order). A stage that cannot go on sets
  // stats.error and returns false: the frame is then not drawn.
  bool prepare(FramePlan& plan, const Camera& camera, FrameStats& stats);
  // raster: the raster effects' maps (their own stages, shadows and probes), then the visibility pass.
  void raster(const FramePlan& plan, const Camera& glCamera, gl::ShadeInputs& in, FrameStats& stats);
  // Before the read-back: the GL's shadow proofs (FramePlan::glShadowProofs); true when it drew them.
  bool proveShadows(const FramePlan& plan, const Camera& camera, FrameStats& stats);
  void readback(const FramePlan& plan, bool proved = false);
  // rays, first step: the exact solids' proxy pixels by camera rays (FramePlan::resolve); the rays traced.
  std::uint64_t resolveExact(const FramePlan& plan, const Camera& camera);
  void traceRays(const FramePlan& plan, const Camera& camera, FrameStats& stats, const rt::RayReuse* reuse,
                 std::span<const std::uint8_t> only);
  void reuseRays(const FramePlan& plan, FrameStats& stats) const;
  // Cost follows the settings: the second copy goes when reuse is off or the scene is replaced.
  void releaseKept() {
    keptVisibility = {};
    keptRays = {};
  }
  bool upload(const FramePlan& plan, gl::ShadeInputs& in, FrameStats& stats, bool reused);
  void shade(const FramePlan& plan, const Camera& glCamera, const gl::ShadeInputs& in);
  void present();
  void remember(const FramePlan& plan, const Camera& camera, const gl::ShadeInputs& in);
};

}  // namespace tandem
