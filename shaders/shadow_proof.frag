#version 450 core
// Shadow proofs in the GL (docs/shadows.md, "Proofs in the GL"): per pixel and direct light, whether the
// primary hit's shadow ray certainly reaches the light (lit), is certainly blocked (shadowed), or neither,
// from the hybrid shadows' light-space maps (rt/ShadowCertainty.h), which the GL holds as buffer textures.
// The CPU's ray pass reads the answers with the ids and traces only the rays left open.
//
// The CPU's own shadow ray starts at its exact hit offset by spawnOrigin; this pass rebuilds the hit from the
// pixel's camera ray as the shade pass does, with another rounding, so it answers for every ray whose origin
// lies within `e` of its own (the hit's error bound plus the offset) and that ends where the CPU's does: the
// tests of classify() run with their margins grown by how far a point of the CPU's ray can lie from the
// matching point of this one (E), its texel path and depth with E as well. Whatever that leaves unsure is
// left to the ray.
#define TD_OUT(T) out T
#include "bindings.glsl"
#include "shading.glsl"  // TD_MAX_LIGHTS, GpuLight, tdLightIncident
#include "scene.glsl"    // TD_MESH_HAS_NORMALS

layout(binding = TD_UNIT_POSITIONS_TEX) uniform samplerBuffer positionsBuf;
layout(binding = TD_UNIT_INDICES_TEX) uniform usamplerBuffer indicesBuf;
layout(binding = TD_UNIT_MESHES_TEX) uniform usamplerBuffer meshesBuf;
layout(binding = TD_UNIT_INSTANCES_TEX) uniform samplerBuffer instancesBuf;
layout(binding = TD_UNIT_INSTANCE_IDS_TEX) uniform usamplerBuffer instanceIdsBuf;
layout(binding = TD_UNIT_IDS) uniform TD_SAMPLER_IDS idsTex;
layout(binding = TD_UNIT_EXACT_HITS) uniform TD_SAMPLER_EXACT_HITS exactHitsTex;  // unread: no solid is proved
// The maps: each texel's record (rt::ShadowCertainty::Texel, TD_PROOF_RECORD words: candidate ids, their
// depth bounds, the rest's bound), each triangle's test (5 texels: plane, three edges, then magnitude,
// valid, blocks), the near-light lists, and per instance its first global triangle id (~0: not proved).
layout(binding = TD_UNIT_PROOF_TEXELS) uniform usamplerBuffer proofTexels;        // R32UI
layout(binding = TD_UNIT_PROOF_TRIANGLES) uniform samplerBuffer proofTriangles;   // RGBA32F
layout(binding = TD_UNIT_PROOF_NEAR) uniform usamplerBuffer proofNear;            // R32UI
layout(binding = TD_UNIT_PROOF_INSTANCES) uniform usamplerBuffer proofInstances;  // R32UI
layout(binding = TD_UNIT_PROOF_FLAGS) uniform usamplerBuffer proofFlags;          // R32UI, this frame's
layout(binding = TD_UNIT_NORMALS_TEX) uniform samplerBuffer normalsBuf;           // RGB32F, object space
layout(std140, binding = TD_BLOCK_LIGHTS) uniform LightBlock { GpuLight lights[TD_MAX_LIGHTS]; };

struct ProofMap {
  vec4 originKind;  // xyz the light (cube), w the kind: 0 none, 1 cube, 2 orthographic
  vec4 axes[18];    // face f: S, T, A at 3f, 3f + 1, 3f + 2 (orthographic: face 0, A towards the light)
  vec4 params;      // extent, nearZ, top, depthEps
  vec4 params2;     // centre (orthographic), size (texels a side), -
  vec4 toLight;     // directional: the CPU's toLight (-dirRange), exactly
  uvec4 ranges;     // first texel record, first near-light id, near-light count, -
};
layout(std140, binding = TD_BLOCK_PROOF_MAPS) uniform ProofBlock {
  ProofMap proofMaps[TD_MAX_LIGHTS];
  vec4 proofConstants;  // kQueryMargin, kDepthRel, kRelativeMargin, kShadowRayEnd
  ivec4 proofLights;    // x: lights
};

