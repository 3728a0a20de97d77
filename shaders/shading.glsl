// Tandem's shading formulas: the ONE definition, compiled both as GLSL (included by the shaders) and as
// C++ (included by engine/src/core/Shading.h with glm, whose vec3 / dot / reflect / pow match GLSL).
// Keep to the common subset: no GLSL-only qualifiers except through TD_OUT / TD_CONST, no C++-only syntax.
// A parity test (tests/gl/ShadingParityGLTest) renders with the GLSL and compares with the C++ twin.

// Function linkage: C++ defines TD_FN as `inline` (several translation units include this file; without it
// every one of them defines each function and the link fails), GLSL as nothing.
#ifndef TD_FN
#define TD_FN
#endif

// ---- Packed scene records (std430 in GLSL; identical glm::vec4 arrays in C++) ----
#define TD_LIGHT_POINT 1
#define TD_LIGHT_SPOT 2
#define TD_LIGHT_DIRECTIONAL 3
#define TD_LIGHT_RECT 4
#define TD_LIGHT_DISK 5
#define TD_LIGHT_SPHERE 6

#define TD_MODEL_FLAT 0
#define TD_MODEL_GOURAUD 1
#define TD_MODEL_PHONG 2
#define TD_MODEL_TOON 3

#define TD_TONEMAP_NONE 0
#define TD_TONEMAP_REINHARD 1
#define TD_TONEMAP_ACES 2

#define TD_MAX_LIGHTS 8
#define TD_MAX_LIGHT_SAMPLES 32  // area-light samples per point per frame: one bit each in a uint
#define TD_TOON_RAMP_SIZE 256

struct GpuLight {
  vec4 posType;      // xyz position (world), w type (TD_LIGHT_*)
  vec4 dirRange;     // xyz direction the light travels (unit), w range (0 = unbounded)
  vec4 radiance;     // rgb colour × intensity, w 1 if it casts shadows
  vec4 attenCone;    // x constant, y linear, z quadratic attenuation; w unused
  vec4 cone;         // x cos(inner), y cos(outer) for spots; zw unused
  vec4 shapeU;       // area lights: xyz the rect's half-width axis or the disk's radius axis (world), w its
                     // slot among the frame's area lights (the sample-visibility layer); 0 otherwise
  vec4 shapeV;       // xyz the rect's half-height axis or the disk's second radius axis, w the sphere's radius
};

struct GpuMaterial {
  vec4 kaToon;       // rgb ka, w toon-ramp row (material index)
  vec4 kdTex;        // rgb kd, w kd texture layer (-1 none)
  vec4 ksNs;         // rgb ks, w specular exponent ns
  vec4 krKtIorModel; // x kr, y kt, z ior, w shading model (TD_MODEL_*)
  vec4 kd2Checker;   // rgb second checker colour, w checker frequency (0 = off)
  vec4 emissionFlags;// rgb emission, w unlit (1) or lit (0)
  vec4 texAlpha;     // x emissive texture layer (-1 none), y normal-map layer (-1 none), z normal scale,
                     // w alpha code (tdCoverage): 0 opaque, > 0 MASK, < 0 BLEND
  vec4 pattern;      // procedural texture (procedural.glsl): x TD_PATTERN_* (0 none), y scale, z turbulence, w octaves
  vec4 patternSpace; // x 1 in world space, 0 in object space; y bump amplitude; zw unused
};

// ---- Lights ----
// Radiance arriving at posW from light L, the unit direction towards the light and its distance
// (directional: infinite, reported as -1). Zero outside a spot cone or beyond the range.
// `type` is L's TD_LIGHT_* (tdLightIncident reads it from the record); a shader that knows it at compile
// time passes a constant, and the other types' code folds away.
TD_FN vec3 tdLightIncidentOfType(GpuLight L, int type, vec3 posW, TD_OUT(vec3) toLight, TD_OUT(float) dist) {
  if (type == TD_LIGHT_DIRECTIONAL) {
    toLight = -vec3(L.dirRange);
    dist = -1.0f;
    return vec3(L.radiance);
  }
  vec3 d = vec3(L.posType) - posW;
  float d2 = dot(d, d);
  dist = sqrt(d2);
  toLight = dist > 0.0f ? d / dist : vec3(0.0f, 1.0f, 0.0f);
  float range = L.dirRange.w;
  if (range > 0.0f && dist > range) return vec3(0.0f);
  float att = L.attenCone.x + L.attenCone.y * dist + L.attenCone.z * d2;
  float falloff = att > 0.0f ? 1.0f / att : 1.0f;
  if (type == TD_LIGHT_SPOT) {
    float cosAngle = dot(-toLight, vec3(L.dirRange));
    float cosInner = L.cone.x;
    float cosOuter = L.cone.y;
    falloff *= cosInner > cosOuter ? smoothstep(cosOuter, cosInner, cosAngle) : (cosAngle >= cosOuter ? 1.0f : 0.0f);
  }
  return vec3(L.radiance) * falloff;
}

