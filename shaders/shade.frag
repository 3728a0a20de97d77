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
#if TD_USE_PROCEDURAL
#include "procedural.glsl"
#endif

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
#if TD_SHADOW_MASK
layout(binding = TD_UNIT_SHADOW_MASK) uniform TD_SAMPLER_SHADOW_MASK shadowMaskTex;  // layer 0: lights 0-3, 1: 4-7
#endif
#ifndef TD_PROBES
#define TD_PROBES 3            // reflections (1) / refraction (2) = Raster: reflection-probe lookups
#endif
#ifndef TD_FRESNEL_SCHLICK
#define TD_FRESNEL_SCHLICK 0   // FresnelMode::Schlick instead of the exact dielectric formula
#endif
#ifndef TD_FRESNEL_WEIGHTED
#define TD_FRESNEL_WEIGHTED 1  // wR = kr + kt·F, wT = kt·(1 − F); else wR = kr, wT = kt
#endif

#if TD_SHADOW_MAPS
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
#endif
#if TD_PROBES != 0
layout(binding = TD_UNIT_PROBES) uniform TD_SAMPLER_PROBES probes;  // RGBA16F linear radiance, layer = probe slot
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
#if TD_USE_AREA_LIGHTS
// Area lights' sample bits (layer = GpuLight.shapeU.w): bit k set where sample k's shadow ray got through.
layout(binding = TD_UNIT_AREA_SAMPLES) uniform TD_SAMPLER_AREA_SAMPLES areaSamplesTex;  // ray grid, row 0 = top
#endif

layout(location = TD_LOC_CAMERA_POS) uniform vec3 cameraPosW;
layout(location = TD_LOC_CAMERA_FORWARD) uniform vec3 cameraForward;
layout(location = TD_LOC_CAMERA_RIGHT) uniform vec3 cameraRight;  // scaled: tan(fov/2)·aspect (perspective) or half width (ortho)
layout(location = TD_LOC_CAMERA_UP) uniform vec3 cameraUp;     // scaled: tan(fov/2) or half height
layout(location = TD_LOC_ORTHOGRAPHIC) uniform int orthographic;
layout(location = TD_LOC_FRAME_SIZE) uniform ivec2 frameSize;
layout(location = TD_LOC_BACKGROUND) uniform vec3 background;
layout(location = TD_LOC_AMBIENT) uniform vec3 ambientIa;
layout(location = TD_LOC_LIGHT_SAMPLES) uniform int lightSamples;  // area-light samples per pixel (rt::FrameShading::lightSamples)
layout(location = TD_LOC_SAMPLE_BASE) uniform uint sampleBase;   // the sequence index of the first (FrameShading::sampleBase)
layout(location = TD_LOC_RAY_SCALE) uniform int rayScale;
layout(location = TD_LOC_RENDER_ANCHOR) uniform vec3 renderAnchor;  // render space's origin in world space (world-space patterns)

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
#if TD_USE_RADIOSITY
layout(binding = TD_UNIT_RADIOSITY_TABLE_TEX) uniform usamplerBuffer radiosityTable;  // core/Radiosity.h's table
layout(binding = TD_UNIT_RADIOSITY_TEX) uniform samplerBuffer radiosityValues;        // RGB32F, 2 per grid vertex
layout(location = TD_LOC_RADIOSITY_AMBIENT) uniform vec3 radiosityAmbient;  // RadiosityField::ambient
layout(location = TD_LOC_RADIOSITY_INSTANCES) uniform int radiosityInstances;  // RadiosityField::instanceCount
#endif
#ifndef TD_USE_EXACT
#define TD_USE_EXACT 1       // some instance is an exact solid: ids may name a hit on it (docs/csg.md)
#endif
#if TD_USE_EXACT
// Where ids.y = TD_EXACT_TRIANGLE: the solid's outward unit normal (xyz) and t along this pixel's camera ray
// (w), as the ray pass's resolve step found them (VisibilityPass::patch).
layout(binding = TD_UNIT_EXACT_HITS) uniform TD_SAMPLER_EXACT_HITS exactHitsTex;
#endif
#ifndef TD_USE_ALPHA_BLEND
#define TD_USE_ALPHA_BLEND 1 // some material is BLEND: coverage scales the surface, the rest passes through
#endif
#if TD_USE_NORMAL_MAPS
layout(binding = TD_UNIT_TANGENTS_TEX) uniform samplerBuffer tangentsBuf;   // RGBA32F: object-space tangent, w handedness
layout(binding = TD_UNIT_NORMAL_MAPS) uniform sampler2DArray normalMaps;   // linear RGBA8, layer = Scene::textures index
#endif
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

layout(location = 0) out TD_OUTPUT_LINEAR outColor;

// ---- camera rays: the same construction as Camera::rayThroughPixel ----
void cameraRay(vec2 fragXY, out vec3 origin, out vec3 dir) {
  // gl_FragCoord has y up; the camera's pixel y runs down, and 1 - 2·(H - y)/H = 2·y/H - 1.
  float nx = fragXY.x / float(frameSize.x) * 2.0 - 1.0;
  float ny = fragXY.y / float(frameSize.y) * 2.0 - 1.0;
  if (orthographic != 0) {
    origin = cameraPosW + cameraRight * nx + cameraUp * ny;
    dir = cameraForward;
  } else {
    origin = cameraPosW;
    dir = normalize(cameraForward + cameraRight * nx + cameraUp * ny);
  }
}

#if TD_USE_RADIOSITY
// The indirect irradiance H at barycentrics b of a triangle, seen from its back or front, and whether the
// solution covers the triangle: RadiosityField::at.
bool radiosityAt(uint instance, uint triangle, vec3 b, bool backFace, out vec3 H) {
  H = vec3(0.0);
  if (int(instance) >= radiosityInstances) return false;
  uvec2 first = texelFetch(radiosityTable, int(instance)).xy;
  if (first.x == 0xffffffffu || triangle >= first.y) return false;
  uvec2 tri = texelFetch(radiosityTable, int(first.x + triangle)).xy;
  ivec3 corner;
  vec3 w;
  tdGridCorners(b, int(tri.y), corner, w);
  int base = int(tri.x) + (backFace ? 1 : 0);
  H = radiosityAmbient + w.x * texelFetch(radiosityValues, base + 2 * corner.x).rgb +
      w.y * texelFetch(radiosityValues, base + 2 * corner.y).rgb + w.z * texelFetch(radiosityValues, base + 2 * corner.z).rgb;
  return true;
}
#endif

