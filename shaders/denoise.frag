#version 450 core
// The spatiotemporal filter (docs/denoise.md; after SVGF, Schied et al., HPG 2017): the shade pass's noisy
// radiance divided by what it is made of (the area lights' light unshadowed, or a glossy surface's colour:
// neither texture detail nor a highlight that moves with the view enters the filter) is accumulated over
// frames along the motion vectors, its variance estimated from luminance moments, and smoothed by an
// edge-aware a-trous filter whose weights stop at other instances, at points off the centre's tangent plane,
// at other normals, and at luminance differences the variance does not explain. Five stages of one program
// (TD_DENOISE_STAGE):
//   0 temporal: reprojection, history rejection and clamping, moments, variance;
//   1 a-trous: one iteration at tap spacing `stepPx`, filter texels in and out;
//   2 compose: the last iteration's texels (which skipped the pixels the temporal stage found settled, as
//     every iteration does) multiplied back by the modulation, with the radiance that went past the filter (a
//     sharp mirror's or glass's rays) added: the filtered frame;
//   3 anti-aliasing (TAA): the filtered frame blended with the last frame's result reprojected along the
//     motion vectors and clamped to this frame's neighbourhood (the jittered frames' sub-pixel samples add up
//     at edges), into the frame's linear radiance and its display, and kept for the next frame;
//   4 upsampling: with rays on a coarser grid (gridScale > 1) the temporal stage and every a-trous iteration
//     run on the grid's pixels (each reads the frame pixel the grid traced: its own sample, not the shade
//     pass's blend of four; a quarter of the pixels at 1/2), and this stage takes each frame pixel's value
//     from its grid neighbours, edge-aware, then composes as stage 2 does for a full-resolution grid.
// Background pixels (instance 0) are never filtered. Texel layouts: denoise.glsl.
#define TD_OUT(T) out T
#include "bindings.glsl"
#include "shading.glsl"
#include "denoise.glsl"

#ifndef TD_DENOISE_STAGE
#define TD_DENOISE_STAGE 0
#endif
#ifndef TD_DENOISE_MOVED
#define TD_DENOISE_MOVED 1  // the temporal stage tests what moved (a frame where nothing did skips the test:
                            // a software GL runs even a uniform branch's untaken side, ~2 ms at 640x360)
#endif

layout(location = TD_LOC_CAMERA_RIGHT) uniform vec3 cameraRight;
layout(location = TD_LOC_CAMERA_UP) uniform vec3 cameraUp;
layout(location = TD_LOC_ORTHOGRAPHIC) uniform int orthographic;
layout(location = TD_LOC_DENOISE_AXIS) uniform vec3 cameraAxis;
layout(location = TD_LOC_FRAME_SIZE) uniform ivec2 frameSize;
layout(location = TD_LOC_DENOISE_STEP) uniform int stepPx;
layout(location = TD_LOC_DENOISE_HISTORY) uniform int history;
layout(location = TD_LOC_DENOISE_MAX_HISTORY) uniform float maxHistory;
layout(location = TD_LOC_DENOISE_EXPOSURE) uniform float exposure;
layout(location = TD_LOC_DENOISE_TONE_MAP) uniform int toneMap;
layout(location = TD_LOC_DENOISE_GRID_SCALE) uniform int gridScale;   // 1: the grid is the frame
layout(location = TD_LOC_DENOISE_GRID_SIZE) uniform ivec2 gridSize;   // the temporal and a-trous stages' pixels

layout(binding = TD_UNIT_DENOISE_NOISY) uniform TD_SAMPLER_DENOISE_NOISY noisyTex;
layout(binding = TD_UNIT_DENOISE_GUIDE) uniform TD_SAMPLER_DENOISE_GUIDE guideTex;
layout(binding = TD_UNIT_DENOISE_MOTION) uniform TD_SAMPLER_DENOISE_MOTION motionTex;
layout(binding = TD_UNIT_DENOISE_HISTORY) uniform TD_SAMPLER_DENOISE_TEXEL historyTex;
layout(binding = TD_UNIT_DENOISE_MOMENTS) uniform TD_SAMPLER_DENOISE_MOMENTS momentsTex;
layout(binding = TD_UNIT_DENOISE_INPUT) uniform TD_SAMPLER_DENOISE_TEXEL inputTex;
layout(binding = TD_UNIT_DENOISE_EXACT) uniform TD_SAMPLER_DENOISE_EXACT exactTex;
layout(binding = TD_UNIT_DENOISE_FILTERED) uniform TD_SAMPLER_DENOISE_RADIANCE filteredTex;
layout(binding = TD_UNIT_DENOISE_TAA_HISTORY) uniform TD_SAMPLER_DENOISE_RADIANCE taaHistoryTex;  // linear: the spline's taps

