// Solid (3D) procedural textures (docs/procedural.md): improved Perlin noise and the patterns built on it, the
// ONE definition compiled as GLSL (shade.frag, TD_USE_PROCEDURAL) and as C++ (core/Procedural.h, the ray pass),
// like shading.glsl, whose tdHash it uses (include it first). Every function returns its value with its
// gradient, found analytically, so bump maps bend normals by the true derivative on both sides.
#ifndef TD_PROCEDURAL_GLSL
#define TD_PROCEDURAL_GLSL

// Function linkage as in shading.glsl: C++ defines TD_FN as `inline`, GLSL as nothing.
#ifndef TD_FN
#define TD_FN
#endif

#define TD_PATTERN_NONE 0
#define TD_PATTERN_NOISE 1       // 0.5 + 0.5·noise
#define TD_PATTERN_FBM 2         // 0.5 + 0.5·fBm (gain 1/2, lacunarity 2), clamped to [0, 1]
#define TD_PATTERN_TURBULENCE 3  // Perlin's turbulence, the sum of |noise| octaves
#define TD_PATTERN_MARBLE 4      // Perlin's marble: veins, a sine of x moved by turbulence
#define TD_PATTERN_WOOD 5        // rings about the y axis moved by noise
#define TD_PATTERN_GRANITE 6     // speckles where turbulence rises over a threshold
#define TD_PATTERN_MAX_OCTAVES 8

// The gradient at lattice corner (ix, iy, iz): one of the 12 directions to the cube's edge midpoints (Perlin 2002,
// "Improving noise"), chosen by a hash of the corner instead of his permutation table (no arrays in the shared
// subset). Negative coordinates wrap through uint the same way in GLSL and C++.
TD_FN vec3 tdLatticeGradient(int ix, int iy, int iz) {
  uint h = tdHash(uint(ix) * 0x8DA6B343u ^ tdHash(uint(iy) * 0xD8163841u ^ tdHash(uint(iz) * 0xCB1AB31Fu)));
  h = h - (h / 12u) * 12u;
  float a = (h & 1u) != 0u ? -1.0f : 1.0f;
  float b = (h & 2u) != 0u ? -1.0f : 1.0f;
  uint axis = h >> 2u;
  if (axis == 0u) return vec3(a, b, 0.0f);
  if (axis == 1u) return vec3(a, 0.0f, b);
  return vec3(0.0f, a, b);
}

// A coordinate the lattice can take: beyond 2^23 a float has no fraction left (every point is a lattice point,
// where noise is 0), and int() of a larger or NaN value is undefined in both languages.
TD_FN float tdLatticeSafe(float x) { return x > -8388608.0f && x < 8388608.0f ? x : 0.0f; }

// Improved Perlin noise at p: vec4(value, ∂/∂x, ∂/∂y, ∂/∂z). The quintic fade 6t⁵ − 15t⁴ + 10t³ (Perlin 2002)
// has continuous second derivatives, so the gradient below (the fade's derivative 30t²(t − 1)² times the
// corner differences, plus the corners' own gradients blended) is continuous too. The fraction is p − floor(p)
// per axis, exact for any float: what limits far points is float input (at 1e5 a step of 1/128).
TD_FN vec4 tdNoiseGrad(vec3 p) {
  p = vec3(tdLatticeSafe(p.x), tdLatticeSafe(p.y), tdLatticeSafe(p.z));
  vec3 c = floor(p);
  vec3 f = p - c;
  int ix = int(c.x);
  int iy = int(c.y);
  int iz = int(c.z);
  vec3 g000 = tdLatticeGradient(ix, iy, iz);
  vec3 g100 = tdLatticeGradient(ix + 1, iy, iz);
  vec3 g010 = tdLatticeGradient(ix, iy + 1, iz);
  vec3 g110 = tdLatticeGradient(ix + 1, iy + 1, iz);
  vec3 g001 = tdLatticeGradient(ix, iy, iz + 1);
  vec3 g101 = tdLatticeGradient(ix + 1, iy, iz + 1);
  vec3 g011 = tdLatticeGradient(ix, iy + 1, iz + 1);
  vec3 g111 = tdLatticeGradient(ix + 1, iy + 1, iz + 1);
  float n000 = dot(g000, f);
  float n100 = dot(g100, f - vec3(1.0f, 0.0f, 0.0f));
  float n010 = dot(g010, f - vec3(0.0f, 1.0f, 0.0f));
  float n110 = dot(g110, f - vec3(1.0f, 1.0f, 0.0f));
  float n001 = dot(g001, f - vec3(0.0f, 0.0f, 1.0f));
  float n101 = dot(g101, f - vec3(1.0f, 0.0f, 1.0f));
  float n011 = dot(g011, f - vec3(0.0f, 1.0f, 1.0f));
  float n111 = dot(g111, f - vec3(1.0f, 1.0f, 1.0f));
  vec3 u = f * f * f * (f * (f * 6.0f - vec3(15.0f)) + vec3(10.0f));
  vec3 du = 30.0f * f * f * (f * (f - vec3(2.0f)) + vec3(1.0f));
  // The trilinear blend written as a polynomial in u (k0 .. k7), so its derivative reads off directly.
  float k1 = n100 - n000;
  float k2 = n010 - n000;
  float k3 = n001 - n000;
  float k4 = n000 - n100 - n010 + n110;
  float k5 = n000 - n010 - n001 + n011;
  float k6 = n000 - n100 - n001 + n101;
  float k7 = -n000 + n100 + n010 - n110 + n001 - n101 - n011 + n111;
  float value = n000 + k1 * u.x + k2 * u.y + k3 * u.z + k4 * u.x * u.y + k5 * u.y * u.z + k6 * u.z * u.x +
                k7 * u.x * u.y * u.z;
  vec3 blended = g000 + u.x * (g100 - g000) + u.y * (g010 - g000) + u.z * (g001 - g000) +
                 u.x * u.y * (g000 - g100 - g010 + g110) + u.y * u.z * (g000 - g010 - g001 + g011) +
                 u.z * u.x * (g000 - g100 - g001 + g101) +
                 u.x * u.y * u.z * (-g000 + g100 + g010 - g110 + g001 - g101 - g011 + g111);
  vec3 grad = blended + du * vec3(k1 + k4 * u.y + k6 * u.z + k7 * u.y * u.z, k2 + k5 * u.z + k4 * u.x + k7 * u.z * u.x,
                                  k3 + k6 * u.x + k5 * u.y + k7 * u.x * u.y);
  return vec4(value, grad.x, grad.y, grad.z);
}

