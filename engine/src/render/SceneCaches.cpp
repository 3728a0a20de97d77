#include "render/SceneCaches.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/Motion.h"
#include "core/Timer.h"
#include "gl/Gl.h"

#include "tandem/Log.h"

namespace tandem {

void SceneCaches::apply(const SceneChanges& changes, const Scene& scene) {
  if (changes.replaced) {
    anchor_ = renderAnchor(scene);
    gpuStale_ = true;
    rtSceneStale_ = true;
    rtBroken_ = false;
  }
  if (changes.instancesMoved()) {
    gpuInstancesStale_ = true;
    rtTransformsStale_ = true;
  }
  if (changes.lights) {
    gpuLightsStale_ = true;
    rtTransformsStale_ = true;
  }
}

bool SceneCaches::follow(const Camera& camera) {
  if (!anchorDue(camera)) return false;
  anchor_ = camera.posW;
  return true;
}

void SceneCaches::syncGpu(const Scene& scene, std::optional<ShadingModel> shadingOverride, float shutter,
                          float timeU, int probeLimit) {
  if (gpu_.probeLimit() != probeLimit) gpuStale_ = true;
  const float open = shutter > 0.0f && std::isfinite(shutter) ? shutter : 0.0f;
  const float time = std::isfinite(timeU) ? std::clamp(timeU, 0.0f, 1.0f) : 0.5f;
  if (open != gpuShutter_ || time != gpuTime_) {
    // Only instances that move (under the new shutter or the old) look any different at another time.
    bool moving = false;
    for (const Instance& inst : scene.instances) moving = moving || isMoving(inst, open) || isMoving(inst, gpuShutter_);
    gpuShutter_ = open;
    gpuTime_ = time;
    if (moving) gpuTimeStale_ = true;
  }
  if (!gpuStale_ && gpu_.anchor() != anchor_) {
    // The floating origin moved: instances and lights are re-packed relative to it, and the raster effects
    // (made in render space: maps fitted to its bounds, probes at its places) are all drawn again.
    gpu_.setAnchor(anchor_);
    gpuInstancesStale_ = gpuLightsStale_ = true;
    ++gpuLayoutVersion_;
  }
  if (gpuStale_) {
    gpu_.upload(scene, shadingOverride, anchor_, probeLimit);
    if (gpuShutter_ > 0.0f) gpu_.updateInstances(scene, gpuShutter_, gpuTime_);
    meshBounds_ = gl::meshBounds(scene);
    normalSpread_.clear();  // made when probes are first drawn (probeDetail)
    gpuStale_ = gpuInstancesStale_ = gpuLightsStale_ = false;
    ++gpuVersion_;
    ++gpuLayoutVersion_;
    ++gpuUploadVersion_;
  }
  if (gpuInstancesStale_) {
    gpu_.updateInstances(scene, gpuShutter_, gpuTime_), ++gpuVersion_;
  } else if (gpuTimeStale_) {
    // Only the time moved: the shadow maps follow it (timeVersion_); the probes keep the time they were
    // drawn at, or every sample of an accumulation would re-render them and none would ever be current.
    gpu_.updateInstances(scene, gpuShutter_, gpuTime_), ++timeVersion_;
  }
  gpuTimeStale_ = false;
  if (gpuLightsStale_) gpu_.updateLights(scene), ++gpuVersion_;
  if (gpu_.shadingOverride() != shadingOverride)
    gpu_.updateMaterials(scene, shadingOverride), ++gpuVersion_, ++gpuLayoutVersion_;
  gpuInstancesStale_ = gpuLightsStale_ = false;
}

void SceneCaches::syncGpuInstances(const Scene& scene, int slot) {
  assert(!gpuStale_ && gpuShutter_ == 0.0f && gpu_.anchor() == anchor_ &&
         "syncGpuInstances: a new scene, a shutter or a new anchor is syncGpu's");
  if (!gpuInstancesStale_) return;
  gpu_.setInstanceSlot(slot);
  gpu_.updateInstances(scene, gpuShutter_, gpuTime_);
  ++gpuVersion_;
  gpuInstancesStale_ = false;
}

bool SceneCaches::syncRays(const Scene& scene, float shutter, rt::RayTracer& tracer) {
  if (rtBroken_) return false;
  const float open = shutter > 0.0f && std::isfinite(shutter) ? shutter : 0.0f;
  if (rtSceneStale_) {
    auto built = tracer.setScene(scene, open, anchor_);
    if (!built) {
      logError("Renderer: the ray pass cannot use this scene, ray effects are off: " + built.error().message);
      rtBroken_ = true;
    }
    rtSceneStale_ = rtTransformsStale_ = false;
  } else if (rtTransformsStale_ || open != tracer.shutter() || tracer.anchor() != anchor_) {
    tracer.updateTransforms(scene, open, anchor_);
    rtTransformsStale_ = false;
  }
  return !rtBroken_;
}

void SceneCaches::syncRasterEffects(const Scene& scene, const FramePlan& plan, const Camera& view,
                                    const gl::VisibilityPass& raster,
                                    gl::ShadePass& shade, gl::ShadeInputs& in, FrameStats& stats,
                                    gl::GpuTimers* gpuTimers) {
  // Each part's time into its stage (the GL's work included: each part ends with glFinish).
  auto stage = [&](double& ms, gl::GpuTimers::Stage which, auto&& work) {
    Timer clock;
    {
      gl::GpuStage gpu(gpuTimers, which);
      work();
      glFinish();
    }
    ms += clock.ms();
  };
  const int probeEffects = (plan.probeReflections ? gl::kProbeReflect : 0) | (plan.probeRefraction ? gl::kProbeRefract : 0);
  std::vector<gl::Bounds> instanceBounds;
  if (plan.rasterShadows || probeEffects != 0)
    instanceBounds = gl::instanceBounds(scene, meshBounds_, gpu_.anchor(), gpuShutter_, gpuTime_);
  auto drawShadowMaps = [&](const std::vector<gl::Bounds>& bounds, float u) {
    stage(stats.shadowsMs, gl::GpuTimers::Shadows, [&] {
      shadowMaps_.update(scene, gpu_, raster, bounds, gl::instanceTransforms(scene, gpu_.anchor(), gpuShutter_, u),
                         gpuLayoutVersion_);
    });
  };
  if (plan.rasterShadows) {
    if (shadowVersion_ != gpuVersion_ || shadowTimeVersion_ != timeVersion_) {
      drawShadowMaps(instanceBounds, gpuTime_);
      shadowVersion_ = gpuVersion_;
      shadowTimeVersion_ = timeVersion_;
    }
    if (shadowMaps_.mapCount() + shadowMaps_.cubeCount() > 0) in.shadowMaps = &shadowMaps_;
  } else if (shadowVersion_ != 0) {
    // Cost follows the settings: no maps held while shadows are not raster (freeing them is the stage's too).
    stage(stats.shadowsMs, gl::GpuTimers::Shadows, [&] { shadowMaps_.release(); });
    shadowVersion_ = 0;
  }
  if (probeEffects != 0) {
    const bool shadowed = in.shadowMaps != nullptr;
    // The probes see local shading only (no ray results, no probes): one bounce.
    gl::ShadeInputs local = in;
    local.softShadows = false;  // a probe's area lights cast hard shadows (ShadeInputs::softShadows)
    // What a probe shows goes past the spatiotemporal filter: with the filter asked for, its area lights draw
    // the samples past it. The settings', not the frame's (a debug view's, an accumulation's samples at rest):
    // the probes are a cache, drawn again (as probesPerFrame says) when that count changes.
    const int samples = plan.settings.unfilteredLightSamples();
    local.lightSamples = samples;
    if (samples != probesLightSamples_) {
      probesLightSamples_ = samples;
      ++lightSampleChanges_;
    }
    const int budget = plan.settings.probesPerFrame;
    // A new radiosity solution changes what they show as a change of the GL copy does (probesPerFrame
    // spreads their re-rendering over frames alike: a background solve publishes ~10 times a second).
    const std::uint64_t radiosity = in.radiosity ? gpu_.radiosityVersion() : 0;
    if (radiosity != probesRadiosity_) {
      probesRadiosity_ = radiosity;
      ++radiosityChanges_;
    }
    // How much detail the view can show in each probe (objects small in a face are drawn coarse): a probe drawn
    // for less than half of what it now needs (the camera came nearer to a mirror reading it) is drawn again.
    if (normalSpread_.empty()) normalSpread_ = gl::meshNormalSpread(scene);
    const std::vector<float> detail = gl::probeDetail(scene, gpu_.probes(), instanceBounds, normalSpread_,
                                                      toRenderSpace(view, gpu_.anchor()), plan.settings.height,
                                                      plan.settings.probeSize);
    if (probeDetailDrawn_.size() == detail.size() && probeSlotVersions_.size() == detail.size())
      for (std::size_t slot = 0; slot < detail.size(); ++slot)
        if (detail[slot] > 2.0f * probeDetailDrawn_[slot] && probeSlotVersions_[slot] != 0) {
          probeSlotVersions_[slot] = 0;
          if (probeVersion_ == probeInputs()) probeVersion_ = kProbesPartial;
        }
    const bool all = probeLayoutVersion_ != gpuLayoutVersion_ || probesShadowed_ != shadowed || probeVersion_ == 0 ||
                     (probes_.probeCount() > 0 && probes_.faceSize() != plan.settings.probeSize) ||
                     (budget <= 0 && probeVersion_ != probeInputs() && probeVersion_ != kProbesPartial);
    // Probes show moving instances at the middle of the shutter, lit by shadow maps of that time, whatever
    // sample's time the GL copy is at: what they hold must not depend on which sample happened to draw them.
    const bool atSampleTime = gpuShutter_ > 0.0f && gpuTime_ != 0.5f &&
                              std::any_of(scene.instances.begin(), scene.instances.end(),
                                          [&](const Instance& inst) { return isMoving(inst, gpuShutter_); });
    std::vector<gl::Bounds> middleBounds;
    if ((all || probeVersion_ != probeInputs()) && atSampleTime) {
      gpu_.updateInstances(scene, gpuShutter_, 0.5f);
      middleBounds = gl::instanceBounds(scene, meshBounds_, gpu_.anchor(), gpuShutter_, 0.5f);
      if (shadowed) drawShadowMaps(middleBounds, 0.5f);
    }
    const std::vector<gl::Bounds>& probeBounds = middleBounds.empty() ? instanceBounds : middleBounds;
    // A new GL copy or probe size makes the probes anew: past the budget they show the environment until their
    // turn. Another change of what they show (a new anchor, shading override or shadowing) keeps what they hold
    // while the budget draws them again, oldest first, as after a move.
    const bool fresh = probeUploadVersion_ != gpuUploadVersion_ || probes_.probeCount() == 0 ||
                       probes_.probeCount() != static_cast<int>(gpu_.probes().probes.size()) ||
                       probes_.faceSize() != plan.settings.probeSize;
    if (all && !fresh && budget > 0) {
      std::fill(probeSlotVersions_.begin(), probeSlotVersions_.end(), 0);
      probeVersion_ = kProbesPartial;
      probeLayoutVersion_ = gpuLayoutVersion_;
      probesShadowed_ = shadowed;
      stage(stats.probesMs, gl::GpuTimers::Probes, [&] {
        stats.probesDrawn += refreshOldestProbes(budget, raster, shade, local, probeBounds, detail);
      });
    } else if (all) {
      probeUploadVersion_ = gpuUploadVersion_;
      int drawn = 0;
      stage(stats.probesMs, gl::GpuTimers::Probes, [&] {
        gpu_.ensureProbeLod(scene);  // once per GL copy: the coarse meshes small objects are drawn with
        drawn = probes_.update(gpu_, raster, shade, local, probeBounds, plan.settings.probeSize, budget, detail);
      });
      stats.probesDrawn += drawn;
      // Those not drawn yet show the environment and are the oldest: the next frames draw them first.
      probeSlotVersions_.assign(static_cast<std::size_t>(probes_.probeCount()), 0);
      std::fill_n(probeSlotVersions_.begin(), drawn, probeInputs());
      probeDetailDrawn_.assign(probeSlotVersions_.size(), 0.0f);
      std::copy_n(detail.begin(), std::min<std::size_t>(static_cast<std::size_t>(drawn), detail.size()),
                  probeDetailDrawn_.begin());
      probeVersion_ = drawn == probes_.probeCount() ? probeInputs() : kProbesPartial;
      probeLayoutVersion_ = gpuLayoutVersion_;
      probesShadowed_ = shadowed;
    } else if (probeVersion_ != probeInputs()) {
      stage(stats.probesMs, gl::GpuTimers::Probes,
            [&] {
              gpu_.ensureProbeLod(scene);
              // Without a budget every stale probe now (a camera that came nearer leaves the others alone).
              stats.probesDrawn += refreshOldestProbes(budget > 0 ? budget : probes_.probeCount(), raster, shade,
                                                       local, probeBounds, detail);
            });
    }
    if (!middleBounds.empty()) {  // back to the sample's time
      gpu_.updateInstances(scene, gpuShutter_, gpuTime_);
      if (shadowed) drawShadowMaps(instanceBounds, gpuTime_);
    }
    stats.probes = probes_.probeCount();
    if (probes_.probeCount() > 0) {
      in.probeCubes = &probes_.cubes();
      in.probeEffects = probeEffects;
    }
    // Raster refraction of see-through surfaces reads what is behind them from this view (gl/BehindView.h):
    // drawn every frame, at the GL copy's time, since it follows the camera.
    if (behindLayoutVersion_ != gpuLayoutVersion_) {
      behindInstances_ = gl::behindViewInstances(scene);
      behindLayoutVersion_ = gpuLayoutVersion_;
    }
    if ((probeEffects & gl::kProbeRefract) && probes_.probeCount() > 0 && !behindInstances_.empty()) {
      Result<void> drawn;
      stage(stats.probesMs, gl::GpuTimers::Probes, [&] {
        drawn = behind_.draw(gpu_, raster, shade, local, probes_.cubes(), toRenderSpace(view, gpu_.anchor()),
                             plan.settings.width, plan.settings.height, behindInstances_);
      });
      if (drawn) {
        in.behindView = &behind_.colour();
        in.probeEffects |= gl::kProbeBehind;
      } else {
        logError("Renderer: see-through surfaces read their probes this frame: " + drawn.error().message);
      }
    } else if (behind_.held()) {
      behind_.release();
    }
  } else if (probeVersion_ != 0) {
    stage(stats.probesMs, gl::GpuTimers::Probes, [&] { probes_.release(); });
    probeSlotVersions_.clear();
    probeDetailDrawn_.clear();
    probeVersion_ = 0;
    behind_.release();
  }
}

// Instances moved or lights changed: the `budget` probes made longest ago, oldest first (a round robin
// while everything keeps moving). probeVersion_ catches up once every probe has been re-rendered since.
int SceneCaches::refreshOldestProbes(int budget, const gl::VisibilityPass& raster, gl::ShadePass& shade,
                                      const gl::ShadeInputs& local, const std::vector<gl::Bounds>& instanceBounds,
                                      const std::vector<float>& detail) {
  std::vector<int> stale;
  for (std::size_t slot = 0; slot < probeSlotVersions_.size(); ++slot)
    if (probeSlotVersions_[slot] != probeInputs()) stale.push_back(static_cast<int>(slot));
  // Oldest first; ties by slot, so the order does not depend on anything but the versions.
  std::stable_sort(stale.begin(), stale.end(), [&](int a, int b) {
    return probeSlotVersions_[static_cast<std::size_t>(a)] < probeSlotVersions_[static_cast<std::size_t>(b)];
  });
  if (stale.size() > static_cast<std::size_t>(budget)) stale.resize(static_cast<std::size_t>(budget));
  probes_.updateSlots(gpu_, raster, shade, local, instanceBounds, stale, detail);
  for (int slot : stale) {
    probeSlotVersions_[static_cast<std::size_t>(slot)] = probeInputs();
    probeDetailDrawn_[static_cast<std::size_t>(slot)] = detail[static_cast<std::size_t>(slot)];
  }
  std::uint64_t oldest = probeInputs();
  for (std::uint64_t v : probeSlotVersions_) oldest = std::min(oldest, v);
  if (oldest == probeInputs()) probeVersion_ = probeInputs();
  return static_cast<int>(stale.size());
}

}  // namespace tandem