#if TD_DENOISE_STAGE == 2 || TD_DENOISE_STAGE == 4
layout(location = 0) out TD_OUTPUT_DENOISE_RADIANCE outFiltered;
#elif TD_DENOISE_STAGE == 3
layout(location = TD_LOC_DENOISE_JITTER) uniform vec2 jitterPx;
layout(location = 0) out TD_OUTPUT_LINEAR outLinear;
layout(location = 1) out TD_OUTPUT_DISPLAY outDisplay;
layout(location = 2) out TD_OUTPUT_DENOISE_RADIANCE outTaa;  // the next frame's history
#else
layout(location = 0) out TD_OUTPUT_DENOISE_TEXEL outTexel;   // the filter texel
#endif
#if TD_DENOISE_STAGE == 0
layout(location = 1) out TD_OUTPUT_DENOISE_MOMENTS outMoments;  // luminance, its square, history length
// The texel again into the iterations' other targets: a pixel they skip (gl_FragDepth 0) reads as drawn in
// every one of them.
layout(location = 2) out TD_OUTPUT_DENOISE_TEXEL outTexelB;
layout(location = 3) out TD_OUTPUT_DENOISE_TEXEL outHistory;
#endif

// Whether a texel's noise is below what the display shows (its standard deviation under 1 % of its
// luminance, under one 8-bit step of sRGB's mid-tones): the a-trous iterations leave such a pixel as it is, and skip it (a software GL skips whole
// blocks of them by the depth test, before any shading).
bool settled(vec3 illum, float var) { return sqrt(var) <= 0.01 * tdDenoiseLuminance(illum) + 1e-5; }

// A pixel's four neighbours (the temporal and anti-aliasing stages' neighbourhoods: a cross of five).
const ivec2 cross4[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));

// The frame pixel (GL rows) grid pixel q (GL rows) stands for: the one the ray pass traced for it (rows from
// the top, engine/src/rt/RayTracer.h), where the shade pass's value is that grid pixel's own sample.
ivec2 standIn(ivec2 q) {
  ivec2 top = min(ivec2(q.x, gridSize.y - 1 - q.y) * gridScale + gridScale / 2, frameSize - 1);
  return ivec2(top.x, frameSize.y - 1 - top.y);
}
// A frame position (GL rows, pixels, centres at .5) in grid pixels (the stand-ins' centres at .5). Where the
// frame is not a whole number of grid pixels, the last grid row or column's stand-in is clamped to the frame's
// edge and this spacing is off there by up to half a grid pixel.
vec2 toGrid(vec2 x) {
  vec2 top = vec2(x.x, float(frameSize.y) - x.y);
  vec2 g = (top - (float(gridScale / 2) + 0.5)) / float(gridScale) + 0.5;
  return vec2(g.x, float(gridSize.y) - g.y);
}
// The grid pixel whose block of frame pixels holds frame pixel p (blocks of rows counted from the top, as the
// ray grid's).
ivec2 gridOf(ivec2 p) {
  ivec2 g = min(ivec2(p.x, frameSize.y - 1 - p.y) / gridScale, gridSize - 1);
  return ivec2(g.x, gridSize.y - 1 - g.y);
}

// Pixel q's normalized device coordinates.
vec2 ndcOf(ivec2 q) { return (vec2(q) + 0.5) / vec2(frameSize) * 2.0 - 1.0; }

vec3 illumination(uvec4 t) { return vec3(unpackHalf2x16(t.x), unpackHalf2x16(t.y).x); }
// The variance's sign bit (a variance is never negative) says whether the temporal stage dropped the pixel's
// history (stale, off the last frame, its light changed): the iterations carry it with the centre to the
// stage that writes the filtered frame, whose alpha takes it to the anti-aliasing (its history goes too).
const uint kDropped = 0x80000000u;
float variance(uvec4 t) { return unpackHalf2x16(t.y & ~kDropped).y; }
bool dropped(uvec4 t) { return (t.y & kDropped) != 0u; }
// (Clamped under half precision's largest value: an infinity there would turn a zero weight's product into a
// NaN that reprojection carries on.)
uvec4 filterTexel(vec3 illum, float var, uint depthBits, uint normalInstance, bool drop) {
  illum = min(illum, vec3(65000.0));
  var = clamp(var, 0.0, 65000.0);
  return uvec4(packHalf2x16(illum.rg), packHalf2x16(vec2(illum.b, var)) | (drop ? kDropped : 0u), depthBits,
               normalInstance);
}

