#pragma once
// Per-frame settings: plain data with documented defaults, units and ranges. resolve() applies the
// dependencies and clamps; the Renderer only ever sees resolved settings.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "tandem/Scene.h"

namespace tandem {

/// How an effect is produced: not at all, by rasterization tricks, or by Embree rays.
enum class EffectMode : std::uint8_t { Off = 0, Raster = 1, Ray = 2 };
enum class FresnelMode : std::uint8_t { Exact = 0, Schlick = 1 };
/// How hybrid shadows prove shadow rays (FrameSettings::shadowProofs): tile shafts first, then the maps, the
/// primary hits' in the GL where it is a GPU (Auto); the maps alone, the primary hits' in the GL (Gl) or in
/// the ray pass (Cpu); the tile shafts alone, no maps (Shafts).
enum class ShadowProofs : std::uint8_t { Auto = 0, Gl = 1, Cpu = 2, Shafts = 3 };
enum class ToneMap : std::uint8_t { None = 0, Reinhard = 1, Aces = 2 };
/// Anti-aliasing of the frame (FrameSettings::aa, docs/antialiasing.md).
enum class AntiAlias : std::uint8_t { Off = 0, Ssaa = 1, Adaptive = 2 };
/// Light bouncing between diffuse surfaces (FrameSettings::gi). None: the ambient term stands in for it.
/// Path: the reference frame traces it (docs/path-tracing.md), the ground truth for the rest.
enum class GlobalIllumination : std::uint8_t { None = 0, Path = 1 };

/// What the frame shows: the final image, or one G-buffer channel / ray result as a debug view.
enum class DebugView : std::uint8_t {
  Final = 0,
  Depth,        // reversed-Z depth, brighter = nearer
  InstanceId,   // hashed colour per instance
  PrimitiveId,  // hashed colour per triangle
  NormalW,      // world normal, 0.5 + 0.5·n
  LightMask,    // ray pass: fraction of lights visible
  Reflection,   // ray pass: weighted reflected radiance
  Transmission, // ray pass: weighted transmitted radiance
  Motion,       // each pixel's motion since the last frame (pixels) and whether it was seen there (docs/motion.md)
};

/// The largest frame side resolved() keeps. The GL's own limits may be lower: Renderer::resize says.
inline constexpr int kMaxFrameSide = 16384;

struct FrameSettings {
  int width = 1280;   // pixels, [1, kMaxFrameSide]
  int height = 720;   // pixels, [1, kMaxFrameSide]
  std::optional<ShadingModel> shadingOverride;  // replaces every material's model when set
  EffectMode shadows = EffectMode::Ray;
  EffectMode reflections = EffectMode::Ray;
  EffectMode refraction = EffectMode::Ray;
  /// Hybrid shadows (with shadows = Ray; `--shadows hybrid`): light-space maps answer the shadow rays they
  /// can prove, the rest are traced; the light mask is the all-rays one, bit for bit (docs/shadows.md).
  bool hybridShadows = false;
  /// With hybridShadows, how shadow rays are proved (`--shadow-proofs auto|gl|cpu|shafts`): Gl, the maps, the
  /// primary hits' from a copy of the maps in the GL, the ray pass reading the answers with the ids and
  /// tracing only the rays left open (docs/shadows.md, "Proofs in the GL"); Cpu, the maps in the ray pass
  /// itself; Shafts, the tile shafts alone (a tile's rays towards a light answered together where nothing can
  /// meet them; docs/shadows.md, "Tile shafts"), no maps; Auto, the tile shafts first, then the maps, in the
  /// GL where it is a GPU and on the CPU where the GL rasterizes on the CPU too (llvmpipe: there the GL's pass
  /// costs more than the ray pass's proofs). The image is the same every way.
  ShadowProofs shadowProofs = ShadowProofs::Auto;
  int maxDepth = 5;               // reflection/refraction bounces after the primary hit, [0, 64]
  float minContribution = 0.01f;  // stop a path when the product of its weights falls under this, [0, 1]
  int rayScale = 1;               // ray pass at 1/rayScale resolution: 1, 2 or 4 (edge-aware upsampling)
  FresnelMode fresnel = FresnelMode::Exact;
  bool fresnelWeighted = true;    // I = local + (kr + kt·F)·S + kt·(1−F)·T, else I = local + kr·S + kt·T
  ToneMap toneMap = ToneMap::Aces;
  float exposure = 1.0f;          // multiplies linear radiance before the tone map
  DebugView debugView = DebugView::Final;
  int referenceSpp = 1;           // reference mode: N×N jittered samples per pixel (converged images to
                                  // measure the other presets against, docs/bench.md)
  bool reference = false;         // primary visibility by Embree rays instead of rasterization
  /// Raster reflections/refraction: how many reflection probes a frame draws. 0 (the default): every probe
  /// that needs it, every frame (exact). N > 0: at most N, oldest first, so a moving scene's probes lag by up
  /// to ceil(probes / N) frames: a game's trade (each probe is six views of the scene). A new scene's probes
  /// arrive N a frame, the others showing the environment until then; after a new shading override,
  /// shadowing or render-space anchor they keep what they showed until their turn. The samples of an
  /// accumulation or anti-aliasing take every probe at once (Accumulation::samplePlan).
  int probesPerFrame = 0;
  /// Raster reflections/refraction: each probe's cube faces, texels a side (a power of two in [16, 512];
  /// resolved() rounds down to one). Six faces of this many pixels are drawn and shaded per probe re-rendered:
  /// 64 costs a quarter of 128 for a blurrier reflection (the raster preset's choice).
  int probeSize = 128;
  /// Raster reflections/refraction: the most reflection probes a scene gets (>= 1; resolved() clamps). Each
  /// object that reflects or transmits needs one, and each costs six views of the whole scene, so a scene with
  /// more such objects shares them: `probeLimit` of the objects, spread over the scene (farthest first, the
  /// largest first of all), get probes drawn from their centres, and every other one looks its reflections
  /// up in the nearest of those (its own parallax lost). The raster's probe cost then grows with the limit,
  /// not with the objects (docs/shading.md, "Reflection probes").
  int probeLimit = 32;
  /// A frame whose ray inputs equal the last frame's (the same camera, scene and ray settings: nothing moved,
  /// no light changed) reuses that frame's ray results instead of tracing them again: they would be the
  /// same to the bit. FrameStats::raysReused says when. With the camera still and instances moved or
  /// lights changed, the primary shadow answers whose rays pass clear of what moved, towards lights that
  /// did not change, are kept (FrameStats::rays.shadowKept; docs/reuse.md): again the same to the bit.
  /// Off: every frame traces (what a benchmark of per-frame cost must use with a still camera).
  bool reuseRays = true;
  /// A frame-time budget in milliseconds (0: none, the settings are drawn as they are). The Renderer then
  /// draws each frame with these settings or the cheaper choice (coarser ray grid, capped depth, raster
  /// fallbacks) expected to be least wrong among those its cost model predicts within the target; the
  /// model is measured on the first frames and refined every frame (docs/budget.md). FrameStats::budget
  /// says what it chose. Ignored by the reference frame. [0, 10000]
  float targetMs = 0.0f;

