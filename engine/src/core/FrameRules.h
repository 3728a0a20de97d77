#pragma once
// The rules that decide which rays a frame traces, in one place (no GL, no Embree): the Whitted sum's
// weights (docs/shading.md), which materials those weights let reflect or transmit, and which ray effects
// the settings ask of the ray pass. The ray pass (rt::TraceModes, rt::Whitted::weights) and the frame's
// plan (render/FramePlan) both take them from here, so a decision cannot drift from what is traced.
#include "core/Shading.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem {

/// The Whitted sum's reflected and transmitted weights before coverage, at Fresnel reflectance f of the
/// hit (f = 1 and no T under total internal reflection).
struct SumWeights {
  float reflect = 0.0f;   // wR
  float transmit = 0.0f;  // wT
};
/// (The one definition is shaders/shading.glsl's tdWhittedSum, which the shade pass's probes use too.)
inline SumWeights whittedSum(float kr, float kt, float f, bool totalInternal, bool fresnelWeighted) {
  const glm::vec2 w = shading::tdWhittedSum(kr, kt, f, totalInternal, fresnelWeighted);
  return {w.x, w.y};
}

/// Whether reflected rays from a material can carry weight at some hit of some depth: wR at the largest
/// Fresnel reflectance its surface reaches — 1 at grazing incidence and under total internal reflection,
/// 0 everywhere when its IOR is 1 (no interface). Glass without kr reflects by Fresnel; a frame that
/// skipped its reflection rays lost that light and, under TIR, all of it.
inline bool mayReflect(const Material& m, bool fresnelWeighted) {
  const float fMax = m.kt > 0.0f && m.ior != 1.0f ? 1.0f : 0.0f;
  return whittedSum(m.kr, m.kt, fMax, false, fresnelWeighted).reflect > 0.0f;
}
/// Whether transmitted rays from a material can carry weight: kt > 0, or BLEND coverage (its uncovered
/// fraction passes straight through).
inline bool mayTransmit(const Material& m) { return m.kt > 0.0f || m.alphaMode == AlphaMode::Blend; }
/// Whether a material has a glossy lobe that rays sample (roughness, and something reflected or transmitted
/// under either Fresnel rule): the sampled effect FrameSettings::glossSamples draws, and the filter's lobes.
inline bool hasGlossyLobe(const Material& m) {
  return m.roughness > 0.0f && (mayReflect(m, true) || mayReflect(m, false) || mayTransmit(m));
}

/// The ray effects of a frame: what the ray pass traces.
struct RayEffects {
  bool primaryShadows = false;    // the primary points' light mask by shadow rays
  bool secondaryShadows = false;  // shadow rays at reflected and refracted hits (no shadow map covers them)
  bool reflections = false;
  bool refraction = false;
  bool any() const { return primaryShadows || secondaryShadows || reflections || refraction; }
};
/// The hybrid frame: effects by rays are traced; raster shadows still need rays at secondary hits.
inline RayEffects hybridRayEffects(const FrameSettings& s) {
  RayEffects e;
  e.primaryShadows = s.shadows == EffectMode::Ray;
  e.secondaryShadows = s.shadows != EffectMode::Off;
  e.reflections = s.reflections == EffectMode::Ray;
  e.refraction = s.refraction == EffectMode::Ray;
  return e;
}
/// The reference frame: every effect that is not off is traced.
inline RayEffects referenceRayEffects(const FrameSettings& s) {
  RayEffects e;
  e.primaryShadows = e.secondaryShadows = s.shadows != EffectMode::Off;
  e.reflections = s.reflections != EffectMode::Off;
  e.refraction = s.refraction != EffectMode::Off;
  return e;
}

}  // namespace tandem