// ---- the visible triangle ----
struct Triangle {
  uint v0, v1, v2;  // absolute vertex numbers
  vec3 p0, p1, p2;  // world space
  uint flags;
  uint material;
  uint probe;  // reflection-probe slot + 1, 0 = none
  mat3 normalFromObject;
  mat3 worldLinear;  // upper 3×3 of worldFromObject: tangents transform with it
};

mat4 instanceWorldFromObject(uint instance) {
  int base = 9 * int(instance);
  return mat4(texelFetch(instancesBuf, base), texelFetch(instancesBuf, base + 1), texelFetch(instancesBuf, base + 2),
              texelFetch(instancesBuf, base + 3));
}

// The instance's part of a Triangle (material, probe, transforms; no vertices, no attribute flags), and its
// record's transform and mesh/material texel for loadTriangle, fetched once.
Triangle loadInstance(uint instance, out mat4 worldFromObject, out uvec4 meshMaterial) {
  Triangle t;
  int base = 9 * int(instance);
  worldFromObject = instanceWorldFromObject(instance);
  meshMaterial = texelFetch(instanceIdsBuf, base + 8);
  t.v0 = t.v1 = t.v2 = 0u;
  t.flags = 0u;
  t.material = meshMaterial.y;
  t.probe = meshMaterial.z;
  t.normalFromObject = mat3(texelFetch(instancesBuf, base + 4).xyz, texelFetch(instancesBuf, base + 5).xyz,
                            texelFetch(instancesBuf, base + 6).xyz);
  t.worldLinear = mat3(worldFromObject);
  return t;
}

Triangle loadTriangle(uint instance, uint primitive) {
  mat4 worldFromObject;
  uvec4 meshMaterial;
  Triangle t = loadInstance(instance, worldFromObject, meshMaterial);
  uvec4 mesh = texelFetch(meshesBuf, int(meshMaterial.x));
  int i = int(mesh.y + 3u * primitive);
  t.v0 = texelFetch(indicesBuf, i).x;
  t.v1 = texelFetch(indicesBuf, i + 1).x;
  t.v2 = texelFetch(indicesBuf, i + 2).x;
  t.p0 = (worldFromObject * vec4(positionO(t.v0), 1.0)).xyz;
  t.p1 = (worldFromObject * vec4(positionO(t.v1), 1.0)).xyz;
  t.p2 = (worldFromObject * vec4(positionO(t.v2), 1.0)).xyz;
  t.flags = mesh.z;
  return t;
}