  /// Anti-aliasing (docs/antialiasing.md). Off: one sample per pixel, at its centre. Ssaa: aaSamples samples
  /// per pixel, each a whole frame (raster, rays, shading) drawn at a sub-pixel offset of the camera
  /// (Camera::jitterPx), averaged in linear radiance: a box filter over the pixel. Adaptive: min(4, aaSamples)
  /// samples for every pixel, then rounds of 4 more only for the pixels whose samples disagree (their
  /// display luminance spans more than aaThreshold), up to aaSamples; the ray pass traces only those pixels.
  /// The reference frame has its own samples (referenceSpp) and a frame-time budget has no anti-aliasing
  /// step yet: resolved() turns aa off for both, and accumulation off under a budget.
  AntiAlias aa = AntiAlias::Off;
  int aaSamples = 4;          // [1, 256]
  float aaThreshold = 0.05f;  // adaptive: display-luminance range (0..1) over which a pixel is refined
  /// Progressive accumulation: while the camera, the scene and these settings stay as they were, each frame
  /// adds new samples (new sub-pixel offsets) to the last frames' and shows their mean, up to this many
  /// frames; after that the converged frame is shown again at no cost. Any change starts again. 0 or 1: off.
  /// [0, 65536]. FrameStats::accumulated says how many samples the shown frame averages.
  int accumulate = 0;
  /// Area lights (docs/area-lights.md): samples per light per shaded point and frame, each with its own
  /// shadow ray when shadows are by rays; the frames of an accumulation draw new ones. [1, 32]
  int lightSamples = 4;
  /// With the spatiotemporal filter on (denoise): area-light samples, at least lightSamples, at every ray hit
  /// past the primary hit (a mirror's or glass's, whose light goes past the filter; a glossy lobe's or a
  /// blended surface's, whose light it smooths from less noise) and in the reflection probes (what they show
  /// goes past it). One filtered sample a pixel then leaves mirrors, glass and probes as an unfiltered frame
  /// of this many samples has them. A frame drawn unfiltered (a debug view, an accumulation's samples at rest)
  /// traces lightSamples at every hit; the probes follow the settings (unfilteredLightSamples()). [1, 32]
  int lightSamplesPastFilter = 4;
  /// Glossy materials (Material::roughness > 0; docs/glossy.md): reflection and refraction rays per primary
  /// hit and frame, sampled from the lobe (deeper bounces take one); accumulated frames draw new ones. [1, 32]
  int glossSamples = 4;
  /// Diffuse interreflection (docs/path-tracing.md): Path makes the reference frame a path tracer on the same
  /// scene and shading model (next-event estimation to every light, no ambient term, Russian roulette).
  /// Only the reference traces paths: resolved() turns it off for the other frames.
  GlobalIllumination gi = GlobalIllumination::None;
  /// Radiosity (docs/radiosity.md): diffuse interreflection from a progressive-refinement solution on the
  /// scene's surfaces, in place of the ambient term, at every point the frame shades (the raster's pixels,
  /// the rays' hits): the classic two-pass frame, direct and specular light staying exact. The solution is
  /// the scene's (view-independent): solved again when an instance moves, a light changes or the scene is
  /// replaced. Off under gi = Path (the paths carry that light).
  bool radiosity = false;
  /// Shooting stops when the unshot light is this fraction of the light that entered (emission and the
  /// lights' direct light), or after radiosityShots shots (0: no cap). [0, 1] and [0, 1e8]
  float radiosityError = 0.01f;
  int radiosityShots = 0;
  /// About how many patches (each two-sided) the scene's surfaces are cut into. [16, 1 << 20]
  int radiosityPatches = 2048;
  /// Adaptive refinement: once solved, the triangles where the solution steps steeply across them (a
  /// gradient or a shadow's edge in the indirect light) get grids twice as fine (within 2 × the patches) and
  /// the solve runs again on them: a closer solution for several times the solve (docs/radiosity.md).
  bool radiosityRefine = false;
  /// Off: render() solves before the frame, to radiosityError (a converged frame: tandem-render). On: the
  /// solve runs on a thread of its own and each frame shows the latest solution, its unshot light as an
  /// ambient estimate (a game: FrameStats::radiosity says how far it is).
  bool radiosityBackground = false;