TD_FN vec3 tdLightIncident(GpuLight L, vec3 posW, TD_OUT(vec3) toLight, TD_OUT(float) dist) {
  return tdLightIncidentOfType(L, int(L.posType.w + 0.5f), posW, toLight, dist);
}

// ---- Area lights (docs/area-lights.md) ----
TD_FN bool tdIsAreaLight(int type) { return type >= TD_LIGHT_RECT; }

// A 32-bit integer hash (Wellons' lowbias32): the same bits in GLSL and C++, so both sides draw the same
// samples from the same seed.
TD_FN uint tdHash(uint x) {
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// The seed of a point's light samples: its full-resolution pixel (primary hits; the shade pass and the ray
// pass must agree on it) and the reference's sample within the pixel (0 for the hybrid frame).
TD_FN uint tdPixelSeed(int x, int y, uint pixelSample) {
  return tdHash(uint(x) * 0x9E3779B1u ^ tdHash(uint(y) ^ tdHash(pixelSample + 0x68E31DA4u)));
}

// Point `index` of the (0, 2)-sequence in base 2 (Sobol's first two dimensions) as 32-bit fixed point: x is
// the index with its bits mirrored (van der Corput), y the second Sobol dimension, whose generator is Pascal's
// triangle mod 2. Every aligned block of 2^k points is a (0, k, 2)-net. The C++ twin (core/Sampling.h's
// sobol02) is this text: the anti-aliasing jitter, the lens points, the shutter times and the
// radiosity's shots read it there.
TD_FN uvec2 tdSobol02Bits(uint index) {
  uint x = 0u;
  uint y = 0u;
  uint vx = 0x80000000u;
  uint vy = 0x80000000u;
  // The index's set bits select the direction numbers through a mask, not a branch: over an accumulation the
  // indices run to hundreds and a CPU mispredicts a branch on their bits often (the ray pass's light sample took
  // 26 % of 64 accumulated frames' time with it, 21.6 % without; one frame's few indices it predicts), and a
  // software GL runs both sides where its lanes disagree.
  for (uint i = index; i != 0u; i >>= 1u) {
    uint take = 0u - (i & 1u);
    x ^= vx & take;
    y ^= vy & take;
    vx >>= 1u;
    vy ^= vy >> 1u;
  }
  return uvec2(x, y);
}

// The sequence's point `index` under the digital shift (XOR) by `shiftX`, `shiftY`, as 24-bit fractions in
// [0, 1): every aligned block of 2^k points stays a (0, k, 2)-net, so K samples of a frame are stratified, and
// so are the frames' samples together.
TD_FN vec2 tdSobol02(uint index, uint shiftX, uint shiftY) {
  uvec2 u = tdSobol02Bits(index);
  uint x = u.x ^ shiftX;
  uint y = u.y ^ shiftY;
  return vec2(float(x >> 8u), float(y >> 8u)) * (1.0f / 16777216.0f);
}

// Sample `index` on area light `light` for a point with `seed`: the shift is the point's own (a hash of seed
// and light), so neighbouring pixels' patterns are decorrelated (noise, not bands).
TD_FN vec2 tdLightSampleU(uint seed, int light, uint index) {
  uint sx = tdHash(seed ^ (uint(light) + 1u) * 0x2C1B3C6Du);
  return tdSobol02(index, sx, tdHash(sx ^ 0x297A2D39u));
}

// One sample of area light L (type TD_LIGHT_RECT / DISK / SPHERE) seen from posW: the unit direction and
// distance to the sampled point, and the radiance it stands for — the light's integral estimated from this
// one point (the mean of K such is the K-sample estimate). Rect and disk: a uniform point y on the surface,
// weight cosθ at y (one-sided, facing dirW), so L·A·cosθ = color·intensity·cosθ. Sphere: a uniform direction
// in the cone the sphere subtends, y where it meets the sphere, weight Ω·d²/(πr²) = 2(d/D)²/(1 + cos α)
// (D to the centre, α the cone's half-angle; no division by r, so a point-sized sphere gives weight 1).
// Either way each sample is then attenuated like a point light at y. Zero from inside a sphere (its surface
// faces away) and behind a rect or disk.
TD_FN vec3 tdAreaLightSample(GpuLight L, int type, vec3 posW, vec2 u, TD_OUT(vec3) toLight, TD_OUT(float) dist) {
  vec3 c = vec3(L.posType);
  float weight = 1.0f;
  if (type == TD_LIGHT_SPHERE) {
    float r = L.shapeV.w;
    vec3 d = c - posW;
    float D2 = dot(d, d);
    float D = sqrt(D2);
    if (!(D > r)) {
      toLight = vec3(0.0f, 1.0f, 0.0f);
      dist = 0.0f;
      return vec3(0.0f);
    }
    vec3 w = d / D;
    float s2 = (r / D) * (r / D);                   // sin² α
    float cosA = sqrt(max(1.0f - s2, 0.0f));
    float xi = u.x * (s2 / (1.0f + cosA));          // 1 − cos θ, without cancelling against 1
    float cosT = 1.0f - xi;
    float sinT = sqrt(max(xi * (2.0f - xi), 0.0f));
    float phi = 6.28318530718f * u.y;
    // An orthonormal frame around w (Duff et al. 2017, "Building an orthonormal basis, revisited").
    float sgn = w.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sgn + w.z);
    float bxy = w.x * w.y * a;
    vec3 t1 = vec3(1.0f + sgn * w.x * w.x * a, sgn * bxy, -sgn * w.x);
    vec3 t2 = vec3(bxy, sgn + w.y * w.y * a, -w.y);
    toLight = normalize(t1 * (sinT * cos(phi)) + t2 * (sinT * sin(phi)) + w * cosT);
    // The near intersection with the sphere; at the cone's rim the root is 0 (clamped: rounding).
    float h = sqrt(max(r * r - D2 * sinT * sinT, 0.0f));
    dist = max(D * cosT - h, 0.0f);
    float q = dist / D;
    weight = 2.0f * q * q / (1.0f + cosA);
  } else {
    vec3 y;
    if (type == TD_LIGHT_RECT) {
      y = c + vec3(L.shapeU) * (2.0f * u.x - 1.0f) + vec3(L.shapeV) * (2.0f * u.y - 1.0f);
    } else {
      // Shirley and Chiu's concentric map of the square onto the disk: strata stay compact.
      float sx = 2.0f * u.x - 1.0f;
      float sy = 2.0f * u.y - 1.0f;
      float rho = 0.0f;
      float theta = 0.0f;
      if (abs(sx) > abs(sy)) {
        rho = sx;
        theta = 0.785398163397f * (sy / sx);
      } else if (sy != 0.0f) {
        rho = sy;
        theta = 1.57079632679f - 0.785398163397f * (sx / sy);
      }
      y = c + vec3(L.shapeU) * (rho * cos(theta)) + vec3(L.shapeV) * (rho * sin(theta));
    }
    vec3 d = y - posW;
    float d2 = dot(d, d);
    dist = sqrt(d2);
    toLight = dist > 0.0f ? d / dist : -vec3(L.dirRange);
    weight = max(dot(-toLight, vec3(L.dirRange)), 0.0f);
  }
  float range = L.dirRange.w;
  if (range > 0.0f && dist > range) return vec3(0.0f);
  float att = L.attenCone.x + L.attenCone.y * dist + L.attenCone.z * dist * dist;
  float falloff = att > 0.0f ? 1.0f / att : 1.0f;
  return vec3(L.radiance) * (falloff * weight);
}

