#include "render/SceneCaches.h"

#include "tandem/Log.h"

namespace tandem {

void SceneCaches::sceneChanged() {
  gpuStale_ = true;
  rtSceneStale_ = true;
  rtBroken_ = false;
}

void SceneCaches::instanceMoved() {
  gpuInstancesStale_ = true;
  rtTransformsStale_ = true;
}

void SceneCaches::lightChanged() {
  gpuLightsStale_ = true;
  rtTransformsStale_ = true;
}

void SceneCaches::syncGpu(const Scene& scene, std::optional<ShadingModel> shadingOverride) {
  if (gpuStale_) {
    gpu_.upload(scene, shadingOverride);
    meshBounds_ = gl::meshBounds(scene);
    gpuStale_ = gpuInstancesStale_ = gpuLightsStale_ = false;
    ++gpuVersion_;
  }
  if (gpuInstancesStale_) gpu_.updateInstances(scene), ++gpuVersion_;
  if (gpuLightsStale_) gpu_.updateLights(scene), ++gpuVersion_;
  if (gpu_.shadingOverride() != shadingOverride) gpu_.updateMaterials(scene, shadingOverride), ++gpuVersion_;
  gpuInstancesStale_ = gpuLightsStale_ = false;
}

bool SceneCaches::syncRays(const Scene& scene, rt::RayTracer& tracer) {
  if (rtBroken_) return false;
  if (rtSceneStale_) {
    auto built = tracer.setScene(scene);
    if (!built) {
      logError("Renderer: the ray pass cannot use this scene, ray effects are off: " + built.error().message);
      rtBroken_ = true;
    }
    rtSceneStale_ = rtTransformsStale_ = false;
  } else if (rtTransformsStale_) {
    tracer.updateTransforms(scene);
    rtTransformsStale_ = false;
  }
  return !rtBroken_;
}

void SceneCaches::syncRasterEffects(const Scene& scene, const FramePlan& plan, const gl::VisibilityPass& raster,
                                    gl::ShadePass& shade, gl::ShadeInputs& in) {
  const int probeEffects = (plan.probeReflections ? gl::kProbeReflect : 0) | (plan.probeRefraction ? gl::kProbeRefract : 0);
  std::vector<gl::Bounds> instanceBounds;
  if (plan.rasterShadows || probeEffects != 0) instanceBounds = gl::instanceBounds(scene, meshBounds_, gpu_.anchor());
  if (plan.rasterShadows) {
    if (shadowVersion_ != gpuVersion_) {
      gl::Bounds world;
      for (const gl::Bounds& b : instanceBounds) world.add(b);
      shadowMaps_.update(scene, gpu_, raster, world);
      shadowVersion_ = gpuVersion_;
    }
    if (shadowMaps_.mapCount() + shadowMaps_.cubeCount() > 0) in.shadowMaps = &shadowMaps_;
  } else if (shadowVersion_ != 0) {
    shadowMaps_.release();  // cost follows the settings: no maps held while shadows are not raster
    shadowVersion_ = 0;
  }
  if (probeEffects != 0) {
    const bool shadowed = in.shadowMaps != nullptr;
    if (probeVersion_ != gpuVersion_ || probesShadowed_ != shadowed) {
      // The probes see local shading only (no ray results, no probes): one bounce.
      gl::ShadeInputs local = in;
      probes_.update(scene, gpu_, raster, shade, local, instanceBounds);
      probeVersion_ = gpuVersion_;
      probesShadowed_ = shadowed;
    }
    if (probes_.probeCount() > 0) {
      in.probeCubes = &probes_.cubes();
      in.probeEffects = probeEffects;
    }
  } else if (probeVersion_ != 0) {
    probes_.release();
    probeVersion_ = 0;
  }
}

}  // namespace tandem