// ---- stage 0: temporal accumulation ----
#if TD_DENOISE_STAGE == 0
layout(location = TD_LOC_DENOISE_CAMERA_POS) uniform vec3 cameraPosR;
layout(location = TD_LOC_DENOISE_MOVED_COUNTS) uniform ivec2 movedCounts;  // boxes, area lights
layout(location = TD_LOC_DENOISE_MOVED_BOXES) uniform vec4 movedBoxes[2 * TD_MAX_MOVED_BOXES];
layout(location = TD_LOC_DENOISE_AREA_LIGHTS) uniform vec4 areaLights[TD_MAX_LIGHTS];
layout(location = TD_LOC_DENOISE_MOVED_REACH) uniform float movedReach;
layout(location = TD_LOC_DENOISE_LOBES_STALE) uniform int lobesStale;
layout(binding = TD_UNIT_DENOISE_IDS) uniform TD_SAMPLER_IDS idsTex;

// Whether an instance that moved since the last frame (a box holding where it was and where it is, other than
// the point's own instance) may have changed the light the filter smooths at the point: by standing between
// the point and an area light, or (a glossy surface, `lobe`: tdLobeOf) in what its lobe reflects or
// transmits. The shadow rays from the point P to a light of radius r at c stay within r·t of the segment at the
// fraction t of the way (a cone from the point), and so within the square pyramid of half-width r·t about it.
// The pyramid meets a box [lo, hi] at t where, on every axis, lo - r·t <= P + t·(c - P) <= hi + r·t: two
// linear bounds on t an axis, lower or upper by the sign of (c - P) ± r, so one pass finds whether some t in
// [0, 1] meets them all. (Growing the box by r alone flagged every point of a floor beside objects resting on
// it: the cone is narrow near the point. Four slab tests, the box grown by r times where the last one left
// the segment, converged towards this bound and cost two and a half times as much on a software GL.) A
// reflection lobe is one more such cone: about the mirror direction, as long as the farthest moved box is
// from the point (`movedReach` from the camera, plus the point's own distance), as wide as the lobe; a
// transmitting lobe takes every moved box. Run here, on the grid's pixels (a quarter of the frame's at 1/2),
// not in the shade pass.
// Whether a moved box, other than one of the point's own instance, meets the cone from the point to the disk of
// radius cone.w at cone.xyz (`every`: whether there is such a box at all).
bool boxInCone(uint instance, vec3 posR, vec4 cone, bool every) {
  // Lights outside, boxes inside: the per-axis reciprocals and which bound each gives, once a cone.
  vec3 to = cone.xyz - posR;
  float r = cone.w;
  vec3 inPlus = 1.0 / (to + r), inMinus = 1.0 / (to - r);
  // lo side: t·(to + r) >= lo - P, a lower bound where to + r > 0, an upper one where < 0; hi side:
  // t·(to - r) <= hi - P, an upper bound where to - r > 0, a lower one where < 0 (at 0 the side holds or
  // fails for every t: left out, which only flags more).
  bvec3 plusLower = greaterThan(to + r, vec3(0.0)), plusUpper = lessThan(to + r, vec3(0.0));
  bvec3 minusUpper = greaterThan(to - r, vec3(0.0)), minusLower = lessThan(to - r, vec3(0.0));
  const vec3 none = vec3(1e30);
  bool inside = false;
  for (int k = 0; k < movedCounts.x; ++k) {
    vec4 lo = movedBoxes[2 * k], hi = movedBoxes[2 * k + 1];
    vec3 tLo = (lo.xyz - posR) * inPlus, tHi = (hi.xyz - posR) * inMinus;
    vec3 lower = max(mix(-none, tLo, plusLower), mix(-none, tHi, minusLower));
    vec3 upper = min(mix(none, tLo, plusUpper), mix(none, tHi, minusUpper));
    float enter = max(max(lower.x, lower.y), max(lower.z, 0.0));
    float leave = min(min(upper.x, upper.y), min(upper.z, 1.0));
    // (lo.w: the box's instance, -1 for boxes of several merged; the point's own instance is no blocker)
    bool own = lo.w >= 0.0 && uint(lo.w + 0.5) == instance;
    inside = inside || ((enter <= leave || every) && !own);
  }
  return inside;
}
bool mayHaveChanged(uint instance, vec3 posR, vec3 N, float lobe) {
  bool mayHave = false;
  for (int j = 0; j < movedCounts.y; ++j) {
    bool inCone = boxInCone(instance, posR, areaLights[j], false);
    mayHave = mayHave || inCone;
  }
  // The lobe's cone in a loop of its own, one trip where the pixel has a lobe: a software GL skips a loop whose
  // lanes all ended (it runs both sides of a branch), so a frame without glossy surfaces pays nothing for it.
  for (int once = 0; once < (lobe != 0.0 ? 1 : 0); ++once) {
    vec3 V = orthographic != 0 ? -cameraAxis : normalize(cameraPosR - posR);
    float reach = length(cameraPosR - posR) + movedReach;
    // The lobe's axis as the ray pass bends it is within ~0.03 rad of the mirror direction rebuilt here (the
    // guide's normal is three bytes; near a silhouette the rays' axis is bent over the facet): the cone is
    // that much wider, so that a sharp lobe's small one does not miss what is dead ahead.
    vec4 lobeCone = vec4(posR + reflect(-V, normalize(N)) * reach, reach * (abs(tdLobeSpread(lobe)) + 0.03));
    bool inCone = boxInCone(instance, posR, lobeCone, lobe < 0.0);
    mayHave = mayHave || inCone;
  }
  return mayHave;
}