// Whether light arriving with radiance E from direction toLight (tdLightIncident's results) can light
// a surface with normal N: the ray pass traces no shadow ray when it cannot.
TD_FN bool tdLightReaches(vec3 E, vec3 toLight, vec3 N) {
  return dot(N, toLight) > 0.0f && (E.x > 0.0f || E.y > 0.0f || E.z > 0.0f);
}

// Whether a light can reach posW at all (tdLightReaches of tdLightIncident).
TD_FN bool tdLightCanReach(GpuLight L, vec3 posW, vec3 N) {
  vec3 toLight;
  float dist;
  vec3 E = tdLightIncident(L, posW, toLight, dist);
  return tdLightReaches(E, toLight, N);
}

// ---- Phong terms ----
TD_FN float tdSpecular(vec3 N, vec3 toLight, vec3 toEye, float ns) {
  vec3 R = reflect(-toLight, N);
  float rv = dot(R, toEye);
  // ns = 0 gives 1 wherever R·V > 0 (pow(0, 0) is undefined in GLSL).
  return rv > 0.0f ? pow(rv, ns) : 0.0f;
}

// Diffuse + specular of one light for a lit point (visibility not applied). `toonLevel` is the ramp
// value of N·L for the toon model (looked up by the caller: a texture in GLSL, a table in C++).
TD_FN vec3 tdShadeLight(vec3 kd, vec3 ks, float ns, int model, vec3 N, vec3 toEye, vec3 E, vec3 toLight,
                        float toonLevel) {
  float nl = dot(N, toLight);
  if (model == TD_MODEL_TOON) {
    // Hard bands for diffuse; the highlight is a hard spot where the Phong term passes one half.
    float spec = nl > 0.0f && tdSpecular(N, toLight, toEye, ns) > 0.5f ? 1.0f : 0.0f;
    return E * (kd * toonLevel + ks * spec);
  }
  if (nl <= 0.0f) return vec3(0.0f);
  return E * (kd * nl + ks * tdSpecular(N, toLight, toEye, ns));
}