layout(location = TD_LOC_CAMERA_POS) uniform vec3 cameraPosW;
layout(location = TD_LOC_CAMERA_FORWARD) uniform vec3 cameraForward;
layout(location = TD_LOC_CAMERA_RIGHT) uniform vec3 cameraRight;
layout(location = TD_LOC_CAMERA_UP) uniform vec3 cameraUp;
layout(location = TD_LOC_ORTHOGRAPHIC) uniform int orthographic;
layout(location = TD_LOC_FRAME_SIZE) uniform ivec2 frameSize;
layout(location = TD_LOC_RAY_SCALE) uniform int rayScale;  // the ray pass reads only its grid's stand-in pixels

vec3 positionO(uint v) { return texelFetch(positionsBuf, int(v)).xyz; }
vec3 objectNormal(uint v) { return texelFetch(normalsBuf, int(v)).xyz; }
const bool kUseExact = false;  // a pixel on an exact solid is left to its rays
#include "camera_ray.glsl"
#include "shade_hit.glsl"

layout(location = 0) out TD_OUTPUT_SHADOW_PROOFS outProof;  // a proof word (bindings.glsl)

float maxAbs(vec3 v) { return max(abs(v.x), max(abs(v.y), abs(v.z))); }

int cubeFace(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
  return d.z >= 0.0 ? 4 : 5;
}

int texelIndex(int x, int y, int n) {
  const int b = TD_PROOF_BLOCK;
  return ((y / b) * (n / b) + x / b) * (b * b) + (y % b) * b + x % b;
}

uint texelWord(int record, int w) { return texelFetch(proofTexels, record * TD_PROOF_RECORD + w).x; }

#include "shadow_tests.glsl"
const int kMisses = TD_SEGMENT_MISSES, kCrosses = TD_SEGMENT_CROSSES, kUnsure = TD_SEGMENT_UNSURE;
// Triangle `id`'s test (its record: plane, edges, then magnitude, valid, blocks) against the segment.
int segmentVsTriangle(uint id, vec3 o, vec3 d, float tEnd, float margin, out bool blocks) {
  int base = 5 * int(id);
  vec4 extra = texelFetch(proofTriangles, base + 4);
  blocks = extra.z > 0.5;
  if (extra.y < 0.5) return kUnsure;
  return tdSegmentVsTriangle(texelFetch(proofTriangles, base), texelFetch(proofTriangles, base + 1),
                             texelFetch(proofTriangles, base + 2), texelFetch(proofTriangles, base + 3), o, d, tEnd,
                             margin);
}

// The CPU's offset origin (rt::offsetRayOrigin): the hit moved along the side's unit normal by its rounding
// scale, each moved coordinate one ULP further.
vec3 offsetRayOrigin(vec3 posW, vec3 n, vec3 magnitude, out float d) {
  const float kUlp = 1.0 / 8388608.0;
  float maxMag = max(magnitude.x, max(magnitude.y, magnitude.z));
  d = max(kUlp * (64.0 * dot(abs(n), magnitude) + 16.0 * maxMag), 1.17549435e-38);
  vec3 o = posW + d * n;
  for (int i = 0; i < 3; ++i) {
    // One ULP away from the surface, as nextFloatUp / nextFloatDown (finite inputs).
    if (n[i] != 0.0) {
      int bits = floatBitsToInt(o[i]);
      bool up = n[i] > 0.0;
      if (o[i] == 0.0) o[i] = up ? intBitsToFloat(1) : -intBitsToFloat(1);
      else o[i] = intBitsToFloat(bits + (((o[i] > 0.0) == up) ? 1 : -1));
    }
  }
  return o;
}

