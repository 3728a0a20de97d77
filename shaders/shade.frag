#version 450 core
// Shade + composite: per pixel, the visible triangle from the visibility buffer, the exact hit rebuilt
// from the camera ray (as the CPU ray pass does), local shading per docs/shading.md, the ray pass's
// light visibility, reflected and transmitted radiance added. Writes linear radiance (or a debug
// view's display values); tonemap.frag encodes it. Channels: docs/gbuffer.md.
#define TD_OUT(T) out T
#include "bindings.glsl"
#include "shading.glsl"
#include "scene.glsl"
#ifndef TD_USE_PROCEDURAL
#define TD_USE_PROCEDURAL 1  // some material has a procedural texture (docs/procedural.md)
#endif
#ifndef TD_USE_ENVIRONMENT
#define TD_USE_ENVIRONMENT 1  // the environment varies with direction: the background pixels look it up
#endif
#ifndef TD_USE_ENV_AMBIENT
#define TD_USE_ENV_AMBIENT 1  // the environment lights the ambient term (docs/environment.md)
#endif
#ifndef TD_DISTANCE_ALPHA
#define TD_DISTANCE_ALPHA 0  // alpha holds the hit's distance from the camera (gl/BehindView.h's layers)
#endif
#include "procedural.glsl"

// Per-pixel gathers go through buffer-texture views of scene.glsl's SSBOs (engine/src/gl/GpuScene.h):
// llvmpipe turns an SSBO read into a bounds-checked loop over the 8 lanes, a texelFetch into one
// vectorized gather. Lights and materials come from uniform blocks: the light loop reads the same
// record in every lane (one scalar load), and materials gather without the per-lane loop.
layout(binding = TD_UNIT_POSITIONS_TEX) uniform samplerBuffer positionsBuf;       // RGB32F: object-space position per vertex
layout(binding = TD_UNIT_NORMALS_TEX) uniform samplerBuffer normalsBuf;         // RGB32F
layout(binding = TD_UNIT_UVS_TEX) uniform samplerBuffer uvsBuf;             // RG32F
layout(binding = TD_UNIT_COLORS_TEX) uniform samplerBuffer colorsBuf;         // RGBA32F
layout(binding = TD_UNIT_INDICES_TEX) uniform usamplerBuffer indicesBuf;       // R32UI, absolute vertex numbers
layout(binding = TD_UNIT_MESHES_TEX) uniform usamplerBuffer meshesBuf;        // RGBA32UI: GpuMesh
layout(binding = TD_UNIT_INSTANCES_TEX) uniform samplerBuffer instancesBuf;      // RGBA32F: GpuInstance = 9 texels
layout(binding = TD_UNIT_INSTANCE_IDS_TEX) uniform usamplerBuffer instanceIdsBuf;   // RGBA32UI view of the same: texel 9i + 8
layout(binding = TD_UNIT_UV_TRANSFORMS_TEX) uniform samplerBuffer uvTransformsBuf;   // RGBA32F: Material::uvTransform, 4 texels

