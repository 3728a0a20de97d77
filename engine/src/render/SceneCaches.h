#pragma once
// The scene's derived copies and what they are missing: the GL copy (GpuScene) and the raster effects
// made from it (shadow maps, probes), and the Embree scene. The Scene is the truth; these are caches,
// told what changed (apply, from the frame's SceneChanges) and brought up to date by the sync calls the frame
// makes. All the caches' stale flags and version counters live here and nowhere else.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/RenderSpace.h"
#include "gl/BehindView.h"
#include "gl/GpuScene.h"
#include "gl/GpuTimers.h"
#include "gl/RasterEffects.h"
#include "gl/ReflectionProbes.h"
#include "gl/ShadePass.h"
#include "gl/VisibilityPass.h"
#include "render/FramePlan.h"
#include "render/SceneChanges.h"
#include "rt/RayTracer.h"

namespace tandem {

class SceneCaches {
 public:
  // ---- what changed ----
  /// A new scene: everything is made again, around the scene camera's position (the anchor). An instance
  /// (static or dynamic) moved: the GL instance buffer is patched and Embree's top level updated; no mesh's BVH
  /// is rebuilt. A light: the GL lights re-packed.
  void apply(const SceneChanges& changes, const Scene& scene);

  // ---- the floating origin (core/RenderSpace.h) ----
  /// The origin of render space the GL copy and the Embree scene are brought to at their syncs.
  glm::vec3 anchor() const { return anchor_; }
  /// Whether a frame from `camera` moves the anchor (the camera farther from it than anchorReach).
  bool anchorDue(const Camera& camera) const { return tandem::anchorDue(anchor_, camera); }
  /// Moves the anchor to the camera's position when that is due; true when it moved. The syncs then re-pack
  /// the GL copy's instances and lights and re-read Embree's top level (no mesh is uploaded or rebuilt), and the
  /// raster effects are drawn again, the probes as FrameSettings::probesPerFrame allows (their places are render
  /// space). The caller drains a
  /// frame in flight first: its records and rays are of the old anchor.
  bool follow(const Camera& camera);

  // ---- syncs ----
  /// The GL copy: uploaded or patched as needed, re-packed when the shading override changes; moving
  /// instances drawn at time `timeU` of a `shutter` (Camera::shutter, timeU; docs/motion-blur.md), the
  /// raster effects made from it following each new time; uploaded anew for a new `probeLimit`
  /// (FrameSettings::probeLimit: the probe layout is in the instances' records).
  void syncGpu(const Scene& scene, std::optional<ShadingModel> shadingOverride, float shutter = 0.0f,
               float timeU = 0.5f, int probeLimit = FrameSettings{}.probeLimit);
  /// Throughput mode (docs/pipeline.md), with a frame in flight: only the GL copy's instance records, and only
  /// when instances moved, written into instance slot `slot` (the other keeps the frame in flight's); syncGpu
  /// does the rest once that frame is composited. Not for a new scene (syncGpu uploads it) nor an open shutter.
  void syncGpuInstances(const Scene& scene, int slot);
  /// The Embree scene (the only place it is built or committed), with motion for `shutter`. False when
  /// Embree refused the scene: logged once; the frames of this scene then run without rays.
  bool syncRays(const Scene& scene, float shutter, rt::RayTracer& tracer);
  /// The raster effects the plan asks for, re-rendered only when the GL copy changed since they were made
  /// (probes also when the shadowing they were shaded with changed) and released when not asked for;
  /// fills what the shade pass takes from them into `in` (which already holds the frame's shading inputs).
  /// Their cost goes to `stats` (shadowsMs, probesMs) and, where given, the GPU's to `gpuTimers`.
  /// `view`: the frame's camera (world space), which says how much detail the probes need (gl::probeDetail).
  void syncRasterEffects(const Scene& scene, const FramePlan& plan, const Camera& view, const gl::VisibilityPass& raster,
                         gl::ShadePass& shade, gl::ShadeInputs& in, FrameStats& stats, gl::GpuTimers* gpuTimers);