// What this pass knows of the CPU's hit for one light's ray: its own hit, the geometric normal and rounding
// scale for the offset, and how far the CPU's ray may lie from its own: eStart at the origin, eEnd at the
// far end (both rays start at their offset origins and end kShadowRayEnd of the way from their hit to the
// light, so their ends differ by the offsets' difference and 1/4096 of the hits').
struct ProofHit {
  vec3 posW, ng, magnitude;
  float eHit, dOffset;  // the hits' distance bound, the offsets' difference bound
  float nErr;           // how far the CPU's geometric normal (made in double) may point from this one's
  uint own;
};

// rt::ShadowCertainty::classify for light j's map, for every ray the CPU's may be. 0: unknown, 1: lit,
// 2: shadowed.
int prove(int j, ProofHit h) {
  int kind = int(proofMaps[j].originKind.w + 0.5);
  if (kind == 0) return 0;
  float extent = proofMaps[j].params.x;
  float size = proofMaps[j].params2.z;
  float scale = size / (2.0 * extent);
  int face = 0;
  vec2 u0, u1;
  float depth, eps, E, eEnd, slackTexels, tEnd;
  vec3 dir, o;
  if (kind == 1) {
    vec3 L = proofMaps[j].originKind.xyz;
    float nearZ = proofMaps[j].params.y;
    vec3 toL = L - h.posW;
    float dist = length(toL);
    if (!(dist > 0.0)) return 0;
    dir = toL / dist;
    float side = dot(dir, h.ng);
    // The side the CPU leaves from must be this one's.
    if (!(abs(side) > 1e-3 + h.nErr)) return 0;
    float d;
    o = offsetRayOrigin(h.posW, side >= 0.0 ? h.ng : -h.ng, h.magnitude, d);
    tEnd = dist * proofConstants.w;
    // The offsets differ by dOffset in length and by d·nErr in direction.
    E = 1.01 * (h.eHit + h.dOffset + d * h.nErr + 3e-7 * maxAbs(o));
    eEnd = 1.01 * (h.dOffset + d * h.nErr + h.eHit / 4096.0 + 8e-7 * (dist + maxAbs(L)) + 3e-7 * maxAbs(o));
    vec3 dv = o - L;
    face = cubeFace(dv);
    vec3 S = proofMaps[j].axes[3 * face].xyz, T = proofMaps[j].axes[3 * face + 1].xyz;
    vec3 A = proofMaps[j].axes[3 * face + 2].xyz;
    float a = dot(A, dv), along = dot(A, dir);
    // The CPU's points nearer the light than nearZ lie within 1.8·(nearZ + E) + d + dist/4096 + E of it:
    // inside the near-light list's 4·nearZ. Its points beyond nearZ have partners beyond reach, on the
    // path checked below.
    float reach = nearZ - E - eEnd;
    if (!(E + d + dist / 4096.0 < 0.5 * nearZ) || !(a - E > nearZ) || !(along < 0.0)) return 0;
    float tStar = min(tEnd, (reach - a) / along);
    vec3 ePt = dv + tStar * dir;
    float eA = dot(A, ePt);
    if (!(eA > 0.0)) return 0;
    u0 = (vec2(dot(S, dv), dot(T, dv)) / a + extent) * scale;
    u1 = (vec2(dot(S, ePt), dot(T, ePt)) / eA + extent) * scale;
    // A partner point lies within (1 − s)·E + s·eEnd at fraction s, at depth ≥ (1 − s)·a and ≥ reach; a
    // point moved by δ at depth z moves its projection by at most √(1 + 2·extent²)·δ/z texels of `scale`.
    slackTexels = 1.8 * scale * (E / a + eEnd / reach);
    depth = a + E;
    eps = proofConstants.y * depth + 4e-6 * (length(L) + depth);
  } else {
    // Towards a directional light both rays run along the same direction (the CPU's, exactly), so they
    // stay E apart; this one runs to 2E past the slab's top, where the CPU's is above every triangle too.
    vec3 A = proofMaps[j].axes[2].xyz;
    dir = proofMaps[j].toLight.xyz;
    float side = dot(dir, h.ng);
    if (!(abs(side) > 1e-3 + h.nErr)) return 0;
    float d;
    o = offsetRayOrigin(h.posW, side >= 0.0 ? h.ng : -h.ng, h.magnitude, d);
    float a = dot(A, o), along = dot(A, dir);
    if (!(along > 1e-3)) return 0;
    float top = proofMaps[j].params.z;
    E = 1.01 * (h.eHit + h.dOffset + d * h.nErr + 3e-7 * maxAbs(o));
    eEnd = E;
    tEnd = max(0.0, (top - a) / along) + 2.0 * E / along;
    vec3 ePt = o + max(0.0, (top - a) / along) * dir;
    vec2 centre = proofMaps[j].params2.xy;
    vec3 S = proofMaps[j].axes[0].xyz, T = proofMaps[j].axes[1].xyz;
    u0 = (vec2(dot(S, o), dot(T, o)) - centre + extent) * scale;
    u1 = (vec2(dot(S, ePt), dot(T, ePt)) - centre + extent) * scale;
    slackTexels = E * scale;
    depth = top - a + E;
    eps = proofMaps[j].params.w;
  }
  if (!(u0.x >= 0.0 && u0.y >= 0.0 && u0.x < size && u0.y < size)) return 0;
  vec2 texel = floor(u0);
  float margin = proofConstants.x - slackTexels;
  if (!(margin > 0.0)) return 0;
  vec2 lo = texel - margin, hi = texel + 1.0 + margin;
  if (!(u1.x >= lo.x && u1.y >= lo.y && u1.x <= hi.x && u1.y <= hi.y)) return 0;
  int n = int(size);
  int record = int(proofMaps[j].ranges.x) + face * n * n + texelIndex(int(texel.x), int(texel.y), n);
  float magnitude = max(maxAbs(o), tEnd);
  bool missesAll = true;
  uint nearFirst = proofMaps[j].ranges.y, nearCount = proofMaps[j].ranges.z;
  for (uint k = 0u; k < nearCount; ++k) {
    uint id = texelFetch(proofNear, int(nearFirst + k)).x;
    if (id == h.own) continue;
    bool blocks;
    float m = proofConstants.z * max(magnitude, texelFetch(proofTriangles, 5 * int(id) + 4).x) + max(E, eEnd);
    int x = segmentVsTriangle(id, o, dir, tEnd, m, blocks);
    if (x == kCrosses && blocks) return 2;
    if (x != kMisses) missesAll = false;
  }
  for (int k = 0; k < TD_PROOF_CANDIDATES; ++k) {
    uint id = texelWord(record, k);
    if (id == 0xFFFFFFFFu) break;
    if (uintBitsToFloat(texelWord(record, TD_PROOF_CANDIDATES + k)) > depth + eps) return missesAll ? 1 : 0;
    if (id == h.own) continue;
    bool blocks;
    float m = proofConstants.z * max(magnitude, texelFetch(proofTriangles, 5 * int(id) + 4).x) + max(E, eEnd);
    int x = segmentVsTriangle(id, o, dir, tEnd, m, blocks);
    if (x == kCrosses && blocks) return 2;
    if (x != kMisses) missesAll = false;
  }
  if (missesAll && uintBitsToFloat(texelWord(record, 2 * TD_PROOF_CANDIDATES)) > depth + eps) return 1;
  return 0;
}