  /// Throughput mode (docs/pipeline.md): render() rasterizes and reads back this frame, shows the frame
  /// before it (its rays finished, uploaded and composited) and leaves this frame's ray pass running on its
  /// own thread while the caller goes on; the next render() call rasterizes its frame while those rays run,
  /// then shows this one. One frame of latency: readImage(), readLinear() and present() give the frame the
  /// last call showed, FrameStats describes it, and Renderer::finish() shows the frame still in flight. Each
  /// frame is the image latency mode (off, the default) draws for the same camera, scene and settings, to the
  /// bit. The camera, instances and lights may change between calls (the rays in flight see their own copy
  /// of the scene); a new scene, other settings or proofs in the GL complete the frame in flight first
  /// (FrameStats::pipelineDrained). Drawn in latency mode, the frame in flight completed first: frames of
  /// several samples (aa, and accumulation going on at rest; its first frame is pipelined), the reference,
  /// raster-only frames, an open shutter, radiosity and a new frame size.
  bool pipelined = false;

  /// The spatiotemporal filter (docs/denoise.md): each frame of one sample draws new light and gloss samples
  /// at a new sub-pixel offset, and a GL pass reprojects the last frames' filtered result along the motion
  /// vectors (history rejected where the point was not in view, clamped to this frame's neighbourhood),
  /// estimates each pixel's variance and smooths the noisy part with an edge-aware a-trous filter guided by
  /// depth, normals and instances (SVGF). Where a pixel's samples agree (hard shadows, mirrors) its variance
  /// is zero and the filter keeps it as drawn. Frames of several samples (aa) and the reference have their own
  /// samples: resolved() turns it off for them; frames that go on accumulating at rest show the exact mean.
  bool denoise = false;