  /// Whether every probe shows the scene as it is (true when there are none): with
  /// FrameSettings::probesPerFrame > 0 they catch up over several frames after a move.
  bool probesCurrent() const { return probeVersion_ == 0 || probeVersion_ == probeInputs(); }
  /// The shutter time the GL copy's moving instances are drawn at (syncGpu's timeU).
  float gpuTime() const { return gpuTime_; }

  /// Each mesh's object-space bounds, as the last upload found them.
  const std::vector<gl::Bounds>& meshBounds() const { return meshBounds_; }
  gl::GpuScene& gpu() { return gpu_; }
  const gl::GpuScene& gpu() const { return gpu_; }

 private:
  gl::GpuScene gpu_;
  glm::vec3 anchor_{0.0f};  // what the GL copy and the Embree scene are synced to (each holds its own)
  gl::ShadowMaps shadowMaps_;
  gl::ReflectionProbes probes_;
  gl::BehindView behind_;
  std::vector<std::uint8_t> behindInstances_;  // gl::behindViewInstances of the GL copy's scene
  std::uint64_t behindLayoutVersion_ = 0;
  std::vector<gl::Bounds> meshBounds_;  // object space, per mesh: recomputed with each upload

  // The GL copy is synced every frame; the Embree scene only on frames whose rays run, so raster-only use
  // never builds a BVH.
  bool gpuStale_ = true;
  bool gpuInstancesStale_ = false;
  bool gpuLightsStale_ = false;
  float gpuShutter_ = 0.0f, gpuTime_ = 0.5f;  // the shutter and time the GL copy's moving instances show
  bool gpuTimeStale_ = false;                 // moving instances to be drawn at a new time
  std::uint64_t timeVersion_ = 0, shadowTimeVersion_ = 0;  // counts those re-draws; what the shadow maps show
  bool rtSceneStale_ = true;
  bool rtTransformsStale_ = false;
  bool rtBroken_ = false;
  // gpuVersion_ counts the GL copy's changes; the effects remember the version they were made from.
  std::uint64_t gpuVersion_ = 1;
  std::uint64_t shadowVersion_ = 0, probeVersion_ = 0;
  // probeVersion_ while some probes of a new layout are not drawn yet (FrameSettings::probesPerFrame).
  static constexpr std::uint64_t kProbesPartial = ~std::uint64_t{0};
  bool probesShadowed_ = false;
  std::uint64_t probesRadiosity_ = 0;  // the radiosity solution the probes last saw (0: none)
  std::uint64_t radiosityChanges_ = 0;  // how often it changed
  int probesLightSamples_ = 0;           // the area-light samples the probes are drawn with (0: none yet)
  std::uint64_t lightSampleChanges_ = 0;  // how often that changed
  /// What the probes show changed: the GL copy, the radiosity solution or their area-light samples (the
  /// counters only grow).
  std::uint64_t probeInputs() const { return gpuVersion_ + radiosityChanges_ + lightSampleChanges_; }
  // What decides which probes exist and how they shade (a new GL copy, the shading override, the anchor): a
  // change draws them all again, FrameSettings::probesPerFrame at a time (syncRasterEffects).
  std::uint64_t gpuLayoutVersion_ = 1, probeLayoutVersion_ = 0;
  // Per probe: probeInputs() when it was last drawn; 0 when it has not been drawn since its cube was made, or
  // must be drawn again (the view needs more detail, a new anchor, shading override or shadowing).
  std::vector<std::uint64_t> probeSlotVersions_;
  std::uint64_t gpuUploadVersion_ = 0, probeUploadVersion_ = 0;  // GL copies made; the one the probes were made for
  std::vector<float> probeDetailDrawn_;  // the detail (gl::probeDetail) each was drawn with, 0 for none yet
  std::vector<float> normalSpread_;      // per mesh (gl::meshNormalSpread), made with the first probes

  /// Returns how many probes it drew.
  int refreshOldestProbes(int budget, const gl::VisibilityPass& raster, gl::ShadePass& shade,
                           const gl::ShadeInputs& local, const std::vector<gl::Bounds>& instanceBounds,
                           const std::vector<float>& detail);
};

}  // namespace tandem