// Octave i of fBm and turbulence is noise at 2^i·p moved by its own offset, so the octaves' lattices do not
// all meet at the origin (where every octave would be 0 at once).
TD_FN vec3 tdOctaveOffset(int i) { return float(i) * vec3(19.19f, 7.37f, 11.73f); }

// Fractional Brownian motion (Musgrave): Σ 2^-i·noise(2^i·p) over `octaves` (1..8), divided by Σ 2^-i so it stays
// about as wide as noise itself. vec4(value, gradient).
TD_FN vec4 tdFbmGrad(vec3 p, int octaves) {
  int n = clamp(octaves, 1, TD_PATTERN_MAX_OCTAVES);
  vec4 sum = vec4(0.0f);
  float amplitude = 1.0f;
  float frequency = 1.0f;
  float total = 0.0f;
  for (int i = 0; i < n; ++i) {
    vec4 o = tdNoiseGrad(p * frequency + tdOctaveOffset(i));
    sum += amplitude * vec4(o.x, frequency * o.y, frequency * o.z, frequency * o.w);
    total += amplitude;
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum / total;
}

// Perlin's turbulence (1985): Σ 2^-i·|noise(2^i·p)|, divided by Σ 2^-i: in [0, ~1], creased where an octave
// crosses zero (there the gradient is the one-sided one). vec4(value, gradient).
TD_FN vec4 tdTurbulenceGrad(vec3 p, int octaves) {
  int n = clamp(octaves, 1, TD_PATTERN_MAX_OCTAVES);
  vec4 sum = vec4(0.0f);
  float amplitude = 1.0f;
  float frequency = 1.0f;
  float total = 0.0f;
  for (int i = 0; i < n; ++i) {
    vec4 o = tdNoiseGrad(p * frequency + tdOctaveOffset(i));
    float s = o.x < 0.0f ? -1.0f : 1.0f;
    sum += (amplitude * s) * vec4(o.x, frequency * o.y, frequency * o.z, frequency * o.w);
    total += amplitude;
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum / total;
}

// v clamped to [0, 1] with its gradient (zero where it is clamped: the value is flat there).
TD_FN vec4 tdClampPattern(float v, vec3 grad) {
  if (v <= 0.0f) return vec4(0.0f);
  if (v >= 1.0f) return vec4(1.0f, 0.0f, 0.0f, 0.0f);
  return vec4(v, grad.x, grad.y, grad.z);
}

// The pattern `type` (TD_PATTERN_*) at p: vec4(v, ∂v/∂p) with v in [0, 1]. `scale` is the features per unit
// (noise at scale·p; marble's stripes and wood's rings per unit), `turbulence` how far noise moves marble's
// stripes and wood's rings (in stripes and rings), `octaves` those of fBm and turbulence.
TD_FN vec4 tdPattern(int type, vec3 p, float scale, float turbulence, int octaves) {
  // Beyond 2^23 q has no fraction left (every float there is a lattice point), and inf or NaN none at all: 0
  // instead, so wood's q.x² cannot overflow and marble's sin never sees inf; every pattern is finite everywhere.
  vec3 q = p * scale;
  q = vec3(tdLatticeSafe(q.x), tdLatticeSafe(q.y), tdLatticeSafe(q.z));
  if (type == TD_PATTERN_NOISE) {
    vec4 n = tdNoiseGrad(q);
    return tdClampPattern(0.5f + 0.5f * n.x, (0.5f * scale) * vec3(n.y, n.z, n.w));
  }
  if (type == TD_PATTERN_FBM) {
    vec4 n = tdFbmGrad(q, octaves);
    return tdClampPattern(0.5f + 0.5f * n.x, (0.5f * scale) * vec3(n.y, n.z, n.w));
  }
  if (type == TD_PATTERN_TURBULENCE) {
    vec4 t = tdTurbulenceGrad(q, octaves);
    return tdClampPattern(t.x, scale * vec3(t.y, t.z, t.w));
  }
  if (type == TD_PATTERN_MARBLE) {
    // Perlin 1985: sin(x + turbulence(x)), a vein every 2/scale along x; w = ½ + ½·sin cubed, so the second
    // colour runs in thin veins through the first.
    vec4 t = tdTurbulenceGrad(q, octaves);
    float s = q.x + turbulence * t.x;
    vec3 ds = scale * (vec3(1.0f, 0.0f, 0.0f) + turbulence * vec3(t.y, t.z, t.w));
    // sin(πs) repeats every 2 in s: s is reduced to [0, 2) first, exactly (s/2, its floor and twice that are exact
    // in float, and so is the difference), so the sine never sees a large argument. GPU sines reduce large ones
    // coarsely (NVIDIA's are off by ~|x|·2^-22: 0.01 at a point 1e4 from the origin), the C++ sin exactly.
    float angle = 3.14159265f * (s - 2.0f * floor(0.5f * s));
    float w = 0.5f + 0.5f * sin(angle);
    return tdClampPattern(w * w * w, (3.0f * w * w * 0.5f * 3.14159265f * cos(angle)) * ds);
  }
  if (type == TD_PATTERN_WOOD) {
    // Rings about the y axis, `scale` a unit, their radius moved by noise; w = ½ + ½·cos(2πs) squared, so each
    // ring is mostly the first colour with a thinner band of the second.
    float rho = sqrt(q.x * q.x + q.z * q.z);
    vec3 dRho = rho > 0.0f ? vec3(q.x / rho, 0.0f, q.z / rho) : vec3(0.0f);
    vec4 n = tdNoiseGrad(q * vec3(1.0f, 0.25f, 1.0f));  // stretched along the grain
    float s = rho + turbulence * n.x;
    vec3 ds = scale * (dRho + turbulence * vec3(n.y, 0.25f * n.z, n.w));
    float angle = 6.28318531f * (s - floor(s));  // cos(2πs) repeats every 1 in s: reduced exactly, as marble's
    float w = 0.5f + 0.5f * cos(angle);
    return tdClampPattern(w * w, (-2.0f * w * 0.5f * 6.28318531f * sin(angle)) * ds);
  }
  if (type == TD_PATTERN_GRANITE) {
    // Grains: a smoothstep of turbulence between 0.12 and 0.32 (about a third of the surface speckled).
    vec4 t = tdTurbulenceGrad(q, octaves);
    float x = (t.x - 0.12f) / 0.2f;
    if (x <= 0.0f) return vec4(0.0f);
    if (x >= 1.0f) return vec4(1.0f, 0.0f, 0.0f, 0.0f);
    return vec4(x * x * (3.0f - 2.0f * x), (6.0f * x * (1.0f - x) / 0.2f * scale) * vec3(t.y, t.z, t.w));
  }
  return vec4(0.0f);
}

// Bump mapping from a height field's world-space gradient (Blinn 1978, in Mikkelsen's surface-gradient form
// 2010): the surface moved by amplitude·h along its unit normal N tilts its normal against the gradient's part
// along the surface, N' = normalize(N − amplitude·(g − (g·N)·N)); a negative amplitude carves (the tilt reverses).
// N itself, bit for bit, when amplitude is 0, or when the result is degenerate or not finite (NaN fails both
// tests of len).
TD_FN vec3 tdBumpNormal(vec3 N, vec3 gradW, float amplitude) {
  if (amplitude == 0.0f) return N;
  vec3 n = N - amplitude * (gradW - dot(gradW, N) * N);
  float len = sqrt(dot(n, n));
  return len > 0.0f && len < 1e30f ? n / len : N;
}

#endif