void main() {
  ivec2 pix = ivec2(gl_FragCoord.xy);
  // A ray grid coarser than the frame (rayScale > 1): the ray pass reads each grid pixel's stand-in only
  // (rt::fullPixelOfGridPixel, rows from the top), so the others are not proved.
  ivec2 pTop = ivec2(pix.x, frameSize.y - 1 - pix.y);
  if (pTop != min((pTop / rayScale) * rayScale + rayScale / 2, frameSize - 1)) {
    outProof = 0u;
    return;
  }
  uvec2 id = texelFetch(idsTex, pix, 0).xy;
  uint proof = 0u;
  uint base = id.x != 0u && id.y != TD_EXACT_TRIANGLE ? texelFetch(proofInstances, int(id.x - 1u)).x : 0xFFFFFFFFu;
  if (base != 0xFFFFFFFFu) {
    PrimaryHit ph = primaryHit(pix, id);
    // Where the CPU's exact hit may lie: both are the camera ray's crossing of the triangle's plane, from
    // camera rays a few ULPs apart (the normalize, the jitter folded in another order) and their own
    // rounding; along the plane that grows as 1/cos of the incidence. Only a hit inside the triangle by
    // that much is proved (then neither side clamps its barycentrics).
    vec3 b = rayBarycentrics(ph.origin, ph.dir, ph.tri);
    vec3 e1 = ph.tri.p1 - ph.tri.p0, e2 = ph.tri.p2 - ph.tri.p0;
    vec3 nRaw = cross(e1, e2);
    float area2 = length(nRaw);
    float t = length(ph.posW - ph.origin);
    float cosI = area2 > 0.0 ? abs(dot(nRaw, ph.dir)) / area2 : 0.0;
    // Each vertex's rounding scale as resolveHit has it (|M|·|p| + |t|): the two sides' transforms of the
    // vertices differ by a few ULPs of it, which can be far more than the world coordinates when a
    // translation cancels large object-space ones.
    mat4 worldFromObject = instanceWorldFromObject(ph.instance);
    mat3 absLinear = mat3(abs(worldFromObject[0].xyz), abs(worldFromObject[1].xyz), abs(worldFromObject[2].xyz));
    vec3 absT = abs(worldFromObject[3].xyz);
    vec3 m0 = absLinear * abs(positionO(ph.tri.v0)) + absT, m1 = absLinear * abs(positionO(ph.tri.v1)) + absT;
    vec3 m2 = absLinear * abs(positionO(ph.tri.v2)) + absT;
    float maxMag = max(maxAbs(m0), max(maxAbs(m1), maxAbs(m2)));
    // The camera ray's origin's scale: an orthographic camera's moves over the image by up to |right| + |up|
    // (lengths there; a perspective camera's are directions, whose rounding the 2e-6·t term covers).
    float cameraMag = maxAbs(cameraPosW) + (orthographic != 0 ? maxAbs(cameraRight) + maxAbs(cameraUp) : 0.0);
    float M = max(max(maxAbs(ph.origin), t), max(max(maxAbs(ph.tri.p0), max(maxAbs(ph.tri.p1), maxAbs(ph.tri.p2))),
                                                  max(maxMag, cameraMag)));
    float eHit = (2e-6 * t + 1e-6 * M) / max(cosI, 1e-30) + 1e-6 * M;
    vec3 edgeLen = vec3(length(ph.tri.p2 - ph.tri.p1), length(ph.tri.p0 - ph.tri.p2), length(e1));
    vec3 height = area2 / max(edgeLen, vec3(1e-30));
    vec3 inside = b * height;
    // The geometric normal from float edges whose ends lie a few ULPs of M apart on the two sides: off by
    // about that over the triangle's smallest height (the CPU's is made in double from its own vertices).
    float nErr = 2e-6 * M / max(min(height.x, min(height.y, height.z)), 1e-30);
    if (area2 > 0.0 && cosI > 1e-4 + nErr && min(inside.x, min(inside.y, inside.z)) > eHit) {
      ProofHit h;
      h.posW = ph.posW;
      h.ng = nRaw / area2;
      h.eHit = eHit;
      h.nErr = nErr;
      h.own = base + id.y;
      h.magnitude = abs(b.x) * m0 + abs(b.y) * m1 + abs(b.z) * m2;
      // The CPU's barycentrics differ by at most eHit over each height; its offset by that much of the
      // magnitudes' 2^-23·(64·√3 + 16), plus its own rounding.
      float db = eHit / height.x + eHit / height.y + eHit / height.z;
      h.dOffset = 1.6e-5 * (db * maxMag + 1e-5 * maxAbs(h.magnitude));
      // The whole light mask, where the hit spawns nothing and every light is decided: the ray pass then
      // need not resolve the hit (TD_PROOF_COMPLETE). The CPU's rules per light (Whitted::shadowRayUnanswered):
      // no shadows, or a light that cannot reach the point (tdLightReaches on the model's normal): bit set,
      // no ray; else the ray's answer. Each only where it is clear of the two hits' rounding.
      uint flags = texelFetch(proofFlags, int(ph.instance)).x;
      bool complete = (flags & TD_PROOF_PLAIN) != 0u;
      vec3 toEye = -ph.dir;
      bool back = dot(h.ng, toEye) < 0.0;
      vec3 N = h.ng;
      float nSpread = nErr;  // how far the CPU's shading normal may point from N
      if ((flags & TD_PROOF_FLAT) == 0u && (ph.tri.flags & TD_MESH_HAS_NORMALS) != 0u) {
        vec3 n0 = ph.tri.normalFromObject * objectNormal(ph.tri.v0);
        vec3 n1 = ph.tri.normalFromObject * objectNormal(ph.tri.v1);
        vec3 n2 = ph.tri.normalFromObject * objectNormal(ph.tri.v2);
        vec3 n = b.x * n0 + b.y * n1 + b.z * n2;
        float len = length(n);
        // The CPU interpolates with its own barycentrics, up to db apart from these.
        float spread = max(length(n0 - n1), max(length(n1 - n2), length(n2 - n0)));
        if (len > 1e-6) {
          N = n / len;
          nSpread = 2.0 * db * spread / len + 1e-6;
        } else {
          complete = false;
        }
      }
      if (back) N = -N;
      uint lit = 0u, decided = 0u, needed = 0u, mask = 0u;
      for (int j = 0; j < proofLights.x; ++j) {
        int answer = prove(j, h);
        uint bit = 1u << uint(j);
        if (answer != 0) decided |= bit;
        if (answer == 1) lit |= bit;
        if (!complete) continue;
        GpuLight L = lights[j];
        int type = int(L.posType.w + 0.5);
        if (tdIsAreaLight(type)) {
          complete = false;
          continue;
        }
        if (!(L.radiance.w > 0.5)) {
          mask |= bit;  // casts no shadows: visible, no ray
          continue;
        }
        vec3 toLight;
        float dist;
        vec3 E = tdLightIncident(L, h.posW, toLight, dist);
        float nl = dot(N, toLight);
        // Both hits' directions to the light differ by about eHit / dist, their normals by rounding.
        bool directional = type == TD_LIGHT_DIRECTIONAL;
        float angle = directional ? 0.0 : 4.0 * h.eHit / max(dist, 1e-30);
        float nlMargin = 1e-4 + nSpread + angle, coneMargin = 1e-5 + angle;
        bool bright = L.radiance.x > 0.0 || L.radiance.y > 0.0 || L.radiance.z > 0.0;
        // E > 0 unless beyond the range or outside a spot's outer cone (tdLightIncident): clear of both edges.
        bool ranged = !directional && L.dirRange.w > 0.0;
        bool inRange = !ranged || dist < L.dirRange.w * (1.0 - 1e-5);
        bool outOfRange = ranged && dist > L.dirRange.w * (1.0 + 1e-5);
        bool inCone = true, outOfCone = false;
        if (type == TD_LIGHT_SPOT) {
          float cosAngle = dot(-toLight, vec3(L.dirRange));
          inCone = cosAngle > L.cone.y + coneMargin;
          outOfCone = cosAngle < L.cone.y - coneMargin;
        }
        bool reaches = inRange && inCone && max(E.x, max(E.y, E.z)) > 1e-30 && nl > nlMargin;
        bool cannot = !bright || outOfRange || outOfCone || nl < -nlMargin;
        if (cannot) {
          mask |= bit;  // no ray; the CPU leaves the bit set
        } else if (reaches && answer != 0) {
          needed |= bit;
          if (answer == 1) mask |= bit;
        } else {
          complete = false;
        }
      }
      proof = complete ? mask | (decided << TD_PROOF_DECIDED_SHIFT) | (needed << TD_PROOF_NEEDED_SHIFT) | TD_PROOF_COMPLETE
                       : lit | (decided << TD_PROOF_DECIDED_SHIFT);
    }
  }
  outProof = proof;
}