// Frame pixel q's point at view depth z (render space; tangentPlane's reconstruction, from the pixel's centre).
vec3 pointAt(ivec2 q, float z) {
  vec2 ndc = ndcOf(q);
  vec3 across = cameraRight * ndc.x + cameraUp * ndc.y;
  return cameraPosR + (orthographic != 0 ? across + z * cameraAxis : z * (cameraAxis + across));
}

void temporal() {
  ivec2 p = ivec2(gl_FragCoord.xy);  // a grid pixel
  ivec2 at = standIn(p);
  uvec4 g = texelFetch(guideTex, at, 0);
  uint tag = tdInstanceTag(g.y);
  if (tag == 0u) {
    outTexel = outTexelB = outHistory = uvec4(0u);
    outMoments = vec4(0.0);
    gl_FragDepth = 0.0;
    return;
  }
  vec3 cur = texelFetch(noisyTex, at, 0).rgb;
  if (any(isnan(cur)) || any(isinf(cur))) cur = vec3(0.0);  // a shading fault must not live on in the history
  // This frame's neighbourhood (a cross of five): the box the history is clamped to (a light switched off, a
  // reflection that moved otherwise than its surface), and the variance of a history too short for its own
  // moments. Taps off the frame read the edge; on a coarser grid the neighbours are the next grid pixels'
  // (samples of their own).
  vec3 m1 = cur, m2 = cur * cur;
  for (int k = 0; k < 4; ++k) {
    vec3 c = texelFetch(noisyTex, standIn(clamp(p + cross4[k], ivec2(0), gridSize - 1)), 0).rgb;
    if (any(isnan(c)) || any(isinf(c))) c = vec3(0.0);  // (a neighbour's fault: max or clamp of a NaN is undefined)
    m1 += c;
    m2 += c * c;
  }
  vec3 mean = m1 / 5.0;
  vec3 sigma = sqrt(max(m2 / 5.0 - mean * mean, vec3(0.0)));
  float lMean = tdDenoiseLuminance(mean);
  float spatialVariance = max(tdDenoiseLuminance(m2 / 5.0) - lMean * lMean, 0.0);

  // The point's place in the last frame: a bilinear tap of the four texels around it, each kept only where
  // the last frame showed the same instance at the depth the point had then, facing the same way.
  vec4 m = texelFetch(motionTex, at, 0);
  // The point lay in the last frame, and no instance that moved may have changed its light. A glossy lobe
  // gathers the light of every kind of light off what it sees: a change of the lights the filter does not
  // smooth (which go past it where they light the point itself) changes it.
  vec3 N = tdUnpackNormal(g.y);
  float lobe = unpackHalf2x16(g.w).y;  // (tdLobeOf: the cone's spread only where the test runs)
  bool holds = history != 0 && m.w > 0.5 && !(lobesStale != 0 && lobe != 0.0);
  if (TD_DENOISE_MOVED != 0)
    holds = holds && !mayHaveChanged(texelFetch(idsTex, at, 0).x - 1u, pointAt(at, uintBitsToFloat(g.x)), N, lobe);
  vec3 past = vec3(0.0);
  float weight = 0.0;
  // The heaviest texel kept: its moments (luminance, its square, history length) are the history's. (A
  // bilinear blend of the four would widen the spread by their differences across a gradient, and cost four
  // fetches: ~1.8 ms at 640x360 on a software GL.)
  float heaviest = 0.0;
  ivec2 from = ivec2(0);
  // (Without branches: a software GL runs both sides of a branch its SIMD lanes disagree on, and a branch in a
  // loop costs it masks besides. Every pixel fetches the four taps; a tap off the grid (it reads the edge), one
  // not kept and every tap of a pixel without a history weigh nothing, which costs it less than the masks.)
  vec2 before = toGrid(vec2(at) + 0.5 - m.xy);
  vec2 base = floor(before - 0.5);
  vec2 f = before - 0.5 - base;
  for (int k = 0; k < 4; ++k) {
    ivec2 o = ivec2(k & 1, k >> 1);
    ivec2 want = ivec2(base) + o;
    ivec2 q = clamp(want, ivec2(0), gridSize - 1);
    uvec4 h = texelFetch(historyTex, q, 0);
    float depthThen = uintBitsToFloat(h.z);
    bool keep = holds && q == want && tdInstanceTag(h.w) == tag && abs(depthThen - m.z) <= 0.03 * m.z &&
                dot(tdUnpackNormal(h.w), N) >= 0.9;
    float w = keep ? (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y) : 0.0;
    past += w * illumination(h);
    weight += w;
    from = w > heaviest ? q : from;
    heaviest = max(heaviest, w);
  }
  float len = 1.0;
  // Whether the anti-aliasing's history must go too: the point was not in the last frame, its light may have
  // changed, or the history was stale. (Another instance there, a disocclusion or an edge the jitter crosses,
  // is not: the anti-aliasing's box bounds it, and edges are what it is for.)
  bool drop = history != 0 && !holds;
  vec3 illum = cur;
  float l = tdDenoiseLuminance(cur);
  vec2 moments = vec2(l, l * l);
  if (weight > 0.01) {
    past /= weight;
    vec3 pastMoments = texelFetch(momentsTex, from, 0).rgb;
    len = min(floor(pastMoments.z + 0.5) + 1.0, maxHistory);
    // Stale history (a shadow that went with the object casting it, a reflection that moved otherwise than its
    // surface) lies outside what this frame's neighbourhood allows: the difference between the two means,
    // five samples' and `len` frames', is within 4 standard deviations of their noise. One sample's spread is
    // the history's (its moments) for the history's mean; for this frame's, the neighbourhood's own, but at
    // least half the history's (a penumbra's samples are 0 or 1, and five of them may well all agree; after a
    // change they agree because the light is no longer half blocked). A history outside that box is dropped.
    float spread = sqrt(max(pastMoments.y - pastMoments.x * pastMoments.x, 0.0));
    vec3 perSample = max(sigma, vec3(0.5 * spread));
    vec3 box = 4.0 * sqrt(perSample * perSample / 5.0 + spread * spread / max(len - 1.0, 1.0)) +
               vec3(0.02 * tdDenoiseLuminance(mean) + 1e-3);
    if (any(greaterThan(abs(past - mean), box))) {
      // Stale: the pixel starts again as a newly seen one (its moments too: a spread made of the old light and
      // the new would let the old one through the next frames' boxes).
      len = 1.0;
      drop = true;
    } else {
      float alpha = 1.0 / len;
      illum = mix(past, cur, alpha);
      moments = mix(pastMoments.xy, moments, alpha);
    }
  }
  // The variance of one frame's sample, from the moments; with few frames of history, the neighbourhood's
  // (SVGF's bootstrap). What the a-trous weights need is the noise left in the temporal mean: that over the
  // frames it averages, so a view that holds still filters less and less, towards its exact mean.
  float var = len >= 4.0 ? max(moments.y - moments.x * moments.x, 0.0) : spatialVariance;
  var /= len;
  outTexel = outTexelB = outHistory = filterTexel(illum, var, g.x, g.y, drop);
  outMoments = vec4(moments, len, 0.0);
  gl_FragDepth = settled(illum, var) ? 0.0 : 1.0;
}
#endif

