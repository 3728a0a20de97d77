#include "render/FramePlan.h"

#include <algorithm>

namespace tandem {

namespace {
// The ray pass traces effects by rays; raster effects are the GL passes' (shadow maps, probes).
EffectMode rayOnly(EffectMode m) { return m == EffectMode::Ray ? EffectMode::Ray : EffectMode::Off; }
}  // namespace

SceneFacts sceneFacts(const Scene& scene) {
  SceneFacts f;
  f.shadowLight = std::any_of(scene.lights.begin(), scene.lights.end(),
                              [](const Light& l) { return l.type != LightType::Ambient && l.castShadows; });
  for (const Material& m : scene.materials) {
    const bool weighted = mayReflect(m, true), classic = mayReflect(m, false), transmits = mayTransmit(m);
    f.reflectiveWeighted = f.reflectiveWeighted || weighted;
    f.reflectiveClassic = f.reflectiveClassic || classic;
    f.transmissive = f.transmissive || transmits;
    f.glossy = f.glossy || hasGlossyLobe(m);
  }
  f.areaLight = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return isAreaLight(l.type); });
  f.exactSolids = std::any_of(scene.instances.begin(), scene.instances.end(), [&](const Instance& inst) {
    return inst.mesh < scene.meshes.size() && scene.meshes[inst.mesh].exact.has_value();
  });
  return f;
}

SceneFacts sceneFacts(const Scene& scene, const Camera& camera) {
  SceneFacts f = sceneFacts(scene);
  f.lensOrShutter = camera.aperture > 0.0f || camera.orthographic || camera.shutter > 0.0f;
  return f;
}

void FramePlan::withoutRays() {
  rayPass = false;
  reference = false;
  resolve = false;
  glShadowProofs = false;
}

FramePlan planFrame(const SceneFacts& facts, const FrameSettings& requested) {
  FramePlan p;
  const FrameSettings s = requested.resolved();
  p.settings = s;
  const bool reflective = facts.reflective(s.fresnelWeighted);
  // Raster shadows stay "raster" for the ray pass: its primary points take the shadow maps' answer, but
  // secondary hits have no map and trace shadow rays.
  FrameSettings r = s;
  r.reflections = rayOnly(s.reflections);
  r.refraction = rayOnly(s.refraction);
  if (!facts.shadowLight) r.shadows = EffectMode::Off;
  if (!reflective || s.maxDepth == 0) r.reflections = EffectMode::Off;
  if (!facts.transmissive || s.maxDepth == 0) r.refraction = EffectMode::Off;
  p.raySettings = r;
  p.reference = s.reference && s.debugView == DebugView::Final;
  const bool wantsRays = r.shadows == EffectMode::Ray || r.reflections == EffectMode::Ray || r.refraction == EffectMode::Ray;
  p.rayPass = wantsRays && !p.reference;
  p.rays = p.reference ? referenceRayEffects(s) : p.rayPass ? hybridRayEffects(r) : RayEffects{};
  p.resolve = facts.exactSolids && !p.reference;
  p.denoise = p.raySettings.denoise = s.denoise && !p.reference && s.debugView == DebugView::Final;
  p.glShadowProofs = p.rayPass && p.rays.primaryShadows && r.hybridShadows &&
                     (r.shadowProofs == ShadowProofs::Gl || (r.shadowProofs == ShadowProofs::Auto && !facts.softwareGl));
  // Raster effects only for what the scene can show (a glass object reflects through its Fresnel term).
  p.rasterShadows = s.shadows == EffectMode::Raster && facts.shadowLight && !p.reference;
  if (s.maxDepth > 0 && !p.reference) {
    p.probeReflections = s.reflections == EffectMode::Raster && (reflective || facts.transmissive);
    p.probeRefraction = s.refraction == EffectMode::Raster && facts.transmissive;
  }
  return p;
}

bool sameRayInputs(const FramePlan& a, const FramePlan& b) {
  if (a.rayPass != b.rayPass || a.reference != b.reference || a.resolve != b.resolve ||
      !(a.rayPass || a.reference || a.resolve))
    return false;
  // What the ray pass reads: raySettings for the hybrid pass, settings for the reference frame.
  auto rayPart = [](const FramePlan& p) {
    FrameSettings s = p.reference ? p.settings : p.raySettings;
    s.toneMap = FrameSettings{}.toneMap;
    s.exposure = FrameSettings{}.exposure;
    s.debugView = FrameSettings{}.debugView;
    s.probesPerFrame = FrameSettings{}.probesPerFrame;
    s.probeSize = FrameSettings{}.probeSize;
    s.probeLimit = FrameSettings{}.probeLimit;
    s.reuseRays = FrameSettings{}.reuseRays;
    s.targetMs = FrameSettings{}.targetMs;  // the budget's choice is in the other fields
    // The filter works on the shaded frame, after the rays; they read only how many light samples it leaves
    // to the points past it.
    s.lightSamplesPastFilter = s.unfilteredLightSamples();
    s.denoise = FrameSettings{}.denoise;
    return s;
  };
  return rayPart(a) == rayPart(b);
}

bool glProofsThisFrame(const FramePlan& plan, bool mapsChanged, bool mapsChangedBefore) {
  if (!plan.glShadowProofs) return false;
  return plan.raySettings.shadowProofs == ShadowProofs::Gl || !(mapsChanged && mapsChangedBefore);
}

}  // namespace tandem