  /// Clamps ranges and applies dependencies (e.g. rayScale rounded to 1, 2 or 4).
  FrameSettings resolved() const;
  /// The area-light samples at the points past the filter (lightSamplesPastFilter): with the filter on, at
  /// least lightSamples; without it, lightSamples.
  int unfilteredLightSamples() const {
    return denoise ? std::max(lightSamples, lightSamplesPastFilter) : lightSamples;
  }
  /// Every field compared; sameRayInputs (render/FramePlan.h) compares only what the ray pass reads.
  bool operator==(const FrameSettings&) const = default;
};

/// Named presets: "raster", "hybrid-fast", "hybrid-full", "reference". Size and debug view untouched.
std::optional<FrameSettings> presetSettings(std::string_view name, FrameSettings base = {});
std::vector<std::string> presetNames();

std::optional<EffectMode> parseEffectMode(std::string_view s);  // off | raster | ray
/// The shadows' mode by name: off | raster | ray (every shadow ray traced) | hybrid (ray, with
/// hybridShadows). False, and `settings` untouched, for any other name.
bool applyShadowMode(std::string_view s, FrameSettings& settings);
/// The name applyShadowMode takes for the settings' shadows: "hybrid" for rays with hybridShadows.
std::string_view shadowModeName(const FrameSettings& s);
std::optional<ShadingModel> parseShadingModel(std::string_view s);  // flat | gouraud | phong | toon
std::optional<DebugView> parseDebugView(std::string_view s);
/// Final, Reflection and Transmission show radiance (exposed and tone mapped); the other views are
/// display values already.
bool isRadianceView(DebugView v);
std::optional<ToneMap> parseToneMap(std::string_view s);  // none | reinhard | aces
std::optional<AntiAlias> parseAntiAlias(std::string_view s);  // off | ssaa | adaptive
std::optional<GlobalIllumination> parseGlobalIllumination(std::string_view s);  // none | path
std::string_view toString(GlobalIllumination g);
std::string_view toString(AntiAlias a);
std::string_view toString(EffectMode m);
std::string_view toString(ShadowProofs p);
std::optional<ShadowProofs> parseShadowProofs(std::string_view s);  // auto | gl | cpu | shafts
std::string_view toString(ToneMap m);
std::string_view toString(ShadingModel m);
std::string_view toString(DebugView v);

}  // namespace tandem