#ifndef TD_LIGHT_COUNT
#define TD_LIGHT_COUNT TD_MAX_LIGHTS  // direct lights: a compile-time bound, so the loop unrolls
#endif
#ifndef TD_UNIFORM_MATERIALS
#define TD_UNIFORM_MATERIALS 0        // material count when they are in a uniform block, 0: SSBO
#endif
layout(std140, binding = TD_BLOCK_LIGHTS) uniform LightBlock { GpuLight lights[TD_MAX_LIGHTS]; };
// Each direct light's type and shadow-map kind, 4 bits per light (SceneFeatures::lightKinds, filled by
// GpuScene::updateLights): bits 0-1 TD_LIGHT_*, bits 2-3 TD_SHADOW_* (0 in a frame without shadow maps).
// llvmpipe runs both sides of a branch on a uniform, so without these every light would evaluate the spot
// cone and both the cube and the 2D map lookups. 0: read them from the records.
#ifndef TD_LIGHT_KINDS
#define TD_LIGHT_KINDS 0u
#endif
int lightType(int j) {
  // 0 in the kinds: an area light (or no kinds at all), whose type is in its record.
  int t = int((TD_LIGHT_KINDS >> uint(4 * j)) & 3u);
  return t != 0 ? t : int(lights[j].posType.w + 0.5);
}
// Whether light j is an area light: with the kinds, a constant once the light loop is unrolled (type bits 0).
// It must be: llvmpipe runs both sides of every branch, so an area light's sampling and soft shadows, and a
// point light's shading, would each be paid for by every light.
bool lightIsArea(int j) {
  return TD_LIGHT_KINDS != 0u ? ((TD_LIGHT_KINDS >> uint(4 * j)) & 3u) == 0u
                              : tdIsAreaLight(int(lights[j].posType.w + 0.5));
}
#if TD_UNIFORM_MATERIALS > 0
layout(std140, binding = TD_BLOCK_MATERIALS) uniform MaterialBlock { GpuMaterial materials[TD_UNIFORM_MATERIALS]; };
#else
layout(std430, binding = TD_BIND_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
#endif

#ifndef TD_SHADOW_MAPS
#define TD_SHADOW_MAPS 1       // shadows = Raster: per-light visibility from the shadow maps
#endif
#ifndef TD_SOFT_SHADOWS
#define TD_SOFT_SHADOWS 1      // area lights' raster shadows soft (ShadeInputs::softShadows)
#endif
// Raster shadows on a ray grid (rayScale > 1; ShadePass::shade): the shadow-mask pass (TD_SHADOW_MASK_PASS)
// looks the maps up once per grid pixel, at the full-resolution pixel it stands for, and the frame's pass
// (TD_SHADOW_MASK, without maps of its own) gathers that visibility edge-aware like the rays' light mask.
// A quarter of the lookups at rayScale 2: soft shadows are most of a raster frame's shading on llvmpipe.
#ifndef TD_SHADOW_MASK_PASS
#define TD_SHADOW_MASK_PASS 0
#endif
#ifndef TD_SHADOW_MASK
#define TD_SHADOW_MASK 0
#endif
layout(binding = TD_UNIT_SHADOW_MASK) uniform TD_SAMPLER_SHADOW_MASK shadowMaskTex;  // layer 0: lights 0-3, 1: 4-7
#ifndef TD_PROBES
#define TD_PROBES 3            // reflections (1) / refraction (2) = Raster: reflection-probe lookups
#endif
#ifndef TD_FRESNEL_SCHLICK
#define TD_FRESNEL_SCHLICK 0   // FresnelMode::Schlick instead of the exact dielectric formula
#endif
#ifndef TD_FRESNEL_WEIGHTED
#define TD_FRESNEL_WEIGHTED 1  // wR = kr + kt·F, wT = kt·(1 − F); else wR = kr, wT = kt
#endif

// engine/src/gl/RasterEffects.h: GpuShadow, one per direct light, and the maps (reversed-Z depth,
// hardware compare GL_GEQUAL: 1 where the receiver is at least as near the light as the stored occluder).
#define TD_SHADOW_NONE 0
#define TD_SHADOW_ORTHO 1
#define TD_SHADOW_PERSPECTIVE 2
#define TD_SHADOW_CUBE 3
struct GpuShadow {
  mat4 clipFromWorldRelative;  // 2D maps: light clip space of (posW − origin)
  vec4 originKind;             // xyz origin, w kind (TD_SHADOW_*)
  vec4 params;                 // x layer / cube index, y near, z far, w texel size (world, or per unit distance)
};
layout(std140, binding = TD_BLOCK_SHADOWS) uniform ShadowBlock { GpuShadow shadows[TD_MAX_LIGHTS]; };
layout(binding = TD_UNIT_SHADOW_MAPS) uniform TD_SAMPLER_SHADOW_MAPS shadowMaps;
layout(binding = TD_UNIT_SHADOW_CUBES) uniform TD_SAMPLER_SHADOW_CUBES shadowCubes;
// The cube maps' stored depths (no compare): where the blockers are (soft shadows).
layout(binding = TD_UNIT_SHADOW_CUBES_DEPTH) uniform TD_SAMPLER_SHADOW_CUBES_DEPTH shadowCubesDepth;
layout(binding = TD_UNIT_PROBES) uniform TD_SAMPLER_PROBES probes;  // RGBA16F linear radiance, layer = probe slot
#if (TD_PROBES & TD_PROBE_BEHIND) != 0
// The scene drawn without its see-through (IOR-1 transmissive) surfaces, from this view (gl/BehindView.h).
layout(binding = TD_UNIT_BEHIND) uniform sampler2D behindView;
#endif

vec3 positionO(uint v) { return texelFetch(positionsBuf, int(v)).xyz; }
vec3 objectNormal(uint v) { return texelFetch(normalsBuf, int(v)).xyz; }

layout(binding = TD_UNIT_IDS) uniform TD_SAMPLER_IDS idsTex;        // GL rows: bottom first
layout(binding = TD_UNIT_DEPTH) uniform TD_SAMPLER_DEPTH depthTex;
layout(binding = TD_UNIT_KD) uniform sampler2DArray kdTextures;
layout(binding = TD_UNIT_RAMPS) uniform sampler2D toonRamps;      // row = material, nearest
layout(binding = TD_UNIT_LIGHT_MASK) uniform TD_SAMPLER_LIGHT_MASK lightMaskTex;  // ray grid, row 0 = top
layout(binding = TD_UNIT_REFLECTED) uniform TD_SAMPLER_REFLECTED reflectedTex;   // ray grid, row 0 = top
layout(binding = TD_UNIT_TRANSMITTED) uniform TD_SAMPLER_TRANSMITTED transmittedTex; // ray grid, row 0 = top
#ifndef TD_USE_AREA_LIGHTS
#define TD_USE_AREA_LIGHTS 1 // some direct light is an area light
#endif
// Area lights' sample bits (layer = GpuLight.shapeU.w): bit k set where sample k's shadow ray got through.
layout(binding = TD_UNIT_AREA_SAMPLES) uniform TD_SAMPLER_AREA_SAMPLES areaSamplesTex;  // ray grid, row 0 = top

layout(location = TD_LOC_CAMERA_POS) uniform vec3 cameraPosW;
layout(location = TD_LOC_CAMERA_FORWARD) uniform vec3 cameraForward;
layout(location = TD_LOC_CAMERA_RIGHT) uniform vec3 cameraRight;  // scaled: tan(fov/2)·aspect (perspective) or half width (ortho)
layout(location = TD_LOC_CAMERA_UP) uniform vec3 cameraUp;     // scaled: tan(fov/2) or half height
layout(location = TD_LOC_ORTHOGRAPHIC) uniform int orthographic;
layout(location = TD_LOC_FRAME_SIZE) uniform ivec2 frameSize;
layout(location = TD_LOC_BACKGROUND) uniform vec3 background;
layout(location = TD_LOC_AMBIENT) uniform vec3 ambientIa;
#include "environment.glsl"
#include "camera_ray.glsl"
layout(location = TD_LOC_LIGHT_SAMPLES) uniform int lightSamples;  // area-light samples per pixel (rt::FrameShading::lightSamples)
layout(location = TD_LOC_SAMPLE_BASE) uniform uint sampleBase;   // the sequence index of the first (FrameShading::sampleBase)
layout(location = TD_LOC_RAY_SCALE) uniform int rayScale;
layout(location = TD_LOC_RENDER_ANCHOR) uniform vec3 renderAnchor;  // render space's origin in world space (world-space patterns)
// The motion view (shade_debug.glsl's motionView): both frames' projections times their view rotations, the
// last frame's camera, and whether the last frame is known (else every pixel counts as newly seen).
layout(location = TD_LOC_CLIP_FROM_VIEW_ROTATION) uniform mat4 clipFromViewRotation;
layout(location = TD_LOC_PREVIOUS_CLIP_FROM_VIEW_ROTATION) uniform mat4 previousClipFromViewRotation;
layout(location = TD_LOC_PREVIOUS_CAMERA_POS) uniform vec3 previousCameraPos;
layout(location = TD_LOC_MOTION_HISTORY) uniform int motionHistory;
layout(binding = TD_UNIT_MOTION_INSTANCES) uniform samplerBuffer motionInstancesBuf;  // 4 texels an instance: columns
layout(binding = TD_UNIT_PREVIOUS_IDS) uniform usampler2D previousIdsTex;
layout(binding = TD_UNIT_PREVIOUS_DEPTH) uniform sampler2D previousDepthTex;
// The filter's guides: the last frame's view axis (the point's depth then).
layout(location = TD_LOC_PREVIOUS_CAMERA_FORWARD) uniform vec3 previousCameraForward;
// And where in its pixel this frame's sample lies (the camera's jitter, x right, y up: GL rows).
layout(location = TD_LOC_SAMPLE_OFFSET) uniform vec2 sampleOffset;

// Variant flags, set by CompositePass for each frame's scene and settings. llvmpipe runs both sides of a
// branch that diverges inside an 8-pixel SIMD group, so features a frame does not use are compiled out
// rather than skipped at run time (a 3-5x difference on the shade pass).
#ifndef TD_DEBUG_VIEW
#define TD_DEBUG_VIEW 0      // DebugView
#endif
#ifndef TD_RAY_INPUTS
#define TD_RAY_INPUTS 0      // TD_RAY_* bits: which ray results were uploaded
#endif
#ifndef TD_RAY_SCALED
#define TD_RAY_SCALED 0      // rayScale > 1: edge-aware upsampling instead of a direct fetch
#endif
#ifndef TD_USE_GOURAUD
#define TD_USE_GOURAUD 1     // some material shades with Gouraud
#endif
#ifndef TD_USE_TOON
#define TD_USE_TOON 1        // some material shades with toon (ramps + outlines)
#endif
#ifndef TD_USE_UVS
#define TD_USE_UVS 1         // some mesh has uvs
#endif
#ifndef TD_USE_KD_TEXTURES
#define TD_USE_KD_TEXTURES 1 // some material has a kd texture
#endif
#ifndef TD_USE_COLORS
#define TD_USE_COLORS 1      // some mesh has vertex colours
#endif
#ifndef TD_USE_NORMAL_MAPS
#define TD_USE_NORMAL_MAPS 1 // some normal-mapped material is drawn on a mesh with tangents
#endif
#ifndef TD_USE_EMISSIVE
#define TD_USE_EMISSIVE 1    // some material has an emissive texture (in the kd array)
#endif
#ifndef TD_USE_RADIOSITY
#define TD_USE_RADIOSITY 1   // the radiosity solution replaces the ambient term (docs/radiosity.md)
#endif
layout(binding = TD_UNIT_RADIOSITY_TABLE_TEX) uniform usamplerBuffer radiosityTable;  // core/Radiosity.h's table
layout(binding = TD_UNIT_RADIOSITY_TEX) uniform samplerBuffer radiosityValues;        // RGB32F, 2 per grid vertex
layout(location = TD_LOC_RADIOSITY_AMBIENT) uniform vec3 radiosityAmbient;  // RadiosityField::ambient
layout(location = TD_LOC_RADIOSITY_INSTANCES) uniform int radiosityInstances;  // RadiosityField::instanceCount
#ifndef TD_USE_EXACT
#define TD_USE_EXACT 1       // some instance is an exact solid: ids may name a hit on it (docs/csg.md)
#endif
// Where ids.y = TD_EXACT_TRIANGLE: the solid's outward unit normal (xyz) and t along this pixel's camera ray
// (w), as the ray pass's resolve step found them (VisibilityPass::patch).
layout(binding = TD_UNIT_EXACT_HITS) uniform TD_SAMPLER_EXACT_HITS exactHitsTex;
#ifndef TD_USE_ALPHA_BLEND
#define TD_USE_ALPHA_BLEND 1 // some material is BLEND: coverage scales the surface, the rest passes through
#endif
layout(binding = TD_UNIT_TANGENTS_TEX) uniform samplerBuffer tangentsBuf;   // RGBA32F: object-space tangent, w handedness
layout(binding = TD_UNIT_NORMAL_MAPS) uniform sampler2DArray normalMaps;   // linear RGBA8, layer = Scene::textures index
#define debugView TD_DEBUG_VIEW
layout(location = TD_LOC_RAY_GRID_SIZE) uniform ivec2 rayGridSize;
// The ray results uploaded this frame (TD_RAY_* bits): the variant is compiled for the channels the
// frame's plan can produce (TD_RAY_INPUTS), and a frame whose rays left one empty says so here instead
// of switching to another variant.
layout(location = TD_LOC_RAY_PRESENT) uniform int rayPresent;
#define rayInputs (TD_RAY_INPUTS & rayPresent)


// DebugView values (Settings.h).
#define TD_VIEW_FINAL 0
#define TD_VIEW_DEPTH 1
#define TD_VIEW_INSTANCE 2
#define TD_VIEW_PRIMITIVE 3
#define TD_VIEW_NORMAL 4
#define TD_VIEW_LIGHT_MASK 5
#define TD_VIEW_REFLECTION 6
#define TD_VIEW_TRANSMISSION 7
#define TD_VIEW_MOTION 8

#ifndef TD_DENOISE_GUIDES
#define TD_DENOISE_GUIDES 1  // the frame's pass writes the spatiotemporal filter's guides too (denoise.frag)
#endif
#include "denoise.glsl"

#ifndef TD_FUSED_OUTPUT
#define TD_FUSED_OUTPUT 0    // the frame's pass writes the display too (ShadeInputs::fusedOutput)
#endif

// The variant's flags as typed constants. A feature the frame does not use is skipped by a plain if on
// one of these: every compiler folds the branch away, and with it the reads of the resources only that
// code uses, which are therefore declared regardless (an unread sampler or block is not active, so it
// needs nothing bound). #if stays only where the declaration itself differs between variants.
const bool kUseProcedural = TD_USE_PROCEDURAL != 0;
const bool kUseEnvironment = TD_USE_ENVIRONMENT != 0;
const bool kUseEnvAmbient = TD_USE_ENV_AMBIENT != 0;
const bool kDistanceAlpha = TD_DISTANCE_ALPHA != 0;
const bool kShadowMaps = TD_SHADOW_MAPS != 0;
const bool kSoftShadows = TD_SOFT_SHADOWS != 0;
const bool kShadowMaskPass = TD_SHADOW_MASK_PASS != 0;
const bool kShadowMask = TD_SHADOW_MASK != 0;
const bool kUseProbes = TD_PROBES != 0;
const bool kProbeReflect = (TD_PROBES & TD_PROBE_REFLECT) != 0;
const bool kProbeRefract = (TD_PROBES & TD_PROBE_REFRACT) != 0;
const bool kFresnelSchlick = TD_FRESNEL_SCHLICK != 0;
const bool kFresnelWeighted = TD_FRESNEL_WEIGHTED != 0;
const bool kUseAreaLights = TD_USE_AREA_LIGHTS != 0;
const bool kRaysScaled = TD_RAY_SCALED != 0;
const bool kUseGouraud = TD_USE_GOURAUD != 0;
const bool kUseToon = TD_USE_TOON != 0;
const bool kUseUvs = TD_USE_UVS != 0;
const bool kUseKdTextures = TD_USE_KD_TEXTURES != 0;
const bool kUseColors = TD_USE_COLORS != 0;
const bool kUseNormalMaps = TD_USE_NORMAL_MAPS != 0;
const bool kUseEmissive = TD_USE_EMISSIVE != 0;
const bool kUseRadiosity = TD_USE_RADIOSITY != 0;
const bool kUseExact = TD_USE_EXACT != 0;
const bool kUseAlphaBlend = TD_USE_ALPHA_BLEND != 0;
const bool kFusedOutput = TD_FUSED_OUTPUT != 0;
const bool kDenoiseGuides = TD_DENOISE_GUIDES != 0;

layout(location = 0) out TD_OUTPUT_LINEAR outColor;

#include "shade_hit.glsl"
#include "shade_surface.glsl"
#include "shade_rays.glsl"
#include "shade_shadows.glsl"
#include "shade_probes.glsl"
#include "shade_local.glsl"
#include "shade_debug.glsl"

// The filter's guides (bindings.glsl's TD_CHANNEL_DENOISE_*): what the pixel shows, where it was, what its
// sampled light is divided by. Zero on the background (instance 0: never filtered), but the motion's w: -1.
#if TD_DENOISE_GUIDES
layout(location = 2) out TD_OUTPUT_DENOISE_GUIDE outGuide;
layout(location = 3) out TD_OUTPUT_DENOISE_MOTION outMotion;
layout(location = 4) out TD_OUTPUT_DENOISE_EXACT outExact;
// What the filter smooths goes out divided by the modulation the filter multiplies it back by: the area lights'
// light (their samples) over their light unshadowed (the visible fraction), or on a glossy material with its
// lobe samples, over the surface colour (texture detail never enters the filter). The rest is exact for the
// pixel's hit and goes past the filter (outExact), added back after it: emission, the ambient term, the other
// lights (a light that moves every frame changes no history), a sharp mirror's or glass's rays.
void writeGuides(uvec2 id, Surface s, vec3 local, vec3 area, vec3 specular, bool outline) {
  bool glossy = !areaLightsAsVisibility;
  vec3 sampled = glossy ? area + specular : area;
  // What the filtered value is multiplied back by: the area lights' light unshadowed (the filter smooths the
  // fraction of it that is visible: shade_local's areaLightAsVisibility), or on a glossy surface its colour.
  // (Under half precision's largest value: the noisy target and the guide hold halves.)
  vec3 modulation = glossy ? tdDemodulation(tdSurfaceColor(s.m, s.uv, s.pattern, s.tint))
                           : clamp(s.coverage * areaLightUnshadowed, vec3(1e-4), vec3(65000.0));
  outColor.rgb = min(sampled / modulation, vec3(65000.0));
  outExact = vec4(local - area + (glossy ? vec3(0.0) : specular), 1.0);
  // View depth (along the camera's axis: cross(up, right), unjittered, where the jitter tilts cameraForward):
  // the filter rebuilds points from it without a square root.
  float depth = dot(s.hit.posW - cameraPosW, normalize(cross(cameraUp, cameraRight)));
  // A toon outline (black, whatever the filter makes of its light) faces no way: the filter's normal weight
  // keeps its zero out of its neighbours'.
  // The glossy lobe: what its light may come from (the temporal stage's test of what moved), of what the frame
  // reflects and transmits (by rays, or the probes).
  bool reflects = (rayInputs & TD_RAY_REFLECTED) != 0 || kProbeReflect;
  bool transmits = (rayInputs & TD_RAY_TRANSMITTED) != 0 || kProbeRefract;
  float lobe = glossy ? tdLobeOf(surfaceRoughness, reflects ? s.m.krKtIorModel.x : 0.0,
                                 transmits ? s.m.krKtIorModel.y : 0.0, transmits ? s.coverage : 1.0)
                      : 0.0;
  outGuide = uvec4(floatBitsToUint(depth), tdPackNormalInstance(outline ? vec3(0.0) : s.N, id.x),
                   packHalf2x16(modulation.rg), packHalf2x16(vec2(modulation.b, lobe)));
  outMotion = denoiseMotion(id, s.hit.posW);
}
// The background's: no guide, and its radiance past the filter (the compose stage takes it as it is).
void writeNoGuides(vec3 sky) {
  outGuide = uvec4(0u);
  outMotion = vec4(0.0, 0.0, 0.0, -1.0);  // (w -1: the background, as the clear)
  outExact = vec4(sky, 0.0);
}
#else
void writeGuides(uvec2 id, Surface s, vec3 local, vec3 area, vec3 specular, bool outline) {}
void writeNoGuides(vec3 sky) {}
#endif

// One pixel of the frame: its surface, the rays gathered there (and the probes' raster effects), its local
// light, the Whitted sum; or a debug view.
void shadePixel() {
  ivec2 pix = ivec2(gl_FragCoord.xy);
  ivec2 pTop = ivec2(pix.x, frameSize.y - 1 - pix.y);
  uvec2 id = texelFetch(idsTex, pix, 0).xy;
  vec3 shown;
  if (id.x == 0u) {
    // Nothing there: the environment along the pixel's camera ray.
    vec3 sky = vec3(0.0);
    if (debugView == TD_VIEW_FINAL) {
      vec3 origin, dir;
      cameraRay(vec2(pix) + 0.5, origin, dir);
      sky = kUseEnvironment ? environmentRadiance(dir) : background;
    }
    outColor = vec4(sky, kDistanceAlpha ? TD_DISTANCE_FAR : 1.0);
    if (kDenoiseGuides) writeNoGuides(sky);
    return;
  }
  if (idView(pix, id, shown)) {
    outColor = vec4(shown, 1.0);
    return;
  }
  if (debugView == TD_VIEW_MOTION) {  // the hit's point alone: no attributes, no material
    outColor = vec4(motionView(id, primaryHit(pix, id).posW), 1.0);
    return;
  }
  Surface s = loadSurface(pix, id);
  if (debugView == TD_VIEW_NORMAL) {
    outColor = vec4(0.5 + 0.5 * s.N, 1.0);
    return;
  }
  orientTwoSided(s);
  RaySample rays = gatherRays(pTop, id.x);
  if (kUseProbes) probeLight(s, rays);
  if (rayView(s, pTop, rays, shown)) {
    outColor = vec4(shown, 1.0);
    return;
  }
  vec3 local = s.coverage * localLight(s, rays, id, pTop);
  vec3 area = s.coverage * areaLightShare;
  vec3 specular = vec3(0.0);
  if ((rayInputs & TD_RAY_REFLECTED) != 0 || kProbeReflect) specular += rays.reflected;
  if ((rayInputs & TD_RAY_TRANSMITTED) != 0 || kProbeRefract) specular += rays.transmitted;
  bool toon = kUseToon && int(s.m.krKtIorModel.w + 0.5) == TD_MODEL_TOON && s.m.emissionFlags.w < 0.5;
  bool outline = toon && isEdge(pix, id, s.hit.ngRaw);
  if (outline) {
    local = area = specular = vec3(0.0);
    areaLightUnshadowed = vec3(0.0);  // (the filter's modulation: an outline stays black)
  }
  outColor = vec4(local + specular, kDistanceAlpha ? distance(s.hit.posW, cameraPosW) : 1.0);
  if (kDenoiseGuides) writeGuides(id, s, local, area, specular, outline);
}

// The frame's shade pass also writes the display value (TD_FUSED_OUTPUT): one full-screen pass instead of
// a second one that reads the RGBA32F target back (on llvmpipe ~6 ms at 1280x720). On a software GL sky pixels
// never run this shader; their display value is the clear of attachment 1, or sky.frag's where the environment
// varies with direction.
layout(location = TD_LOC_FUSED_EXPOSURE) uniform float exposure;
layout(location = TD_LOC_FUSED_TONE_MAP) uniform int toneMap;
layout(location = TD_LOC_FUSED_PASS_THROUGH) uniform int passThrough;
// The second colour target: the display (the fused frame pass) or lights 4-7 (the shadow-mask pass); the
// two channels' output types may differ, so which one is declared is the one resource the roles choose.
#if TD_SHADOW_MASK_PASS
layout(location = 1) out TD_OUTPUT_SHADOW_MASK outMaskHi;
#define TD_SECOND_TARGET outMaskHi
#else
layout(location = 1) out TD_OUTPUT_DISPLAY outDisplay;
#define TD_SECOND_TARGET outDisplay
#endif

// The shadow-mask pass: this target is the ray grid (rows top first, as RayOutputs holds them; gl_FragCoord's
// rows are the texture's), lights 0-3 in outColor, 4-7 in the second target. Each grid pixel takes the
// visibility the full-resolution pass would look up at the pixel it stands for; no surface there (the sky):
// visible.
void shadowMaskPixel() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  ivec2 pTop = gridPixelCentre(g);
  ivec2 pix = ivec2(pTop.x, frameSize.y - 1 - pTop.y);
  uvec2 id = texelFetch(idsTex, pix, 0).xy;
  float vis[8] = float[8](1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0);
  if (id.x != 0u) {
    PrimaryHit hit = primaryHit(pix, id);
    vec3 Ng = dot(hit.ngRaw, hit.dir) > 0.0 ? -hit.ngRaw : hit.ngRaw;  // towards the viewer, as shadePixel's
    // One lookup per light with a constant index, as shadePixel's lights (TD_ADD_LIGHT says why).
#define TD_MASK_LIGHT(J) if (J < TD_LIGHT_COUNT && lights[J].radiance.w > 0.5) vis[J] = rasterShadow(J, hit.posW, Ng, pTop);
    TD_MASK_LIGHT(0) TD_MASK_LIGHT(1) TD_MASK_LIGHT(2) TD_MASK_LIGHT(3)
    TD_MASK_LIGHT(4) TD_MASK_LIGHT(5) TD_MASK_LIGHT(6) TD_MASK_LIGHT(7)
#undef TD_MASK_LIGHT
  }
  outColor = vec4(vis[0], vis[1], vis[2], vis[3]);
  TD_SECOND_TARGET = vec4(vis[4], vis[5], vis[6], vis[7]);
}

void main() {
  if (kShadowMaskPass) {
    shadowMaskPixel();
    return;
  }
  shadePixel();
  if (kFusedOutput) TD_SECOND_TARGET = vec4(tdDisplay(outColor.rgb, exposure, toneMap, passThrough != 0), 1.0);
}