// ---- stages 1, 2 and 4: one a-trous iteration, the upsampling ----

// A point's tangent plane, as the a-trous and upsampling taps measure distances off it. The point pixel q
// shows at view depth zq, relative to the camera, is zq·(F + R·x + U·y) (perspective; F the forward axis, R and
// U the scaled right and up, x and y its ndc), or R·x + U·y + zq·F (orthographic). Its distance off the plane,
// dot(N, Pq − P), is then affine in x, y and zq: three dot products once per pixel, a few multiplies per tap.
struct TangentPlane {
  vec3 N;
  float nf, nr, nu, at;
  float footprint;  // a pixel's width at the point's depth
};
TangentPlane tangentPlane(vec3 N, float z, vec2 ndc) {
  TangentPlane t;
  t.N = N;
  t.nf = dot(N, cameraAxis);
  t.nr = dot(N, cameraRight);
  t.nu = dot(N, cameraUp);
  bool ortho = orthographic != 0;
  t.at = ortho ? t.nr * ndc.x + t.nu * ndc.y + z * t.nf : z * (t.nf + t.nr * ndc.x + t.nu * ndc.y);
  t.footprint = 2.0 * length(cameraUp) * (ortho ? 1.0 : z) / float(frameSize.y);
  return t;
}
float planeDistance(TangentPlane t, float zq, vec2 nq) {
  float along = t.nr * nq.x + t.nu * nq.y;
  return abs((orthographic != 0 ? along + zq * t.nf : zq * (t.nf + along)) - t.at);
}
// The normals' weight, max(cos, 0)^32 by squaring.
float normalWeight(TangentPlane t, uint normalInstance) {
  float wn = max(dot(t.N, tdUnpackNormal(normalInstance)), 0.0);
  wn *= wn;
  wn *= wn;
  wn *= wn;
  wn *= wn;
  return wn * wn;
}