vec3 geometricNormal(Triangle t) {
  vec3 n = cross(t.p1 - t.p0, t.p2 - t.p0);
  float len = length(n);
  return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

// Barycentrics (b0, b1, b2) where the ray meets the triangle's plane (Möller–Trumbore without the
// inside test: the rasterizer already decided this pixel sees this triangle). Unclamped, for ray
// differentials; hitBarycentrics clamps onto the triangle as the CPU's resolveHit does, so a pixel whose
// centre grazes past an edge still shades a point of the triangle.
vec3 rayBarycentrics(vec3 origin, vec3 dir, Triangle t) {
  vec3 e1 = t.p1 - t.p0;
  vec3 e2 = t.p2 - t.p0;
  vec3 pv = cross(dir, e2);
  float det = dot(e1, pv);
  if (abs(det) <= 1e-20 * dot(e1, e1) * dot(e2, e2) || det == 0.0) return vec3(1.0 / 3.0);
  float inv = 1.0 / det;
  vec3 tv = origin - t.p0;
  float b1 = dot(tv, pv) * inv;
  float b2 = dot(dir, cross(tv, e1)) * inv;
  return vec3(1.0 - b1 - b2, b1, b2);
}

vec3 hitBarycentrics(vec3 origin, vec3 dir, Triangle t) {
  vec3 b = rayBarycentrics(origin, dir, t);
  if (min(b.x, min(b.y, b.z)) >= 0.0) return b;
  b = max(b, vec3(0.0));
  float sum = b.x + b.y + b.z;
  return sum > 0.0 ? b / sum : vec3(1.0 / 3.0);
}


// ---- the exact hit of a pixel's camera ray (rt::resolveHit's twin) ----
struct PrimaryHit {
  vec3 origin, dir;  // the pixel's camera ray
  uint instance;
  Triangle tri;
  vec3 b;            // barycentrics on tri
  vec3 posW;
  vec3 ngRaw;        // the unflipped geometric normal
  bool onSolid;      // a point on an exact solid (ids.y = TD_EXACT_TRIANGLE)
};

// The hit that pixel `pix` (GL rows) shows, with its ids `id` (id.x > 0): rebuilt from the camera ray through
// the pixel's centre, as the CPU ray pass does.
PrimaryHit primaryHit(ivec2 pix, uvec2 id) {
  PrimaryHit h;
  cameraRay(vec2(pix) + 0.5, h.origin, h.dir);
  h.instance = id.x - 1u;
  h.onSolid = false;
#if TD_USE_EXACT
  if (id.y == TD_EXACT_TRIANGLE) {
    h.onSolid = true;
    // A point on an exact solid (rt::resolveHit's twin): no vertices or attributes, the solid's own normal;
    // its "triangle" is the point itself, so Gouraud and flat shade it per pixel with that normal.
    vec4 exact = texelFetch(exactHitsTex, pix, 0);
    mat4 worldFromObject;
    uvec4 meshMaterial;
    h.tri = loadInstance(h.instance, worldFromObject, meshMaterial);
    h.posW = h.origin + exact.w * h.dir;
    h.tri.p0 = h.posW;
    h.tri.p1 = h.posW;
    h.tri.p2 = h.posW;
    h.b = vec3(1.0, 0.0, 0.0);
    h.ngRaw = exact.xyz;
    return h;
  }
#endif
  h.tri = loadTriangle(h.instance, id.y);
  h.b = hitBarycentrics(h.origin, h.dir, h.tri);
  h.posW = h.b.x * h.tri.p0 + h.b.y * h.tri.p1 + h.b.z * h.tri.p2;
  h.ngRaw = geometricNormal(h.tri);
  return h;
}

// ---- the toon ramp: the same texel as shading::toonRampIndex picks in C++ ----
int tdToonRampIndex(float nl) {
  float t = clamp(nl * 0.5 + 0.5, 0.0, 1.0);
  return min(int(t * float(TD_TOON_RAMP_SIZE)), TD_TOON_RAMP_SIZE - 1);
}

float toonLevel(GpuMaterial m, float nl) {
  return texelFetch(toonRamps, ivec2(tdToonRampIndex(nl), int(m.kaToon.w + 0.5)), 0).r;
}

// ---- ray results, upsampled edge-aware from the ray grid ----
// Grid pixel g stands for full-resolution pixel min(g·s + s/2, size − 1) (rows from the top), as
// engine/src/rt/RayTracer.h defines; only grid pixels that saw this pixel's instance are blended.
uint instanceAtTop(ivec2 pTop) { return texelFetch(idsTex, ivec2(pTop.x, frameSize.y - 1 - pTop.y), 0).x; }
ivec2 gridPixelCentre(ivec2 g) { return min(g * rayScale + rayScale / 2, frameSize - 1); }

struct RaySample {
  float vis[TD_MAX_LIGHTS];  // an area light's: the fraction of its samples that are visible
  uint area[TD_MAX_LIGHTS];  // an area light's sample bits (full-resolution rays only)
  vec3 reflected;
  vec3 transmitted;
};

void accumulate(inout RaySample acc, ivec2 g, float w) {
  if ((rayInputs & TD_RAY_LIGHT_MASK) != 0) {
    uint mask = texelFetch(lightMaskTex, g, 0).x;
    for (int j = 0; j < TD_LIGHT_COUNT; ++j) {
#if TD_USE_AREA_LIGHTS
      if (lightIsArea(j)) {
        uint bits = texelFetch(areaSamplesTex, ivec3(g, int(lights[j].shapeU.w + 0.5)), 0).x;
        acc.area[j] = bits;
        acc.vis[j] += w * float(bitCount(bits & (lightSamples >= 32 ? 0xFFFFFFFFu : (1u << uint(lightSamples)) - 1u))) /
                      float(lightSamples);
        continue;
      }
#endif
      acc.vis[j] += ((mask >> uint(j)) & 1u) != 0u ? w : 0.0;
    }
  }
#if TD_SHADOW_MASK
  vec4 lo = texelFetch(shadowMaskTex, ivec3(g, 0), 0);
  vec4 hi = TD_LIGHT_COUNT > 4 ? texelFetch(shadowMaskTex, ivec3(g, 1), 0) : vec4(1.0);
  // (j < 4 ? lo : hi)[j & 3], not j < 4 ? lo[j] : hi[j - 4]: once the loop unrolls, the untaken arm's
  // hi[-4] is a constant index out of bounds, which NVIDIA's compiler rejects (the program fails to link).
  for (int j = 0; j < TD_LIGHT_COUNT; ++j) acc.vis[j] += w * (j < 4 ? lo : hi)[j & 3];
#endif
  if ((rayInputs & TD_RAY_REFLECTED) != 0) acc.reflected += w * texelFetch(reflectedTex, g, 0).rgb;
  if ((rayInputs & TD_RAY_TRANSMITTED) != 0) acc.transmitted += w * texelFetch(transmittedTex, g, 0).rgb;
}

RaySample gatherRays(ivec2 pTop, uint instance) {
  RaySample acc;
  for (int j = 0; j < TD_MAX_LIGHTS; ++j) {
    acc.vis[j] = 0.0;
    acc.area[j] = 0xFFFFFFFFu;
  }
  acc.reflected = vec3(0.0);
  acc.transmitted = vec3(0.0);
  if (rayInputs == 0 && TD_SHADOW_MASK == 0) return acc;
#if !TD_RAY_SCALED
  // Full-resolution rays: grid pixel = this pixel, which saw this instance by definition.
  accumulate(acc, pTop, 1.0);
  return acc;
#endif
  vec2 f = (vec2(pTop) - float(rayScale / 2)) / float(rayScale);
  ivec2 g0 = ivec2(floor(f));
  vec2 w = f - vec2(g0);
  float total = 0.0;
  RaySample sum = acc;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      float wk = (dx == 1 ? w.x : 1.0 - w.x) * (dy == 1 ? w.y : 1.0 - w.y);
      ivec2 g = clamp(g0 + ivec2(dx, dy), ivec2(0), rayGridSize - 1);
      if (wk <= 0.0 || instanceAtTop(gridPixelCentre(g)) != instance) continue;
      accumulate(sum, g, wk);
      total += wk;
    }
  if (total <= 0.0) {
    // No bilinear neighbour saw this surface (a thin object or a silhouette): take the nearest grid
    // pixel within one step that did, else the nearest grid pixel at all.
    ivec2 gn = clamp(ivec2(floor(f + 0.5)), ivec2(0), rayGridSize - 1);
    ivec2 best = gn;
    float bestD = 1e30;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 g = clamp(gn + ivec2(dx, dy), ivec2(0), rayGridSize - 1);
        vec2 d = vec2(g) - f;
        if (instanceAtTop(gridPixelCentre(g)) == instance && dot(d, d) < bestD) {
          bestD = dot(d, d);
          best = g;
        }
      }
    accumulate(sum, best, 1.0);
    total = 1.0;
  }
  for (int j = 0; j < TD_LIGHT_COUNT; ++j) acc.vis[j] = sum.vis[j] / total;
  acc.reflected = sum.reflected / total;
  acc.transmitted = sum.transmitted / total;
  return acc;
}

#if TD_SHADOW_MAPS
// Light j's map kind (TD_SHADOW_*): a constant with the kinds, as lightIsArea.
int shadowKind(int j) {
  return TD_LIGHT_KINDS != 0u ? int((TD_LIGHT_KINDS >> uint(4 * j + 2)) & 3u) : int(shadows[j].originKind.w + 0.5);
}