// The diffuse colour at a point before its texture and vertex colour (the caller's: textures differ between GL
// and CPU sampling, the patterns do not): kd, or the uv checker's kd / kd2, or kd and kd2 mixed by the
// procedural texture's value `pattern` in [0, 1] at the point (procedural.glsl's tdPattern, found by the caller
// since its bump map needs the gradient too).
TD_FN vec3 tdPatternKd(GpuMaterial m, vec2 uv, float pattern) {
  float f = m.kd2Checker.w;
  if (f <= 0.0f) return m.pattern.x > 0.5f ? mix(vec3(m.kdTex), vec3(m.kd2Checker), pattern) : vec3(m.kdTex);
  float cx = floor(uv.x * f);
  float cy = floor(uv.y * f);
  float parity = cx + cy - 2.0f * floor((cx + cy) * 0.5f);
  return parity < 0.5f ? vec3(m.kdTex) : vec3(m.kd2Checker);
}

// Surface colour C: the pattern's colour times the texture × vertex colour `tint` (white when absent).
TD_FN vec3 tdSurfaceColor(GpuMaterial m, vec2 uv, float pattern, vec3 tint) {
  return tdPatternKd(m, uv, pattern) * tint;
}

// Ambient term ka·Ia, carried by the surface's pattern: the texture × vertex colour `tint` and the pattern's
// colour relative to kd (so shadowed checkerboards keep their squares, and marble its veins).
TD_FN vec3 tdAmbient(GpuMaterial m, vec3 Ia, vec2 uv, float pattern, vec3 tint) {
  vec3 kd = vec3(m.kdTex);
  vec3 c = tdPatternKd(m, uv, pattern);
  vec3 ratio = vec3(kd.x > 0.0f ? c.x / kd.x : 1.0f, kd.y > 0.0f ? c.y / kd.y : 1.0f, kd.z > 0.0f ? c.z / kd.z : 1.0f);
  return vec3(m.kaToon) * Ia * tint * ratio;
}

// ---- Radiosity (docs/radiosity.md) ----
// A triangle with radiosity is cut into n × n sub-triangles (the patches) by lines parallel to its edges.
// Grid vertex (i, j), i + j <= n, lies at barycentrics (1 − (i + j)/n, i/n, j/n); its number within the
// triangle's block counts rows j = 0..n of n + 1 − j vertices each.
TD_FN int tdGridVertex(int i, int j, int n) { return j * (n + 1) - (j * (j - 1)) / 2 + i; }