// One iteration at grid pixel p (a frame pixel when gridScale is 1): taps stepPx grid pixels apart.
uvec4 atrous(ivec2 p, uvec4 centre) {
  uint tag = tdInstanceTag(centre.w);
  vec3 c0 = illumination(centre);
  float v0 = variance(centre);
  float lc = tdDenoiseLuminance(c0);
  vec2 ndc = ndcOf(standIn(p));
  TangentPlane plane = tangentPlane(tdUnpackNormal(centre.w), uintBitsToFloat(centre.z), ndc);
  // The weights as one exponential: the distance off the plane in pixel footprints at the centre's depth (per
  // frame pixel of tap spacing), and the luminance difference in units of the centre's noise (a pixel whose
  // samples agree has none and keeps its value). log2(e) is folded into both scales.
  const float spacing = float(stepPx * gridScale);  // in frame pixels
  float planeScale = 1.4426950 / (plane.footprint * spacing);
  float lumScale = 1.4426950 / (4.0 * sqrt(max(v0, 0.0)) + 1e-6);
  vec2 ndcStep = 2.0 * spacing / vec2(frameSize);
  const float kernel[3] = float[3](0.25, 0.5, 0.25);
  vec3 sum = c0 * 0.25;
  float wsum = 0.25;
  float vsum = 0.0625 * v0;
  // Branch-free taps (a software GL runs both sides of a branch its SIMD lanes disagree on): a tap off the
  // frame reads the nearest edge texel and weighs nothing, as does one on another instance.
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      ivec2 want = p + stepPx * ivec2(dx, dy);
      ivec2 q = clamp(want, ivec2(0), gridSize - 1);
      uvec4 t = texelFetch(inputTex, q, 0);
      vec3 c = illumination(t);
      float d = (dx == 0 || dy == 0) ? 1.0 : 1.41421356;
      float e = planeDistance(plane, uintBitsToFloat(t.z), ndc + ndcStep * vec2(dx, dy)) * planeScale / d +
                abs(tdDenoiseLuminance(c) - lc) * lumScale;
      float valid = (q == want && tdInstanceTag(t.w) == tag) ? 1.0 : 0.0;
      float w = kernel[dx + 1] * kernel[dy + 1] * valid * normalWeight(plane, t.w) * exp2(-e);
      sum += w * c;
      wsum += w;
      vsum += w * w * variance(t);
    }
  return filterTexel(sum / wsum, vsum / (wsum * wsum), centre.z, centre.w, dropped(centre));
}