// Visibility of direct light j at posW from its shadow map: the point is first moved 1.5 map texels along
// the (viewer-facing) geometric normal — a normal offset, which removes acne at grazing angles without a
// depth bias that would detach shadows from their casters — then 4 bilinear depth-compare taps half a
// texel apart (a 3×3-texel PCF) soften the one-texel staircase.
float shadowVisibility(int j, vec3 posW, vec3 Ng) {
  GpuShadow s = shadows[j];
  if (int(s.originKind.w + 0.5) == TD_SHADOW_NONE) return 1.0;  // this light casts no shadow
  int kind = shadowKind(j);
  vec3 rel = posW - s.originKind.xyz;
  float texel = s.params.w * (kind == TD_SHADOW_ORTHO ? 1.0 : length(rel));
  rel += Ng * (1.5 * texel);
  float layer = s.params.x;
  if (kind == TD_SHADOW_CUBE) {
    // The face's depth is that of the major axis: n(f − d) / (d(f − n)) in reversed-Z (Camera::clipFromView).
    vec3 a = abs(rel);
    float d = max(a.x, max(a.y, a.z));
    float n = s.params.y, f = s.params.z;
    float ref = max(n * (f - d) / (d * (f - n)), 0.0);
    vec3 u = normalize(cross(rel, abs(rel.y) < 0.99 * length(rel) ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 v = normalize(cross(rel, u));
    float h = 0.5 * s.params.w * d;  // half a texel at distance d on the face
    float sum = texture(shadowCubes, vec4(rel + h * (u + v), layer), ref) +
                texture(shadowCubes, vec4(rel + h * (u - v), layer), ref) +
                texture(shadowCubes, vec4(rel - h * (u + v), layer), ref) +
                texture(shadowCubes, vec4(rel - h * (u - v), layer), ref);
    return 0.25 * sum;
  }
  vec4 clip = s.clipFromWorldRelative * vec4(rel, 1.0);
  if (clip.w <= 0.0) return 1.0;  // behind a spot: outside its cone anyway
  vec3 ndc = clip.xyz / clip.w;
  // Outside the map is outside the spot's cone (zero light) or outside the scene's bounds (no caster).
  if (abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return 1.0;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  float ref = max(ndc.z, 0.0);  // beyond far: nothing stored there (cleared to 0) shadows it
  vec2 h = 0.5 / vec2(textureSize(shadowMaps, 0).xy);
  float sum = texture(shadowMaps, vec4(uv + vec2(h.x, h.y), layer, ref)) +
              texture(shadowMaps, vec4(uv + vec2(-h.x, h.y), layer, ref)) +
              texture(shadowMaps, vec4(uv + vec2(h.x, -h.y), layer, ref)) +
              texture(shadowMaps, vec4(uv + vec2(-h.x, -h.y), layer, ref));
  return 0.25 * sum;
}
#endif

#ifndef TD_SOFT_SHADOWS
#define TD_SOFT_SHADOWS 1
#endif
#if TD_SHADOW_MAPS && TD_USE_AREA_LIGHTS && TD_SOFT_SHADOWS
// The cube maps' stored depths (no compare): where the blockers are.
layout(binding = TD_UNIT_SHADOW_CUBES_DEPTH) uniform TD_SAMPLER_SHADOW_CUBES_DEPTH shadowCubesDepth;

// Reversed-Z depth of a point `rel` from a cube map's centre: that of its major axis (as shadowVisibility).
float cubeDepth(vec3 rel, float n, float f) {
  vec3 a = abs(rel);
  float d = max(a.x, max(a.y, a.z));
  return max(n * (f - d) / (d * (f - n)), 0.0);
}

// Tap i of `count` on Vogel's golden-angle spiral in the unit disk, turned by the rotation (cos, sin) `turn`.
// The unturned taps are constants once the loops unroll; one rotation a pixel instead of a sine and cosine a
// tap.
vec2 vogelTap(int i, int count, vec2 turn) {
  float r = sqrt((float(i) + 0.5) / float(count));
  float theta = float(i) * 2.39996323;
  vec2 t = r * vec2(cos(theta), sin(theta));
  return vec2(t.x * turn.x - t.y * turn.y, t.x * turn.y + t.y * turn.x);
}

// Raster soft shadows of area light j (docs/area-lights.md): percentage-closer soft shadows (Fernando 2005)
// on the cube map rendered from the light's centre. A blocker search over the light's extent, the penumbra
// width from similar triangles, w = size·(receiver − blocker)/blocker, then percentage-closer filtering
// over it. Each tap compares against the receiver's tangent plane where the tap's direction meets it (a
// receiver-plane depth bias: wide kernels on a floor would otherwise shadow the floor itself). `turn`
// rotates the taps per pixel and frame, so accumulated frames average them.
float softShadowVisibility(int j, vec3 posW, vec3 Ng, float lightSize, vec2 turn) {
  GpuShadow s = shadows[j];
  if (shadowKind(j) != TD_SHADOW_CUBE) return shadowVisibility(j, posW, Ng);
  float n = s.params.y, f = s.params.z, layer = s.params.x;
  vec3 rel = posW - s.originKind.xyz;
  float len = length(rel);
  if (!(len > 0.0)) return 1.0;  // at the light's centre: no direction to look up
  rel += Ng * (1.5 * s.params.w * len);
  vec3 u = normalize(cross(rel, abs(rel.y) < 0.99 * len ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
  vec3 v = normalize(cross(rel, u));
  float planeDist = dot(Ng, rel);
  float texel = s.params.w * len;
  // 1. Blockers: their mean distance along the major axis, among taps nearer the light than the receiver.
  float search = min(2.0 * lightSize, 0.5 * len);
  float blockerSum = 0.0;
  float blockers = 0.0;
  const int kSearch = 8;
  for (int i = 0; i < kSearch; ++i) {
    vec2 o = vogelTap(i, kSearch, turn) * search;
    vec3 dir = rel + u * o.x + v * o.y;
    float along = dot(Ng, dir);
    float ref = along * planeDist > 0.0 ? cubeDepth(dir * (planeDist / along), n, f) : cubeDepth(rel, n, f);
    float stored = texture(shadowCubesDepth, vec4(dir, layer)).r;
    if (stored > ref) {
      blockerSum += n * f / (stored * (f - n) + n);  // the stored depth's distance along its axis
      blockers += 1.0;
    }
  }
  vec3 a = abs(rel);
  float receiver = max(a.x, max(a.y, a.z));
  float blocker = blockerSum / max(blockers, 1.0);
  float width = lightSize * max(receiver - blocker, 0.0) / max(blocker, 1e-6 * receiver);
  // A light no wider than a texel of its map is a point light to it (the point limit of its radiometry), and
  // a penumbra narrower than a texel the map resolves: both take the hard lookup. Each lookup is written once,
  // with the branches around it: llvmpipe runs both sides of a branch, so every copy would cost its taps.
  if (lightSize <= texel || (blockers > 0.0 && width <= texel)) return shadowVisibility(j, posW, Ng);
  if (blockers == 0.0) return 1.0;
  // 2. Percentage-closer filtering over the penumbra.
  float lit = 0.0;
  const int kFilter = 8;
  for (int i = 0; i < kFilter; ++i) {
    vec2 o = vogelTap(i, kFilter, turn) * width;
    vec3 dir = rel + u * o.x + v * o.y;
    float along = dot(Ng, dir);
    float ref = along * planeDist > 0.0 ? cubeDepth(dir * (planeDist / along), n, f) : cubeDepth(rel, n, f);
    lit += texture(shadowCubes, vec4(dir, layer), ref);
  }
  return lit / float(kFilter);
}

// The extent soft shadows take an area light's size as: a sphere's or disk's radius, half a rect's mean side.
float areaLightSize(GpuLight L, int type) {
  return type == TD_LIGHT_SPHERE ? L.shapeV.w : 0.5 * (length(vec3(L.shapeU)) + length(vec3(L.shapeV)));
}
#endif

#if TD_SHADOW_MAPS
// Light j's visibility from its shadow map: soft for an area light, else shadowVisibility's.
float rasterShadow(int j, vec3 posW, vec3 Ng, ivec2 pTop) {
#if TD_USE_AREA_LIGHTS && TD_SOFT_SHADOWS
  if (lightIsArea(j)) {
    int type = lightType(j);
    uint h = tdHash(tdPixelSeed(pTop.x, pTop.y, 0u) ^ tdHash(sampleBase + uint(j)));
    float angle = float(h >> 8u) * (6.28318530718 / 16777216.0);
    return softShadowVisibility(j, posW, Ng, areaLightSize(lights[j], type), vec2(cos(angle), sin(angle)));
  }
#endif
  return shadowVisibility(j, posW, Ng);
}
#endif

// ---- debug colours ----
vec3 hashColor(uint x) {
  x = x * 747796405u + 2891336453u;
  x = ((x >> ((x >> 28u) + 4u)) ^ x) * 277803737u;
  x = (x >> 22u) ^ x;
  return vec3(float(x & 255u), float((x >> 8u) & 255u), float((x >> 16u) & 255u)) / 255.0 * 0.8 + 0.2;
}

// ---- toon outlines: black where instance, depth or normal are discontinuous ----
// The unflipped geometric normal of what pixel p (GL rows) shows, id its ids.
vec3 surfaceNormal(ivec2 p, uvec2 id) {
#if TD_USE_EXACT
  if (id.y == TD_EXACT_TRIANGLE) return texelFetch(exactHitsTex, p, 0).xyz;
#endif
  return geometricNormal(loadTriangle(id.x - 1u, id.y));
}

bool isEdge(ivec2 p, uvec2 id, vec3 ngUnflipped) {
  float d = texelFetch(depthTex, p, 0).r;
  const ivec2 offsets[2] = ivec2[2](ivec2(1, 0), ivec2(0, 1));
  for (int k = 0; k < 2; ++k) {
    ivec2 a = clamp(p - offsets[k], ivec2(0), frameSize - 1);
    ivec2 b = clamp(p + offsets[k], ivec2(0), frameSize - 1);
    uvec2 ia = texelFetch(idsTex, a, 0).xy;
    uvec2 ib = texelFetch(idsTex, b, 0).xy;
    if (ia.x != id.x || ib.x != id.x) return true;
    // Reversed-Z depth is affine in 1/z, so it is linear in screen space across a plane: a large second
    // difference is a fold or a step, not a slope.
    float da = texelFetch(depthTex, a, 0).r;
    float db = texelFetch(depthTex, b, 0).r;
    if (abs(da + db - 2.0 * d) > 0.02 * d) return true;
    // A triangle's neighbours on the same triangle share its plane; points on a solid are compared always.
    if ((ia.y != id.y || ia.y == TD_EXACT_TRIANGLE) && dot(surfaceNormal(a, ia), ngUnflipped) < 0.8) return true;
    if ((ib.y != id.y || ib.y == TD_EXACT_TRIANGLE) && dot(surfaceNormal(b, ib), ngUnflipped) < 0.8) return true;
  }
  return false;
}

#if TD_MAX_LIGHTS != 8
#error "shadePixel and shadowMaskPixel call each of the 8 lights by a constant index"
#endif

// What each light's term reads at the shaded point (shadePixel fills it once).
struct LightingPoint {
  vec3 C, ks;
  float ns;
  int model;
  vec3 Ns, N0, N1, N2;  // the shading normal; Gouraud's vertex normals
  vec3 posW, V, origin, Ng;
  vec3 b;               // barycentrics on tri
  ivec2 pTop;
};

// Direct light j's term at p, visibility included: the rays' or the shadow mask's (gathered in `rays`), or
// the shadow maps'.
vec3 directLight(int j, LightingPoint p, Triangle tri, GpuMaterial m, RaySample rays) {
  GpuLight L = lights[j];
  int type = lightType(j);
  // The rays' light mask, or the raster shadows' grid (TD_SHADOW_MASK), gathered above.
  bool rayShadowed = ((rayInputs & TD_RAY_LIGHT_MASK) != 0 || TD_SHADOW_MASK != 0) && L.radiance.w > 0.5;
  float vis = rayShadowed ? rays.vis[j] : 1.0;
  if (vis <= 0.0) return vec3(0.0);
  vec3 Lj;
  vec3 toLight;
  float dist;
#if TD_USE_AREA_LIGHTS
  if (lightIsArea(j)) {
    // The mean over the frame's samples (rt::shadeLocal's twin): with full-resolution rays each sample
    // counts where its shadow ray got through, so the pixel is exactly the ray pass's estimate; with a
    // coarser ray grid, all samples count, scaled by the visible fraction around the pixel.
    uint bits = 0xFFFFFFFFu;
#if !TD_RAY_SCALED
    if (rayShadowed) {
      bits = rays.area[j];
      vis = 1.0;
    }
#endif
    uint seed = tdPixelSeed(p.pTop.x, p.pTop.y, 0u);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < lightSamples; ++k) {
      if (((bits >> uint(k)) & 1u) == 0u) continue;
      vec2 u = tdLightSampleU(seed, j, sampleBase + uint(k));
      if (TD_USE_GOURAUD != 0 && p.model == TD_MODEL_GOURAUD) {
        vec3 E0 = tdAreaLightSample(L, type, tri.p0, u, toLight, dist);
        sum += p.b.x * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N0, normalize(p.origin - tri.p0), E0, toLight, 0.0);
        vec3 E1 = tdAreaLightSample(L, type, tri.p1, u, toLight, dist);
        sum += p.b.y * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N1, normalize(p.origin - tri.p1), E1, toLight, 0.0);
        vec3 E2 = tdAreaLightSample(L, type, tri.p2, u, toLight, dist);
        sum += p.b.z * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N2, normalize(p.origin - tri.p2), E2, toLight, 0.0);
      } else {
        vec3 E = tdAreaLightSample(L, type, p.posW, u, toLight, dist);
        float level = TD_USE_TOON != 0 && p.model == TD_MODEL_TOON ? toonLevel(m, dot(p.Ns, toLight)) : 0.0;
        sum += tdShadeLight(p.C, p.ks, p.ns, p.model, p.Ns, p.V, E, toLight, level);
      }
    }
    Lj = sum * (1.0 / float(lightSamples));
  } else
#endif
  if (TD_USE_GOURAUD != 0 && p.model == TD_MODEL_GOURAUD) {
    vec3 E0 = tdLightIncidentOfType(L, type, tri.p0, toLight, dist);
    vec3 L0 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N0, normalize(p.origin - tri.p0), E0, toLight, 0.0);
    vec3 E1 = tdLightIncidentOfType(L, type, tri.p1, toLight, dist);
    vec3 L1 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N1, normalize(p.origin - tri.p1), E1, toLight, 0.0);
    vec3 E2 = tdLightIncidentOfType(L, type, tri.p2, toLight, dist);
    vec3 L2 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N2, normalize(p.origin - tri.p2), E2, toLight, 0.0);
    Lj = p.b.x * L0 + p.b.y * L1 + p.b.z * L2;
  } else {
    vec3 E = tdLightIncidentOfType(L, type, p.posW, toLight, dist);
    float level = TD_USE_TOON != 0 && p.model == TD_MODEL_TOON ? toonLevel(m, dot(p.Ns, toLight)) : 0.0;
    Lj = tdShadeLight(p.C, p.ks, p.ns, p.model, p.Ns, p.V, E, toLight, level);
  }
