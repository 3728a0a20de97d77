#pragma once
// What one frame runs and how, decided before anything runs: a pure function of what the scene can show
// and the requested settings (no GL, no Embree), so every decision is a one-line unit test
// (tests/unit/FramePlanTest.cpp). The Renderer executes a plan; it decides nothing itself, except to drop
// the rays when Embree refused the scene (FramePlan::withoutRays).
#include <cstdint>

#include "core/FrameRules.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem {

/// What a scene can show, and the GL it is drawn with, for planning its frames.
struct SceneFacts {
  bool shadowLight = false;          // a direct light casts shadows
  bool reflectiveWeighted = false;   // a material's wR can be > 0 under the Fresnel-weighted sum
  bool reflectiveClassic = false;    // ... under the classic sum (kr only)
  bool transmissive = false;         // a material's wT can be > 0, or BLEND coverage lets light through
  bool exactSolids = false;          // an instance is an exact solid (Mesh::exact): its proxy's pixels need rays
  bool areaLight = false;            // an area light: its light is sampled (FrameSettings::lightSamples)
  bool glossy = false;               // a glossy material reflects or transmits: its lobe is sampled (glossSamples)
  /// The frame's camera is a thin lens or orthographic, or its shutter is open: the spatiotemporal filter's
  /// motion vectors do not model it (docs/motion.md), so the frame-time budget does not offer the filter.
  /// From the frame's camera (sceneFacts(scene) alone leaves it false).
  bool lensOrShutter = false;
  bool softwareGl = false;           // the GL rasterizes on the CPU (llvmpipe): its passes share the ray pass's cores
  bool reflective(bool fresnelWeighted) const { return fresnelWeighted ? reflectiveWeighted : reflectiveClassic; }
  bool operator==(const SceneFacts&) const = default;
};
SceneFacts sceneFacts(const Scene& scene);
/// The scene's facts with the frame's camera's (lensOrShutter).
SceneFacts sceneFacts(const Scene& scene, const Camera& camera);

struct FramePlan {
  FrameSettings settings;      // resolved
  /// The whole frame by rays: the reference preset's final view. Otherwise the hybrid frame.
  bool reference = false;
  /// The hybrid ray pass runs, with raySettings (effects the scene cannot show are off there).
  bool rayPass = false;
  FrameSettings raySettings;
  /// What the ray pass traces (TraceModes is made from these same rules).
  RayEffects rays;
  /// Exact solids (docs/csg.md): the pixels the raster drew with a solid's proxy are resolved by camera rays
  /// (RayTracer::resolveExact) before the ray pass, in every hybrid frame, raster-only ones too.
  bool resolve = false;
  /// Hybrid shadows proved in the GL (ShadowProofPass): the primary hits' shadow rays are decided per pixel
  /// before the ray pass, which traces only the open ones (the Renderer drops it for a frame whose maps the
  /// ray pass would not use: motion blur).
  bool glShadowProofs = false;
  bool rasterShadows = false;    // shadow maps for the primary points
  bool probeReflections = false; // cube-map probes stand in for reflection rays
  bool probeRefraction = false;  // ... and for refraction rays
  /// The spatiotemporal filter runs on this frame (FrameSettings::denoise in the final hybrid view; a frame of
  /// an accumulation going on at rest has it off: its samples are summed as drawn, Accumulation::samplePlan).
  /// raySettings.denoise says the same: the light past the filter draws unfilteredLightSamples() there.
  bool denoise = false;
  bool needsRayScene() const { return rayPass || reference || resolve; }
  /// Whether the visibility ids are read back: the ray pass and the resolve step start from them.
  bool readsIds() const { return rayPass || resolve; }
  /// The frame when Embree cannot take the scene: no ray pass, no reference, no resolve (the GL shades it,
  /// exact solids as their proxies).
  void withoutRays();
  /// The frame drawn unfiltered: every point draws lightSamples.
  void withoutFilter() { denoise = raySettings.denoise = false; }
};

FramePlan planFrame(const SceneFacts& facts, const FrameSettings& requested);

/// Whether a frame whose plan has glShadowProofs draws them, from whether the maps were built anew for this
/// frame and for the one before: under Auto, maps that change every frame (something moves) would be copied
/// to the GL every frame, which costs more than the proofs save; the ray pass proves those frames itself.
bool glProofsThisFrame(const FramePlan& plan, bool mapsChanged, bool mapsChangedBefore);

/// The history glProofsThisFrame reads, frame by frame: the maps' generation the last frame saw and whether
/// it was new. A frame that reuses the last one's rays whole changed nothing, so its maps did not change
/// either (still()): without it a reused frame between two changes would count as a change, and the frame
/// after it would take the other route than a renderer that traced the still frame (same image, other counts).
struct ProofRoute {
  std::uint64_t lastGeneration = 0;
  bool changedBefore = false;
  /// Whether the GL proves this frame, whose maps are of `generation`; remembers them.
  bool inGl(const FramePlan& plan, std::uint64_t generation) {
    const bool changed = generation != lastGeneration;
    const bool gl = glProofsThisFrame(plan, changed, changedBefore);
    lastGeneration = generation;
    changedBefore = changed;
    return gl;
  }
  void still() { changedBefore = false; }
};

/// Whether two plans' rays are the same work: the same kind of ray pass with the same ray settings, up to
/// the settings the ray pass does not read (tone map, exposure, debug view, probes per frame, reuse, target).
/// Every other field counts, so a setting added later is compared until someone decides otherwise.
bool sameRayInputs(const FramePlan& a, const FramePlan& b);

}  // namespace tandem