// The grid vertices of the sub-triangle holding barycentrics `b` and b's weights there: the solution
// interpolated linearly over each patch, Gouraud's way. Points a rounding error outside the triangle take
// the nearest sub-triangle's (extrapolated) values.
TD_FN void tdGridCorners(vec3 b, int n, TD_OUT(ivec3) corner, TD_OUT(vec3) weight) {
  float fn = float(n);
  float u = clamp(b.y, 0.0f, 1.0f) * fn;
  float v = clamp(b.z, 0.0f, 1.0f) * fn;
  int j = int(floor(v));
  if (j > n - 1) j = n - 1;
  int i = int(floor(u));
  if (i > n - 1 - j) i = n - 1 - j;
  float fu = u - float(i);
  float fv = v - float(j);
  if (fu + fv > 1.0f && i + j <= n - 2) {
    // The upper sub-triangle (i+1, j), (i+1, j+1), (i, j+1).
    corner = ivec3(tdGridVertex(i + 1, j, n), tdGridVertex(i + 1, j + 1, n), tdGridVertex(i, j + 1, n));
    weight = vec3(1.0f - fv, fu + fv - 1.0f, 1.0f - fu);
  } else {
    corner = ivec3(tdGridVertex(i, j, n), tdGridVertex(i + 1, j, n), tdGridVertex(i, j + 1, n));
    weight = vec3(1.0f - fu - fv, fu, fv);
  }
}

// The radiosity term that replaces the ambient one: the surface colour C times the indirect irradiance H
// (light that reached the point after at least one diffuse bounce, in the units a light's E has here, so
// a Lambertian surface reflects C·H as it reflects kd·E·cosθ).
TD_FN vec3 tdRadiosityTerm(GpuMaterial m, vec3 H, vec2 uv, float pattern, vec3 tint) {
  return tdSurfaceColor(m, uv, pattern, tint) * H;
}

// ---- glTF surface extras: alpha coverage, normal maps, transmission ----
// Coverage of a surface point from its kd texture's alpha `texA` (1 without a texture). The alpha code
// folds glTF's alphaMode, alphaCutoff and baseColorFactor.a (`opacity`) into one float (packMaterial):
//   0            OPAQUE (also MASK with cutoff 0, which keeps everything): coverage 1;
//   c > 0        MASK: coverage 1 where opacity·texA >= cutoff, i.e. texA >= c = cutoff / opacity, else 0
//                (opacity 0 is stored as c = 2: nothing passes);
//   -1 - opacity BLEND: coverage = opacity·texA, in [0, 1].
TD_FN float tdCoverage(GpuMaterial m, float texA) {
  float code = m.texAlpha.w;
  if (code > 0.0f) return texA >= code ? 1.0f : 0.0f;
  if (code < 0.0f) return clamp((-code - 1.0f) * texA, 0.0f, 1.0f);
  return 1.0f;
}

// Tangent-space normal map (glTF): the map's texel `tn` (already × 2 − 1, linear) bends the shading normal
// N in the frame (T, B, N). T is the interpolated world tangent, re-orthogonalised against N; B = N × T
// times the tangent's handedness w. Returns N unchanged when the frame is degenerate.
TD_FN vec3 tdPerturbNormal(vec3 N, vec3 tangentW, float handedness, vec3 tn, float scale) {
  vec3 t = tangentW - dot(tangentW, N) * N;
  float tLen = sqrt(dot(t, t));
  if (!(tLen > 0.0f)) return N;
  t = t / tLen;
  vec3 b = cross(N, t) * (handedness < 0.0f ? -1.0f : 1.0f);
  vec3 n = t * (tn.x * scale) + b * (tn.y * scale) + N * tn.z;
  float len = sqrt(dot(n, n));
  return len > 0.0f ? n / len : N;
}

// The Whitted sum's reflected (x) and transmitted (y) weights before coverage (docs/shading.md), at Fresnel
// reflectance f of the hit (1 under total internal reflection, where T is absent): Fresnel-weighted,
// wR = kr + kt·F and wT = kt·(1 − F); classic, wR = kr and wT = kt. The ray pass (rt::Whitted::weights, through
// core/FrameRules.h's whittedSum), the frame's plan and the shade pass's probes all weigh with this.
TD_FN vec2 tdWhittedSum(float kr, float kt, float f, bool totalInternal, bool fresnelWeighted) {
  float wR = kr;
  float wT = kt;
  if (fresnelWeighted) {
    wR = kr + (kt > 0.0f ? kt * f : 0.0f);
    wT = kt > 0.0f ? kt * (1.0f - f) : 0.0f;
  }
  if (kt <= 0.0f || totalInternal) wT = 0.0f;
  return vec2(wR, wT);
}

// Weight of the transmitted radiance T at a surface point with coverage `a` (docs/gltf.md): the covered
// part transmits wT·tint (the material's refraction, tinted by its transmission tint), the uncovered part
// 1 − a passes straight through (BLEND as thin transmission with IOR 1). wR and local shading scale by a.
TD_FN vec3 tdTransmitWeight(float a, float wT, vec3 transmissionTint) {
  return a * wT * transmissionTint + vec3(1.0f - a);
}