#if TD_SHADOW_MAPS
  // A light that adds nothing here needs no map lookup (a GPU skips it where a whole warp agrees; llvmpipe
  // runs both sides); skipping it is exact, since vis · 0 would add nothing either.
  if (L.radiance.w > 0.5 && (Lj.x != 0.0 || Lj.y != 0.0 || Lj.z != 0.0)) vis = rasterShadow(j, p.posW, p.Ng, p.pTop);
  if (vis <= 0.0) return vec3(0.0);
#endif
  return vis * Lj;
}

void shadePixel() {
  ivec2 pix = ivec2(gl_FragCoord.xy);
  ivec2 pTop = ivec2(pix.x, frameSize.y - 1 - pix.y);
  uvec2 id = texelFetch(idsTex, pix, 0).xy;

  if (id.x == 0u) {
    outColor = vec4(debugView == TD_VIEW_FINAL ? background : vec3(0.0), 1.0);
    return;
  }
  if (debugView == TD_VIEW_DEPTH) {
    // Reversed-Z depth crowds towards 0 with distance; the fourth root spreads it over the grey ramp.
    outColor = vec4(vec3(pow(texelFetch(depthTex, pix, 0).r, 0.25)), 1.0);
    return;
  }
  if (debugView == TD_VIEW_INSTANCE) {
    outColor = vec4(hashColor(id.x), 1.0);
    return;
  }
  if (debugView == TD_VIEW_PRIMITIVE) {
    outColor = vec4(hashColor(id.x * 2654435761u + id.y), 1.0);
    return;
  }

  // ---- the exact hit ----
  PrimaryHit hit = primaryHit(pix, id);
  vec3 origin = hit.origin, dir = hit.dir;
  uint instance = hit.instance;
  Triangle tri = hit.tri;
  vec3 b = hit.b;
  vec3 posW = hit.posW;
  vec3 ngRaw = hit.ngRaw;
  bool onSolid = hit.onSolid;
  vec3 V = -dir;
  vec3 Ng = ngRaw;
  vec3 N = Ng;
  bool hasNormals = (tri.flags & TD_MESH_HAS_NORMALS) != 0u;
  if (hasNormals) {
    vec3 nO = b.x * objectNormal(tri.v0) + b.y * objectNormal(tri.v1) + b.z * objectNormal(tri.v2);
    vec3 n = tri.normalFromObject * nO;
    float len = length(n);
    if (len > 0.0) N = n / len;
  }
  GpuMaterial m = materials[tri.material];

  // ---- surface inputs: uv, texture × vertex colour, coverage, emissive and normal maps ----
  vec2 uv = vec2(0.0);
  vec3 tint = vec3(1.0);
  vec3 emission = vec3(m.emissionFlags);
  float texA = 1.0;  // kd texture alpha (coverage)
  if (TD_USE_UVS != 0 && (tri.flags & TD_MESH_HAS_UVS) != 0u) {
    vec2 uv0 = texelFetch(uvsBuf, int(tri.v0)).xy, uv1 = texelFetch(uvsBuf, int(tri.v1)).xy,
         uv2 = texelFetch(uvsBuf, int(tri.v2)).xy;
    int ut = 4 * int(tri.material);  // Material::uvTransform, its upper 3×3
    mat3 uvFromMesh = mat3(texelFetch(uvTransformsBuf, ut).xyz, texelFetch(uvTransformsBuf, ut + 1).xyz,
                           texelFetch(uvTransformsBuf, ut + 2).xyz);
    uv = (uvFromMesh * vec3(b.x * uv0 + b.y * uv1 + b.z * uv2, 1.0)).xy;
    bool kdTex = TD_USE_KD_TEXTURES != 0 && m.kdTex.w >= 0.0;
    bool emTex = TD_USE_EMISSIVE != 0 && m.texAlpha.x >= 0.0;
    bool nmTex = TD_USE_NORMAL_MAPS != 0 && m.texAlpha.y >= 0.0 && (tri.flags & TD_MESH_HAS_TANGENTS) != 0u;
    if (kdTex || emTex || nmTex) {
      // Ray differentials: where the neighbouring pixels' rays meet this triangle's plane gives exact
      // uv derivatives (screen-space dFdx would mix triangles at edges in a full-screen pass).
      vec3 ox, dx, oy, dy;
      cameraRay(gl_FragCoord.xy + vec2(1.0, 0.0), ox, dx);
      cameraRay(gl_FragCoord.xy + vec2(0.0, 1.0), oy, dy);
      vec3 bx = rayBarycentrics(ox, dx, tri);
      vec3 by = rayBarycentrics(oy, dy, tri);
      vec2 duvx = (uvFromMesh * vec3(bx.x * uv0 + bx.y * uv1 + bx.z * uv2, 1.0)).xy - uv;
      vec2 duvy = (uvFromMesh * vec3(by.x * uv0 + by.y * uv1 + by.z * uv2, 1.0)).xy - uv;
      if (kdTex) {
        vec4 texel = textureGrad(kdTextures, vec3(uv, float(int(m.kdTex.w + 0.5))), duvx, duvy);
        tint = texel.rgb;
        texA = texel.a;
      }
      if (emTex) emission *= textureGrad(kdTextures, vec3(uv, float(int(m.texAlpha.x + 0.5))), duvx, duvy).rgb;
#if TD_USE_NORMAL_MAPS
      if (nmTex) {
        // The CPU twin's frame (rt::resolveHit): interpolated tangent through the upper 3×3, the shared
        // perturbation, before the two-sided flip.
        vec4 t4 = b.x * texelFetch(tangentsBuf, int(tri.v0)) + b.y * texelFetch(tangentsBuf, int(tri.v1)) +
                  b.z * texelFetch(tangentsBuf, int(tri.v2));
        vec3 tn = textureGrad(normalMaps, vec3(uv, float(int(m.texAlpha.y + 0.5))), duvx, duvy).xyz * 2.0 - 1.0;
        N = tdPerturbNormal(N, tri.worldLinear * t4.xyz, t4.w, tn, m.texAlpha.z);
      }
#endif
    }
  }
  if (TD_USE_COLORS != 0 && (tri.flags & TD_MESH_HAS_COLORS) != 0u)
    tint *= (b.x * texelFetch(colorsBuf, int(tri.v0)) + b.y * texelFetch(colorsBuf, int(tri.v1)) +
             b.z * texelFetch(colorsBuf, int(tri.v2))).rgb;
  // The procedural texture (rt::resolveHit's twin): its value mixes kd and kd2, its gradient bumps N. The point
  // in the pattern's space: world (render space + the anchor), or object space, the vertices' positions
  // interpolated, or a solid's point brought back through the inverse of the instance's transform.
  float pattern = 0.0;
#if TD_USE_PROCEDURAL
  if (m.pattern.x > 0.5) {
    bool world = m.patternSpace.x > 0.5;
    vec3 p = world ? posW + renderAnchor
           : onSolid ? transpose(tri.normalFromObject) * (posW - instanceWorldFromObject(instance)[3].xyz)
                     : b.x * positionO(tri.v0) + b.y * positionO(tri.v1) + b.z * positionO(tri.v2);
    vec4 v = tdPattern(int(m.pattern.x + 0.5), p, m.pattern.y, m.pattern.z, int(m.pattern.w + 0.5));
    pattern = v.x;
    if (m.patternSpace.y > 0.0) N = tdBumpNormal(N, world ? v.yzw : tri.normalFromObject * v.yzw, m.patternSpace.y);
  }
#endif
  // BLEND coverage (MASK was decided by the visibility pass's discard: a pixel here is covered).
  float coverage = TD_USE_ALPHA_BLEND != 0 && m.texAlpha.w < 0.0 ? tdCoverage(m, texA) : 1.0;

  if (debugView == TD_VIEW_NORMAL) {
    outColor = vec4(0.5 + 0.5 * N, 1.0);
    return;
  }
  float side = dot(Ng, V) < 0.0 ? -1.0 : 1.0;  // two-sided: back faces are lit like fronts
  Ng *= side;
  N *= side;

  RaySample rays = gatherRays(pTop, id.x);
#if TD_SHADOW_MAPS
  // Raster shadows stand where the ray pass's light mask would (the two are never both on). The final
  // view looks a map up only where its light adds something (the light loop below), as the ray pass
  // traces a shadow ray only where the light can reach.
  if (debugView == TD_VIEW_LIGHT_MASK)
    for (int j = 0; j < TD_LIGHT_COUNT; ++j)
      rays.vis[j] = lights[j].radiance.w > 0.5 ? rasterShadow(j, posW, Ng, pTop) : 1.0;
#endif
#if TD_PROBES != 0
  if (tri.probe != 0u) {
    // Environment-mapped reflection and refraction through this object's probe, weighted like the ray
    // pass's Whitted::weights (docs/shading.md): Fresnel from the shared formulas, inside/outside from
    // the geometric normal, refraction by Snell at this surface only (no exit through the far side), and
    // the ray pass's directions: reflected over the facet, refracted through it (tdReflectOverFacet,
    // tdRefractOverFacet), so a silhouette's probe lookup is the direction its ray would take.
    float kr = m.krKtIorModel.x, kt = m.krKtIorModel.y, ior = m.krKtIorModel.z;
    bool backFace = side < 0.0;
    float etaI = backFace ? ior : 1.0, etaT = backFace ? 1.0 : ior;
    float cosI = clamp(dot(N, V), 0.0, 1.0);
    float eta = etaI / etaT;
    float cos2T = tdCos2T(cosI, eta);
    float F = 0.0;
    if (kt > 0.0 && etaI != etaT)
      F = cos2T <= 0.0 ? 1.0 : (TD_FRESNEL_SCHLICK != 0 ? tdFresnelSchlick(cosI, etaI, etaT) : tdFresnelExact(cosI, etaI, etaT));
    vec2 sum = tdWhittedSum(kr, kt, F, etaI != etaT && cos2T <= 0.0, TD_FRESNEL_WEIGHTED != 0);
    float wR = sum.x, wT = sum.y;
    // Coverage and tint (docs/gltf.md): the covered part reflects and refracts (tinted), the rest passes
    // straight through; BLEND materials have IOR 1, so both go along the same direction.
    wR *= coverage;
    int ut = 4 * int(tri.material) + 3;  // the transmission tint and roughness sit in the uv-transform record
    vec4 tintRough = texelFetch(uvTransformsBuf, ut);
    vec3 wTv = tdTransmitWeight(coverage, wT, tintRough.rgb);
    float layer = float(tri.probe - 1u);
    // A glossy material (docs/glossy.md) reads the probe at the mip level whose texels are as wide as its
    // lobe: about α = roughness² radians, a level-0 texel of an n² face being (π/2)/n.
    float alpha = tintRough.a * tintRough.a;
    float faceSize = float(textureSize(probes, 0).x);
    float lod = alpha > 0.0 ? clamp(log2(alpha * (faceSize * 2.0 / 3.14159265)), 0.0, log2(faceSize)) : 0.0;
#if (TD_PROBES & TD_PROBE_REFLECT) != 0
    if (wR > 0.0) rays.reflected += wR * textureLod(probes, vec4(tdReflectOverFacet(V, N, Ng), layer), lod).rgb;
#endif
#if (TD_PROBES & TD_PROBE_REFRACT) != 0
    if (wTv.x > 0.0 || wTv.y > 0.0 || wTv.z > 0.0) {
      vec3 T = etaI == etaT ? -V : tdRefractOverFacet(normalize(eta * -V + (eta * cosI - sqrt(max(cos2T, 0.0))) * N), V, Ng, eta);
      rays.transmitted += wTv * textureLod(probes, vec4(T, layer), kt > 0.0 ? lod : 0.0).rgb;  // pass-through: sharp
    }
#endif
  }
#endif
  if (debugView == TD_VIEW_LIGHT_MASK) {
    float visible = 1.0;
    if (((rayInputs & TD_RAY_LIGHT_MASK) != 0 || TD_SHADOW_MAPS != 0 || TD_SHADOW_MASK != 0) && TD_LIGHT_COUNT > 0) {
      visible = 0.0;
      for (int j = 0; j < TD_LIGHT_COUNT; ++j) visible += rays.vis[j];
      visible /= float(TD_LIGHT_COUNT);
    }
    outColor = vec4(vec3(visible), 1.0);
    return;
  }
  if (debugView == TD_VIEW_REFLECTION || debugView == TD_VIEW_TRANSMISSION) {
    outColor = vec4(debugView == TD_VIEW_REFLECTION ? rays.reflected : rays.transmitted, 1.0);
    return;
  }

  // ---- local shading ----
  vec3 C = tdSurfaceColor(m, uv, pattern, tint);
  int model = int(m.krKtIorModel.w + 0.5);
  vec3 local;
  if (m.emissionFlags.w > 0.5) {
    local = C + emission;
  } else {
    // Diffuse interreflection: the radiosity solution where it covers the surface, else the ambient term.
#if TD_USE_RADIOSITY
    vec3 H;
    local = emission + (radiosityAt(instance, id.y, b, side < 0.0, H) ? tdRadiosityTerm(m, H, uv, pattern, tint)
                                                                       : tdAmbient(m, ambientIa, uv, pattern, tint));
#else
    local = emission + tdAmbient(m, ambientIa, uv, pattern, tint);
#endif
    vec3 ks = vec3(m.ksNs);
    float ns = m.ksNs.w;
    vec3 Ns = model == TD_MODEL_FLAT ? Ng : N;
    vec3 N0 = Ng, N1 = Ng, N2 = Ng;
    if (TD_USE_GOURAUD != 0 && model == TD_MODEL_GOURAUD && hasNormals) {
      vec3 n0 = tri.normalFromObject * objectNormal(tri.v0);
      vec3 n1 = tri.normalFromObject * objectNormal(tri.v1);
      vec3 n2 = tri.normalFromObject * objectNormal(tri.v2);
      N0 = dot(n0, n0) > 0.0 ? side * normalize(n0) : Ng;
      N1 = dot(n1, n1) > 0.0 ? side * normalize(n1) : Ng;
      N2 = dot(n2, n2) > 0.0 ? side * normalize(n2) : Ng;
    }
    LightingPoint lp;
    lp.C = C;
    lp.ks = ks;
    lp.ns = ns;
    lp.model = model;
    lp.Ns = Ns;
    lp.N0 = N0;
    lp.N1 = N1;
    lp.N2 = N2;
    lp.posW = posW;
    lp.V = V;
    lp.origin = origin;
    lp.Ng = Ng;
    lp.b = b;
    lp.pTop = pTop;
    // One call per light with a constant index, not a loop: a body this large stays a rolled loop in the
    // compiler, whose light index is a variable, so every light would run every light type's code and every
    // map kind's lookup (llvmpipe runs both sides of each branch); the kinds (TD_LIGHT_KINDS) and
    // lightIsArea specialize a constant index only.
#define TD_ADD_LIGHT(J) if (J < TD_LIGHT_COUNT) local += directLight(J, lp, tri, m, rays);
    TD_ADD_LIGHT(0) TD_ADD_LIGHT(1) TD_ADD_LIGHT(2) TD_ADD_LIGHT(3)
    TD_ADD_LIGHT(4) TD_ADD_LIGHT(5) TD_ADD_LIGHT(6) TD_ADD_LIGHT(7)
#undef TD_ADD_LIGHT
  }

  vec3 I = coverage * local;
  if ((rayInputs & TD_RAY_REFLECTED) != 0 || (TD_PROBES & TD_PROBE_REFLECT) != 0) I += rays.reflected;
  if ((rayInputs & TD_RAY_TRANSMITTED) != 0 || (TD_PROBES & TD_PROBE_REFRACT) != 0) I += rays.transmitted;
#if TD_USE_TOON
  if (model == TD_MODEL_TOON && m.emissionFlags.w < 0.5 && isEdge(pix, id, ngRaw)) I = vec3(0.0);
#endif
  outColor = vec4(I, 1.0);
}