// ---- stage 4: upsampling from a coarser grid ----
#if TD_DENOISE_STAGE == 4
// Frame pixel p's filtered illumination from the grid's: its four bilinear neighbours among the grid pixels,
// each weighed as an a-trous tap (the same instance, near p's tangent plane, facing its way). None of them
// weighs anything: the nearest of them that shows p's instance (a crease), else (a thin object, a silhouette)
// p's own sample, which the shade pass gathered from the nearest grid pixel within one step that shows p's
// instance: the same grid pixel's light, unfiltered. (A wider search here would be run by every pixel: a
// software GL runs both sides of the branch, ~40 % of this stage on llvmpipe.) `drop`: whether the temporal
// stage dropped the history of the grid pixel whose block holds p (always one of the four).
vec3 upsample(ivec2 p, uvec4 guide, out bool drop) {
  uint tag = tdInstanceTag(guide.y);
  vec2 ndc = ndcOf(p);
  TangentPlane plane = tangentPlane(tdUnpackNormal(guide.y), uintBitsToFloat(guide.x), ndc);
  float planeScale = 1.4426950 / (plane.footprint * float(gridScale));
  vec2 u = toGrid(vec2(p) + 0.5) - 0.5;
  ivec2 g0 = ivec2(floor(u));
  vec2 f = u - vec2(g0);
  vec3 sum = vec3(0.0);
  float wsum = 0.0;
  vec3 nearest = texelFetch(noisyTex, p, 0).rgb;
  if (any(isnan(nearest)) || any(isinf(nearest))) nearest = vec3(0.0);  // (a shading fault, as the temporal stage's)
  float nearestD = 1e30;
  ivec2 block = gridOf(p);
  drop = false;
  for (int k = 0; k < 4; ++k) {
    ivec2 o = ivec2(k & 1, k >> 1);
    ivec2 want = g0 + o;
    ivec2 q = clamp(want, ivec2(0), gridSize - 1);
    uvec4 t = texelFetch(inputTex, q, 0);
    vec3 c = illumination(t);
    drop = q == block ? dropped(t) : drop;
    vec2 bilinear = mix(vec2(1.0) - f, f, vec2(o));
    float valid = (q == want && tdInstanceTag(t.w) == tag) ? 1.0 : 0.0;
    float w = bilinear.x * bilinear.y * valid * normalWeight(plane, t.w) *
              exp2(-planeDistance(plane, uintBitsToFloat(t.z), ndcOf(standIn(q))) * planeScale);
    sum += w * c;
    wsum += w;
    vec2 d = vec2(q) - u;
    if (valid > 0.0 && dot(d, d) < nearestD) {
      nearestD = dot(d, d);
      nearest = c;
    }
  }
  return wsum > 1e-4 ? sum / wsum : nearest;
}
#endif

// ---- stage 3: temporal anti-aliasing ----
#if TD_DENOISE_STAGE == 3
// The last frame's anti-aliased radiance at window position `at` (pixels, centres at .5) through a Catmull-Rom
// spline along each axis (the 4×4 texels around it), which keeps an edge as sharp as the texels hold it where a
// bilinear tap blurs it by up to half a pixel each frame. Its two middle weights along an axis are both positive,
// so one bilinear tap between their texels, at their weights' ratio, gives their sum: 3 taps an axis, and of
// the 3×3 the four corners (each the product of two outer weights: 1.6 % of the whole together at most) are left
// out and the rest renormalized: 5 bilinear taps. Its outer weights are negative: it overshoots at a step, which
// the neighbourhood's clamp takes back; and an infinity in the history (a filtered value past half precision's
// largest) would meet them as inf - inf: this frame's own sample then stands in for the history.
vec3 historyCatmullRom(vec2 at) {
  vec2 texel = at - 0.5;
  vec2 i = floor(texel), f = texel - i;
  // The spline's weights for texels i - 1, i, i + 1 and i + 2 at the fraction f between i and i + 1.
  vec2 wBefore = f * (-0.5 + f * (1.0 - 0.5 * f));
  vec2 wNear = 1.0 + f * f * (-2.5 + 1.5 * f);
  vec2 wFar = f * (0.5 + f * (2.0 - 1.5 * f));
  vec2 wAfter = f * f * (-0.5 + 0.5 * f);
  vec2 wMiddle = wNear + wFar;
  vec2 size = vec2(frameSize);
  vec2 before = (i - 0.5) / size, middle = (i + 0.5 + wFar / wMiddle) / size, after = (i + 2.5) / size;
  vec3 sum = textureLod(taaHistoryTex, middle, 0.0).rgb * (wMiddle.x * wMiddle.y) +
             textureLod(taaHistoryTex, vec2(before.x, middle.y), 0.0).rgb * (wBefore.x * wMiddle.y) +
             textureLod(taaHistoryTex, vec2(after.x, middle.y), 0.0).rgb * (wAfter.x * wMiddle.y) +
             textureLod(taaHistoryTex, vec2(middle.x, before.y), 0.0).rgb * (wMiddle.x * wBefore.y) +
             textureLod(taaHistoryTex, vec2(middle.x, after.y), 0.0).rgb * (wMiddle.x * wAfter.y);
  return sum / (wMiddle.x * (wMiddle.y + wBefore.y + wAfter.y) + wMiddle.y * (wBefore.x + wAfter.x));
}