// ---- Fresnel (dielectric, outside IOR 1) ----
// Exact unpolarised Fresnel reflectance for a ray with cos(incidence) `cosI` measured against the
// normal on the side it arrives from, going from IOR etaI into etaT. Returns 1 on total internal reflection.
// cos²θt = 1 − eta²·sin²θi is evaluated as (1 − eta)(1 + eta) + eta²·cos²θi (tdCos2T): 1 − eta is exact in
// float for IORs within a factor 2, so near the critical angle the small result keeps its digits instead
// of cancelling against 1 (with IOR 1.0001 the direct form had no correct digit 1e-6 rad from it).
// Total internal reflection is cos²θt <= 0, decided by this one expression everywhere.
TD_FN float tdCos2T(float cosI, float eta) {
  return (1.0f - eta) * (1.0f + eta) + eta * eta * cosI * cosI;
}

TD_FN float tdFresnelExact(float cosI, float etaI, float etaT) {
  cosI = clamp(cosI, 0.0f, 1.0f);
  float eta = etaI / etaT;
  float cos2T = tdCos2T(cosI, eta);
  if (cos2T <= 0.0f) return 1.0f;
  float cosT = sqrt(cos2T);
  float rPar = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
  float rPerp = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
  return 0.5f * (rPar * rPar + rPerp * rPerp);
}

// Schlick's approximation, with the cosine on the less dense side and TIR tested first.
TD_FN float tdFresnelSchlick(float cosI, float etaI, float etaT) {
  cosI = clamp(cosI, 0.0f, 1.0f);
  float eta = etaI / etaT;
  float cos2T = tdCos2T(cosI, eta);
  if (cos2T <= 0.0f) return 1.0f;
  float c = etaI > etaT ? sqrt(cos2T) : cosI;
  float r0 = (etaI - etaT) / (etaI + etaT);
  r0 = r0 * r0;
  float k = 1.0f - c;
  return r0 + (1.0f - r0) * k * k * k * k * k;
}

// ---- Secondary directions over the facet (docs/numerics.md, "Directions over the facet") ----
// The mirror and Snell directions are taken about the shading normal N (interpolated or normal-mapped),
// but a ray leaves from the triangle's own plane (unit normal Ng on the viewer's side, dot(Ng, V) >= 0).
// Near silhouettes N·V is ≈ 0 or negative while Ng·V is not, and the direction about N can fall on the
// wrong side of the facet: a reflected ray pointing into the object (trapped inside a closed mesh until
// the depth limit), a transmitted one pointing back out. A reflected direction must leave over the facet
// (Ng·R > 0), a transmitted one must cross it (Ng·T < 0). One that does not is bent minimally: to the
// nearest direction at the margin m on the right side, i.e. its own azimuth about Ng (its tangential
// part) at elevation asin(m). Iray (Keller et al. 2017) and Blender Cycles (ensure_valid_reflection, whose
// margin this is) lift the mirror direction just above the facet the same way, by bending the normal;
// bending the direction instead leaves the Fresnel weights as N gives them. The margin is
// m = min(0.01, 0.9·|Ng·D0|), D0 the direction the flat facet itself would give: a ray is never forced
// steeper than the facet's own (so with N = Ng the rule changes nothing, at grazing view and near the
// critical angle alike) and never more than 0.01 (0.57°) off the plane; the bent direction is continuous
// with the unbent one where the rule starts to act.

// D (unit) moved to side·(Ng·D) >= m, side = +1 over the facet, -1 through it: D itself (bit for bit)
// when it is there already, else the unit direction with D's tangential part and side·Ng·result = m.
// A D along -side·Ng has no tangential part to keep and becomes side·Ng.
TD_FN vec3 tdBendOverFacet(vec3 D, vec3 Ng, float side, float m) {
  float d = side * dot(Ng, D);
  if (d >= m) return D;
  vec3 t = D - dot(Ng, D) * Ng;
  float len = sqrt(dot(t, t));
  if (!(len > 0.0f)) return side * Ng;
  return t * (sqrt(1.0f - m * m) / len) + (side * m) * Ng;
}

