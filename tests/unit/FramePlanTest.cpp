// The frame's plan (render/FramePlan.h): which rays and raster effects a frame runs, from what the scene
// can show and the settings. Each decision users found wrong is one test here; the renderer executes the
// plan (tests/gl/FrameDecisionsGLTest.cpp checks the frames).
#include <gtest/gtest.h>

#include "render/FramePlan.h"

namespace tandem {
namespace {

SceneFacts everything() {
  SceneFacts f;
  f.shadowLight = f.reflectiveWeighted = f.reflectiveClassic = f.transmissive = true;
  return f;
}

FrameSettings with(EffectMode shadows, EffectMode reflections, EffectMode refraction, int depth = 4) {
  FrameSettings s;
  s.shadows = shadows;
  s.reflections = reflections;
  s.refraction = refraction;
  s.maxDepth = depth;
  return s;
}

TEST(FramePlan, MayReflectFollowsTheWeights) {
  // mayReflect is wR at the largest Fresnel term the material reaches; checked against the sum itself.
  for (float kr : {0.0f, 0.4f})
    for (float kt : {0.0f, 0.7f})
      for (float ior : {0.5f, 1.0f, 1.5f})
        for (bool weighted : {true, false}) {
          Material m;
          m.kr = kr;
          m.kt = kt;
          m.ior = ior;
          bool some = false;
          for (float f : {0.0f, 0.01f, 0.5f, 1.0f}) {
            const float fr = ior == 1.0f ? 0.0f : f;  // F = 0 at every angle when the IOR is 1
            some |= whittedSum(kr, kt, fr, fr == 1.0f, weighted).reflect > 0.0f;
          }
          EXPECT_EQ(mayReflect(m, weighted), some) << "kr " << kr << " kt " << kt << " ior " << ior << " weighted " << weighted;
        }
}

TEST(FramePlan, GlassWithoutKrReflectsUnderTheWeightedSumOnly) {
  Scene s;
  Material glass;
  glass.kr = 0.0f;
  glass.kt = 0.9f;
  glass.ior = 1.5f;
  s.materials = {glass};
  const SceneFacts f = sceneFacts(s);
  EXPECT_TRUE(f.reflectiveWeighted);
  EXPECT_FALSE(f.reflectiveClassic);
  FrameSettings rays = with(EffectMode::Off, EffectMode::Ray, EffectMode::Ray);
  EXPECT_TRUE(planFrame(f, rays).rays.reflections) << "Fresnel reflection and TIR of glass";
  rays.fresnelWeighted = false;
  EXPECT_FALSE(planFrame(f, rays).rays.reflections) << "the classic sum reflects kr only";
}

TEST(FramePlan, FactsSayWhatIsSampled) {
  // What the frame-time budget offers the filter for (render/FrameBudget.h): an area light; a glossy material
  // that reflects or transmits (a rough one that does neither samples no lobe).
  Scene s;
  Material matte, roughMatte, roughMirror, roughGlass;
  roughMatte.roughness = 0.3f;
  roughMirror.kr = 0.8f;
  roughMirror.roughness = 0.2f;
  roughGlass.kt = 0.9f;
  roughGlass.ior = 1.5f;
  roughGlass.roughness = 0.1f;
  s.materials = {matte, roughMatte};
  Light point;
  point.type = LightType::Point;
  s.lights = {point};
  SceneFacts f = sceneFacts(s);
  EXPECT_FALSE(f.areaLight);
  EXPECT_FALSE(f.glossy);
  for (LightType t : {LightType::Rect, LightType::Disk, LightType::Sphere}) {
    s.lights[0].type = t;
    EXPECT_TRUE(sceneFacts(s).areaLight) << static_cast<int>(t);
  }
  s.lights.clear();
  s.materials = {matte, roughMirror};
  EXPECT_TRUE(sceneFacts(s).glossy);
  s.materials = {roughGlass};
  EXPECT_TRUE(sceneFacts(s).glossy);
  roughGlass.roughness = 0.0f;  // sharp glass: its rays are exact
  s.materials = {roughGlass};
  EXPECT_FALSE(sceneFacts(s).glossy);
  // The frame's camera: a thin lens, orthographic, or an open shutter is motion the filter does not model.
  Camera pinhole;
  EXPECT_FALSE(sceneFacts(s, pinhole).lensOrShutter);
  Camera lens = pinhole, ortho = pinhole, shutter = pinhole;
  lens.aperture = 0.1f;
  ortho.orthographic = true;
  shutter.shutter = 0.02f;
  for (const Camera& c : {lens, ortho, shutter}) EXPECT_TRUE(sceneFacts(s, c).lensOrShutter);
}

TEST(FramePlan, RasterShadowsKeepShadowRaysAtSecondaryHits) {
  const FramePlan p = planFrame(everything(), with(EffectMode::Raster, EffectMode::Ray, EffectMode::Off));
  EXPECT_TRUE(p.rayPass);
  EXPECT_TRUE(p.rasterShadows);
  EXPECT_FALSE(p.rays.primaryShadows) << "the primary points take the shadow maps' answer";
  EXPECT_TRUE(p.rays.secondaryShadows) << "reflected hits have no map";
  EXPECT_EQ(p.raySettings.shadows, EffectMode::Raster);
}

TEST(FramePlan, RasterOnlyEffectsRunNoRayPass) {
  const FramePlan p = planFrame(everything(), with(EffectMode::Raster, EffectMode::Raster, EffectMode::Raster));
  EXPECT_FALSE(p.rayPass);
  EXPECT_FALSE(p.rays.any());
  EXPECT_TRUE(p.rasterShadows && p.probeReflections && p.probeRefraction);
}

TEST(FramePlan, EffectsTheSceneCannotShowAreNotRun) {
  SceneFacts none;
  const FramePlan p = planFrame(none, with(EffectMode::Ray, EffectMode::Ray, EffectMode::Ray));
  EXPECT_FALSE(p.rayPass) << "no shadow-casting light, nothing reflective or transmissive: no ray";
  const FramePlan q = planFrame(none, with(EffectMode::Raster, EffectMode::Raster, EffectMode::Raster));
  EXPECT_FALSE(q.rasterShadows || q.probeReflections || q.probeRefraction);
  const FramePlan flat = planFrame(everything(), with(EffectMode::Off, EffectMode::Ray, EffectMode::Ray, 0));
  EXPECT_FALSE(flat.rayPass) << "depth 0: no secondary ray";
  EXPECT_FALSE(planFrame(everything(), with(EffectMode::Off, EffectMode::Raster, EffectMode::Raster, 0)).probeReflections);
}

TEST(FramePlan, ReferenceTracesEveryEffectThatIsNotOff) {
  FrameSettings s = *presetSettings("reference");
  s.shadows = EffectMode::Raster;
  s.reflections = EffectMode::Off;
  const FramePlan p = planFrame(everything(), s);
  EXPECT_TRUE(p.reference);
  EXPECT_FALSE(p.rayPass);
  EXPECT_TRUE(p.rays.primaryShadows && p.rays.secondaryShadows) << "raster-made effects become rays";
  EXPECT_FALSE(p.rays.reflections);
  EXPECT_FALSE(p.rasterShadows || p.probeReflections || p.probeRefraction) << "the reference uses no raster effect";
  s.debugView = DebugView::NormalW;
  EXPECT_FALSE(planFrame(everything(), s).reference) << "a debug view is the hybrid frame's";
}

// Hybrid shadows' primary rays are proved in the GL where it is a GPU (Auto), always (Gl) or never (Cpu); only
// when the ray pass traces the primary hits' shadow rays at all.
TEST(FramePlan, ShadowProofsGoToTheGlWhereItIsAGpu) {
  FrameSettings s = with(EffectMode::Ray, EffectMode::Ray, EffectMode::Ray);
  s.hybridShadows = true;
  SceneFacts gpu = everything(), software = everything();
  software.softwareGl = true;
  EXPECT_TRUE(planFrame(gpu, s).glShadowProofs);
  EXPECT_FALSE(planFrame(software, s).glShadowProofs) << "on llvmpipe the GL's pass costs more than the CPU's proofs";
  s.shadowProofs = ShadowProofs::Gl;
  EXPECT_TRUE(planFrame(software, s).glShadowProofs);
  s.shadowProofs = ShadowProofs::Cpu;
  EXPECT_FALSE(planFrame(gpu, s).glShadowProofs);
  s.shadowProofs = ShadowProofs::Gl;
  s.hybridShadows = false;
  EXPECT_FALSE(planFrame(gpu, s).glShadowProofs) << "every shadow ray traced: nothing to prove";
  s.hybridShadows = true;
  s.shadows = EffectMode::Raster;
  EXPECT_FALSE(planFrame(gpu, s).glShadowProofs) << "raster shadows: the primary hits trace no shadow ray";
  s.shadows = EffectMode::Ray;
  FramePlan p = planFrame(gpu, s);
  p.withoutRays();
  EXPECT_FALSE(p.glShadowProofs);
}

// Maps built anew every frame (something moves) would be copied to the GL every frame: Auto leaves those frames
// to the CPU (on an H100 the game's run took 246 ms of raster a frame for the copies); Gl copies regardless.
TEST(FramePlan, GlProofsSkipMapsThatChangeEveryFrame) {
  FrameSettings s = with(EffectMode::Ray, EffectMode::Ray, EffectMode::Ray);
  s.hybridShadows = true;
  const FramePlan autoPlan = planFrame(everything(), s);
  ASSERT_TRUE(autoPlan.glShadowProofs);
  EXPECT_TRUE(glProofsThisFrame(autoPlan, false, false));
  EXPECT_TRUE(glProofsThisFrame(autoPlan, true, false)) << "built once (the first frame, a light moved once)";
  EXPECT_TRUE(glProofsThisFrame(autoPlan, false, true));
  EXPECT_FALSE(glProofsThisFrame(autoPlan, true, true)) << "built anew two frames running";
  s.shadowProofs = ShadowProofs::Gl;
  EXPECT_TRUE(glProofsThisFrame(planFrame(everything(), s), true, true));
  s.shadowProofs = ShadowProofs::Cpu;
  EXPECT_FALSE(glProofsThisFrame(planFrame(everything(), s), false, false));
}

// The route's history: maps built anew two frames running go to the CPU; a frame that reused its rays whole
// between two changes breaks the run (it changed nothing), as a traced still frame does.
TEST(FramePlan, ProofRouteCountsAStillFrameAsNoChange) {
  FrameSettings s = *presetSettings("hybrid-full");
  s.hybridShadows = true;
  const FramePlan plan = planFrame(everything(), s);
  ASSERT_TRUE(plan.glShadowProofs);
  ProofRoute traced, reused;
  for (ProofRoute* r : {&traced, &reused}) {
    EXPECT_TRUE(r->inGl(plan, 1)) << "the first maps";
    EXPECT_FALSE(r->inGl(plan, 2)) << "anew two frames running";
  }
  EXPECT_TRUE(traced.inGl(plan, 2)) << "a still frame traced: the same maps";
  reused.still();
  EXPECT_TRUE(traced.inGl(plan, 3)) << "a light moved after the still frame";
  EXPECT_TRUE(reused.inGl(plan, 3)) << "a light moved after a reused frame: the same route";
  EXPECT_FALSE(reused.inGl(plan, 4));
}

TEST(FramePlan, WithoutRaysDropsThePassAndTheReference) {
  FramePlan p = planFrame(everything(), *presetSettings("reference"));
  ASSERT_TRUE(p.needsRayScene());
  p.withoutRays();
  EXPECT_FALSE(p.needsRayScene());
}

// A frame may reuse the last one's rays only when the ray pass would do the same work (the Renderer checks
// the camera and the scene besides): every setting the pass reads counts, the display's do not.
TEST(FramePlan, SameRayInputsComparesWhatTheRayPassReads) {
  const FrameSettings base = *presetSettings("hybrid-full");
  auto same = [&](auto change) {
    FrameSettings s = base;
    change(s);
    return sameRayInputs(planFrame(everything(), base), planFrame(everything(), s));
  };
  EXPECT_TRUE(same([](FrameSettings&) {}));
  EXPECT_TRUE(same([](FrameSettings& s) { s.toneMap = ToneMap::None; }));
  EXPECT_TRUE(same([](FrameSettings& s) { s.exposure = 3.0f; }));
  EXPECT_TRUE(same([](FrameSettings& s) { s.debugView = DebugView::Reflection; }));
  EXPECT_TRUE(same([](FrameSettings& s) { s.probesPerFrame = 2; }));
  EXPECT_TRUE(same([](FrameSettings& s) { s.probeSize = 64; }));
  EXPECT_TRUE(same([](FrameSettings& s) { s.reuseRays = false; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.width += 1; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.maxDepth = 2; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.minContribution = 0.5f; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.rayScale = 2; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.fresnel = FresnelMode::Schlick; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.fresnelWeighted = false; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.shadingOverride = ShadingModel::Flat; }));
  EXPECT_FALSE(same([](FrameSettings& s) { s.shadows = EffectMode::Raster; }));
  // A frame without rays has nothing to reuse; the reference frame only its own kind.
  const FramePlan raster = planFrame(everything(), *presetSettings("raster"));
  EXPECT_FALSE(sameRayInputs(raster, raster));
  const FramePlan reference = planFrame(everything(), *presetSettings("reference"));
  EXPECT_TRUE(sameRayInputs(reference, reference));
  EXPECT_FALSE(sameRayInputs(reference, planFrame(everything(), base)));
}

TEST(FramePlan, TheFilterRunsOnHybridFramesOfOneSampleInTheFinalView) {
  FrameSettings s = *presetSettings("hybrid-full");
  s.denoise = true;
  EXPECT_TRUE(planFrame(everything(), s).denoise);
  FrameSettings raster = *presetSettings("raster");
  raster.denoise = true;
  EXPECT_TRUE(planFrame(everything(), raster).denoise) << "raster shadows of area lights are sampled too";
  FrameSettings view = s;
  view.debugView = DebugView::NormalW;
  EXPECT_FALSE(planFrame(everything(), view).denoise) << "a debug view shows the frame's own values";
  FrameSettings reference = *presetSettings("reference");
  reference.denoise = true;
  EXPECT_FALSE(reference.resolved().denoise) << "the reference is converged, not filtered";
  EXPECT_FALSE(planFrame(everything(), reference).denoise);
  FrameSettings aa = s;
  aa.aa = AntiAlias::Ssaa;
  EXPECT_FALSE(aa.resolved().denoise) << "a frame of several samples has its own";
  EXPECT_FALSE(planFrame(everything(), aa).denoise);
  // The filter is a ray input only by the light samples it leaves to the points past it: with four at every
  // point a frame with it traces what one without it would.
  FrameSettings off = s;
  off.denoise = false;
  EXPECT_TRUE(sameRayInputs(planFrame(everything(), s), planFrame(everything(), off)));
}

// The light the filter does not smooth (a mirror's or glass's ray hits, the probes) is drawn with
// lightSamplesPastFilter samples, at least lightSamples, where the filter runs; every other frame draws
// lightSamples at every point.
TEST(FramePlan, TheLightPastTheFilterDrawsItsOwnSamplesWhereTheFilterRuns) {
  FrameSettings s = *presetSettings("hybrid-full");
  s.lightSamples = 1;
  EXPECT_EQ(s.lightSamplesPastFilter, 4) << "as many as an unfiltered frame's default";
  EXPECT_EQ(s.unfilteredLightSamples(), 1) << "no filter";
  s.denoise = true;
  EXPECT_EQ(s.unfilteredLightSamples(), 4);
  s.lightSamples = 8;
  EXPECT_EQ(s.unfilteredLightSamples(), 8) << "at least lightSamples";
  s.lightSamples = 1;
  s.lightSamplesPastFilter = 99;
  EXPECT_EQ(s.resolved().lightSamplesPastFilter, 32);
  s.lightSamplesPastFilter = 0;
  EXPECT_EQ(s.resolved().lightSamplesPastFilter, 1);
  s.lightSamplesPastFilter = 4;
  // The plan's ray settings say whether the filter runs: not in a debug view, nor for an accumulation's
  // samples summed as drawn (Accumulation::samplePlan).
  FramePlan filtered = planFrame(everything(), s);
  EXPECT_TRUE(filtered.raySettings.denoise);
  EXPECT_EQ(filtered.raySettings.unfilteredLightSamples(), 4);
  FrameSettings view = s;
  view.debugView = DebugView::Reflection;
  EXPECT_EQ(planFrame(everything(), view).raySettings.unfilteredLightSamples(), 1);
  FramePlan summed = filtered;
  summed.withoutFilter();
  EXPECT_FALSE(summed.denoise);
  EXPECT_EQ(summed.raySettings.unfilteredLightSamples(), 1);
  // So a frame's rays are reused across a switch of the filter only where the samples past it stay.
  FrameSettings off = s;
  off.denoise = false;
  EXPECT_FALSE(sameRayInputs(filtered, planFrame(everything(), off)));
  EXPECT_FALSE(sameRayInputs(filtered, summed));
  off.lightSamples = 4;
  FrameSettings four = s;
  four.lightSamples = 4;
  EXPECT_TRUE(sameRayInputs(planFrame(everything(), four), planFrame(everything(), off)));
  FrameSettings more = s;
  more.lightSamplesPastFilter = 8;
  EXPECT_FALSE(sameRayInputs(filtered, planFrame(everything(), more)));
}

}  // namespace
}  // namespace tandem