// The frame's shade pass also writes the display value (TD_FUSED_OUTPUT): one full-screen pass instead of
// a second one that reads the RGBA32F target back (on llvmpipe ~6 ms at 1280x720). Sky pixels never run
// this shader; their display value is the clear of attachment 1.
#ifndef TD_FUSED_OUTPUT
#define TD_FUSED_OUTPUT 0
#endif
#if TD_FUSED_OUTPUT
layout(location = 1) out TD_OUTPUT_DISPLAY outDisplay;
layout(location = TD_LOC_FUSED_EXPOSURE) uniform float exposure;
layout(location = TD_LOC_FUSED_TONE_MAP) uniform int toneMap;
layout(location = TD_LOC_FUSED_PASS_THROUGH) uniform int passThrough;
#endif

#if TD_SHADOW_MASK_PASS
// The shadow-mask pass: this target is the ray grid (rows top first, as RayOutputs holds them; gl_FragCoord's
// rows are the texture's), lights 0-3 in outColor, 4-7 here. Each grid pixel takes the visibility the full-
// resolution pass would look up at the pixel it stands for; no surface there (the sky): visible.
layout(location = 1) out TD_OUTPUT_SHADOW_MASK outMaskHi;

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
  outMaskHi = vec4(vis[4], vis[5], vis[6], vis[7]);
}
#endif

void main() {
#if TD_SHADOW_MASK_PASS
  shadowMaskPixel();
#else
  shadePixel();
#if TD_FUSED_OUTPUT
  outDisplay = vec4(tdDisplay(outColor.rgb, exposure, toneMap, passThrough != 0), 1.0);
#endif
#endif
}