// The reflected direction at a point with shading normal N, facet normal Ng and unit V towards the viewer.
// Behind N (N·V <= 0) the Whitted weights already evaluate Fresnel at cosθ = 0 (clamped), and so does the
// direction: the mirror direction at cosθ = 0 is −V, which then goes over the facet by the margin.
TD_FN vec3 tdReflectOverFacet(vec3 V, vec3 N, vec3 Ng) {
  vec3 R = dot(N, V) > 0.0f ? reflect(-V, N) : -V;
  float gv = dot(Ng, V);
  return tdBendOverFacet(R, Ng, 1.0f, 0.9f * gv < 0.01f ? 0.9f * gv : 0.01f);
}

// The transmitted direction T (Snell about N, IOR ratio eta = etaI / etaT) made to cross the facet. The
// flat facet's own refracted ray leaves at cos²θt = tdCos2T(Ng·V, eta) below it; where the facet itself
// would reflect totally the margin is 0.01.
TD_FN vec3 tdRefractOverFacet(vec3 T, vec3 V, vec3 Ng, float eta) {
  float c2 = tdCos2T(clamp(dot(Ng, V), 0.0f, 1.0f), eta);
  float m = 0.01f;
  if (c2 > 0.0f && 0.9f * sqrt(c2) < m) m = 0.9f * sqrt(c2);
  return tdBendOverFacet(T, Ng, -1.0f, m);
}

// What a glossy material's filtered light may come from, for the spatiotemporal filter's test of what moved
// (the shade pass writes it into the filter's guide, denoise.frag's mayHaveChanged reads tdLobeSpread of it):
// 0, nothing beyond the area lights (not glossy, or neither reflecting nor transmitting what is traced: a
// highlight alone); -1, a transmitting lobe or a BLEND surface's uncovered part (coverage < 1), which may see
// anything behind the surface (a ball's refraction turns the view over); else a reflection lobe, its
// roughness (at least 1e-3: a half float keeps it, a narrower lobe's cone is tdLobeSpread's floor anyway).
TD_FN float tdLobeOf(float roughness, float kr, float kt, float coverage) {
  return !(roughness > 0.0f)           ? 0.0f
         : kt > 0.0f || coverage < 1.0f ? -1.0f
         : kr > 0.0f                    ? max(roughness, 1e-3f)
                                        : 0.0f;
}
// A lobe (tdLobeOf) as the cone the filter tests: for a reflection lobe, the tangent of the half-angle of the
// cone about the mirror direction that holds 99 % of its samples (the Phong lobe cos^e θ of docs/glossy.md,
// sampled as cos θ = u^(1/(e+1)): a fraction c^(e+1) of them falls outside cos θ = c); 0 and -1 as they are.
// The C++ twin is tested against the lobe's sampler.
TD_FN float tdLobeSpread(float lobe) {
  if (!(lobe > 0.0f)) return lobe;
  float alpha = lobe * lobe;
  float e = max(2.0f / (alpha * alpha) - 2.0f, 0.0f);
  // 1 - cos θ at 99 %: -expm1(ln(0.01) / (e + 1)), its series where the lobe is narrow (cos θ rounds to 1)
  float x = -4.6051702f / (e + 1.0f);
  float oneMinusCos = min(x > -1e-3f ? -x * (1.0f + 0.5f * x) : 1.0f - exp(x), 0.99f);
  // tan θ from 1 - cos θ (sin² = (1 - cos)(1 + cos): no cancellation for the narrow lobes); at least 1e-4, a
  // lobe narrower than that still reflecting along its ray
  return max(sqrt(oneMinusCos * (2.0f - oneMinusCos)) / (1.0f - oneMinusCos), 1e-4f);
}

// ---- Output ----
TD_FN vec3 tdToneMap(vec3 c, int op) {
  // Bounded first: beyond 65504 (half-float max) every operator is at 1 anyway, and the curves' c² and
  // c/(1 + c) would make inf/inf = NaN from an overflowed (or infinite) radiance.
  c = min(max(c, vec3(0.0f)), vec3(65504.0f));
  if (op == TD_TONEMAP_REINHARD) return c / (vec3(1.0f) + c);
  if (op == TD_TONEMAP_ACES) {
    // Narkowicz 2015 fit of the ACES filmic curve.
    vec3 num = c * (2.51f * c + vec3(0.03f));
    vec3 den = c * (2.43f * c + vec3(0.59f)) + vec3(0.14f);
    return clamp(num / den, vec3(0.0f), vec3(1.0f));
  }
  return clamp(c, vec3(0.0f), vec3(1.0f));
}