void antiAlias(ivec2 p) {
  vec4 centre = texelFetch(filteredTex, p, 0);
  vec3 current = centre.rgb;
  // This frame's neighbourhood (a cross of five) bounds what the history may say (a history outside it is
  // stale: a disocclusion, a change of light).
  vec3 lo = current, hi = current;
  vec3 across[4];
  for (int k = 0; k < 4; ++k) {
    vec3 c = texelFetch(filteredTex, clamp(p + cross4[k], ivec2(0), frameSize - 1), 0).rgb;
    across[k] = c;
    lo = min(lo, c);
    hi = max(hi, c);
  }
  // Without a history: the frame's value at the pixel's centre, not at its jittered sample (a sample off the
  // centre is further from the pixel's mean than the centre's), interpolated along each axis between the
  // pixel's sample and the neighbour's on the other side of the centre.
  vec2 toward = step(0.0, jitterPx);  // 1: the neighbour on the negative side
  vec3 nx = mix(across[0], across[1], toward.x), ny = mix(across[2], across[3], toward.y);
  vec3 result = current + abs(jitterPx.x) * (nx - current) + abs(jitterPx.y) * (ny - current);
  vec4 m = texelFetch(motionTex, p, 0);
  // The background has no motion of its own (its motion's w is -1): its colour is the same wherever it is.
  bool background = m.w < -0.5;
  // A pixel whose filter history was dropped as stale (or off the last frame, or its light changed) drops this
  // one too: the box above is as wide as a fresh pixel's noise, and would let the old colour through. (The
  // filtered frame's alpha: the temporal stage's flag, carried by the texels.)
  bool fresh = !background && centre.a > 0.5;
  if (history != 0 && !fresh && (background || m.w > 0.5)) {
    vec2 motion = background ? vec2(0.0) : m.xy;
    // (A bilinear tap's blur adds up over the history: with it, area-lights.json's floor with alpha stripes,
    // panning, was FLIP 0.032 from the truth, behind four raw samples' 0.027; with the spline 0.0245.)
    vec3 past = historyCatmullRom(vec2(p) + 0.5 - motion);
    if (any(isnan(past)) || any(isinf(past))) past = current;  // (a GLSL clamp of a NaN is undefined)
    past = clamp(past, lo, hi);
    // The new frame's share: 0.15 up to 1.5 pixels of motion a frame (the jittered frames' sub-pixel samples
    // add up over ~12 frames), rising to 0.5 at 3 and beyond (each frame's resampling of the history blurs it,
    // the spline less than a bilinear tap but still, and over a long history the blur costs more than the
    // averaging gains; the camera's jitter fades over the same range: render/Accumulation.h's
    // filteredJitterScale). In the game's run, 2 to 16 pixels a frame, FLIP 0.037 at 0.15 throughout, 0.030 so
    // (with a bilinear tap; with the spline, 0.3 beyond 3 pixels measured 0.0365 against 0.5's 0.0351).
    result = mix(past, current, mix(0.15, 0.5, clamp((length(motion) - 1.5) / 1.5, 0.0, 1.0)));
  }
  outLinear = vec4(result, 1.0);
  outDisplay = vec4(tdDisplay(result, exposure, toneMap, false), 1.0);
  outTaa = vec4(result, 1.0);
}
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
#if TD_DENOISE_STAGE == 0
  temporal();
#elif TD_DENOISE_STAGE == 1
  // (Only pixels the temporal stage left unsettled run this: the depth test.)
  outTexel = atrous(p, texelFetch(inputTex, p, 0));
#elif TD_DENOISE_STAGE == 2
  // Compose: back to radiance (times the modulation).
  uvec4 centre = texelFetch(inputTex, p, 0);
  // (The background's radiance is all past the filter: the environment, as the shade pass wrote it.)
  vec3 exact = texelFetch(exactTex, p, 0).rgb;
  vec3 linear = exact;
  bool drop = false;
  if (tdInstanceTag(centre.w) != 0u) {
    uvec4 g = texelFetch(guideTex, p, 0);
    vec3 modulation = vec3(unpackHalf2x16(g.z), unpackHalf2x16(g.w).x);
    vec3 illum = illumination(centre);
    linear = illum * modulation + exact;
    drop = dropped(centre);
  }
  outFiltered = vec4(linear, drop ? 1.0 : 0.0);
#elif TD_DENOISE_STAGE == 4
  // Last on a coarser grid: the grid's filtered value at this pixel, times the pixel's own modulation.
  uvec4 g = texelFetch(guideTex, p, 0);
  vec3 exact = texelFetch(exactTex, p, 0).rgb;
  vec3 linear = exact;
  bool drop = false;
  if (tdInstanceTag(g.y) != 0u) {
    vec3 modulation = vec3(unpackHalf2x16(g.z), unpackHalf2x16(g.w).x);
    linear = upsample(p, g, drop) * modulation + exact;
  }
  outFiltered = vec4(linear, drop ? 1.0 : 0.0);
#else
  antiAlias(p);
#endif
}