TD_FN float tdSrgbEncode1(float x) {
  return x <= 0.0031308f ? 12.92f * x : 1.055f * pow(x, 1.0f / 2.4f) - 0.055f;
}

TD_FN vec3 tdSrgbEncode(vec3 c) {
  return vec3(tdSrgbEncode1(c.x), tdSrgbEncode1(c.y), tdSrgbEncode1(c.z));
}

// Linear radiance to the display value the RGBA8 target stores: exposure, tone map, sRGB encode. Debug
// views that are already display values pass through (clamped). The output pass and the fused shade pass
// both write this.
TD_FN vec3 tdDisplay(vec3 c, float exposure, int toneMap, bool passThrough) {
  return passThrough ? clamp(c, vec3(0.0f), vec3(1.0f)) : tdSrgbEncode(tdToneMap(exposure * c, toneMap));
}

TD_FN float tdSrgbDecode1(float x) {
  return x <= 0.04045f ? x / 12.92f : pow((x + 0.055f) / 1.055f, 2.4f);
}

// ---- The environment (docs/environment.md): what escaped rays see, and the ambient light it sheds ----
#define TD_ENV_BACKGROUND 0  // the scene's background colour in every direction; no light
#define TD_ENV_SKY 1         // tdSkyRadiance's gradient
#define TD_ENV_MAP 2         // an equirectangular image, looked up at tdEquirectUv

// A world direction in the environment's own frame: the environment turned about +Y by the angle whose
// cosine and sine are `turn`, so the direction is turned back by it.
TD_FN vec3 tdEnvironmentFrame(vec3 dirW, vec2 turn) {
  return vec3(turn.x * dirW.x - turn.y * dirW.z, dirW.y, turn.y * dirW.x + turn.x * dirW.z);
}

// The sky gradient along unit direction d: the horizon's colour at the horizon, rising (as the square root of
// the height, so the bright band stays narrow) to the zenith's straight up, and falling to the ground's within
// a quarter of the way down (a ground plane a little below the eye, not a mirrored sky).
TD_FN vec3 tdSkyRadiance(vec3 d, vec3 zenith, vec3 horizon, vec3 ground) {
  float y = clamp(d.y, -1.0f, 1.0f);
  return y >= 0.0f ? mix(horizon, zenith, sqrt(y)) : mix(horizon, ground, sqrt(min(-4.0f * y, 1.0f)));
}

// What the frame may hold of an environment's radiance: half precision's largest value (the probes, the filter's
// targets), so an unclipped sun in an image stays a bright finite colour where it is stored.
TD_FN vec3 tdEnvironmentClamp(vec3 l) { return min(l, vec3(65504.0f)); }

// The texture coordinates of unit direction d on an equirectangular image (EnvironmentMap): u turns about +Y
// (0.5 along −Z, 0.75 along +X), v runs from 0 straight up to 1 straight down (t = v: the top row first).
TD_FN vec2 tdEquirectUv(vec3 d) {
  return vec2(atan(d.x, -d.z) * 0.15915494f + 0.5f, acos(clamp(d.y, -1.0f, 1.0f)) * 0.31830989f);
}

// The real spherical harmonics of bands 0-2 at unit n (the order the nine coefficients are kept in).
TD_FN float tdShBasis(int i, vec3 n) {
  if (i == 0) return 0.28209479f;
  if (i == 1) return 0.48860251f * n.y;
  if (i == 2) return 0.48860251f * n.z;
  if (i == 3) return 0.48860251f * n.x;
  if (i == 4) return 1.09254843f * n.x * n.y;
  if (i == 5) return 1.09254843f * n.y * n.z;
  if (i == 6) return 0.31539157f * (3.0f * n.z * n.z - 1.0f);
  if (i == 7) return 1.09254843f * n.x * n.z;
  return 0.54627422f * (n.x * n.x - n.y * n.y);
}

// The ambient light at a surface facing unit n (in the environment's frame): the environment's irradiance
// over π from its nine coefficients, each already times its band's cosine-lobe factor over π (1, 2/3, 1/4;
// Ramamoorthi and Hanrahan 2001). Never negative (a truncated series can ring below zero).
TD_FN vec3 tdShAmbient(vec3 n, vec3 sh[9]) {
  vec3 e = vec3(0.0f);
  for (int i = 0; i < 9; ++i) e += sh[i] * tdShBasis(i, n);
  return max(e, vec3(0.0f));
}
