// The shade pass (shade.frag): local light: the ambient or radiosity term and each direct light, toon ramps.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
// ---- the toon ramp: the same texel as shading::toonRampIndex picks in C++ ----
int tdToonRampIndex(float nl) {
  float t = clamp(nl * 0.5 + 0.5, 0.0, 1.0);
  return min(int(t * float(TD_TOON_RAMP_SIZE)), TD_TOON_RAMP_SIZE - 1);
}

float toonLevel(GpuMaterial m, float nl) {
  return texelFetch(toonRamps, ivec2(tdToonRampIndex(nl), int(m.kaToon.w + 0.5)), 0).r;
}

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

// Area light j's term at p without its shadows: the mean over `samples` samples of the light from sequence
// index `base` on, each counted where its bit in `bits` is set.
vec3 areaLightSum(int j, LightingPoint p, Triangle tri, GpuMaterial m, int samples, uint base, uint bits) {
  GpuLight L = lights[j];
  int type = lightType(j);
  vec3 toLight;
  float dist;
  uint seed = tdPixelSeed(p.pTop.x, p.pTop.y, 0u);
  vec3 sum = vec3(0.0);
  for (int k = 0; k < samples; ++k) {
    if (((bits >> uint(k)) & 1u) == 0u) continue;
    vec2 u = tdLightSampleU(seed, j, base + uint(k));
    if (kUseGouraud && p.model == TD_MODEL_GOURAUD) {
      vec3 E0 = tdAreaLightSample(L, type, tri.p0, u, toLight, dist);
      sum += p.b.x * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N0, normalize(p.origin - tri.p0), E0, toLight, 0.0);
      vec3 E1 = tdAreaLightSample(L, type, tri.p1, u, toLight, dist);
      sum += p.b.y * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N1, normalize(p.origin - tri.p1), E1, toLight, 0.0);
      vec3 E2 = tdAreaLightSample(L, type, tri.p2, u, toLight, dist);
      sum += p.b.z * tdShadeLight(p.C, p.ks, p.ns, p.model, p.N2, normalize(p.origin - tri.p2), E2, toLight, 0.0);
    } else {
      vec3 E = tdAreaLightSample(L, type, p.posW, u, toLight, dist);
      float level = kUseToon && p.model == TD_MODEL_TOON ? toonLevel(m, dot(p.Ns, toLight)) : 0.0;
      sum += tdShadeLight(p.C, p.ks, p.ns, p.model, p.Ns, p.V, E, toLight, level);
    }
  }
  return sum * (1.0 / float(samples));
}

// Direct light j's term at p, visibility included: the rays' or the shadow mask's (gathered in `rays`), or
// the shadow maps'.
vec3 directLight(int j, LightingPoint p, Triangle tri, GpuMaterial m, RaySample rays) {
  GpuLight L = lights[j];
  int type = lightType(j);
  // The rays' light mask, or the raster shadows' grid (TD_SHADOW_MASK), gathered above.
  bool rayShadowed = ((rayInputs & TD_RAY_LIGHT_MASK) != 0 || kShadowMask) && L.radiance.w > 0.5;
  float vis = rayShadowed ? rays.vis[j] : 1.0;
  if (vis <= 0.0) return vec3(0.0);
  vec3 Lj;
  vec3 toLight;
  float dist;
  if (kUseAreaLights && lightIsArea(j)) {
    // The mean over the frame's samples (rt::shadeLocal's twin): with full-resolution rays each sample
    // counts where its shadow ray got through, so the pixel is exactly the ray pass's estimate; with a
    // coarser ray grid, all samples count, scaled by the visible fraction around the pixel.
    uint bits = 0xFFFFFFFFu;
    if (!kRaysScaled && rayShadowed) {
      bits = rays.area[j];
      vis = 1.0;
    }
    Lj = areaLightSum(j, p, tri, m, lightSamples, sampleBase, bits);
  } else if (kUseGouraud && p.model == TD_MODEL_GOURAUD) {
    vec3 E0 = tdLightIncidentOfType(L, type, tri.p0, toLight, dist);
    vec3 L0 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N0, normalize(p.origin - tri.p0), E0, toLight, 0.0);
    vec3 E1 = tdLightIncidentOfType(L, type, tri.p1, toLight, dist);
    vec3 L1 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N1, normalize(p.origin - tri.p1), E1, toLight, 0.0);
    vec3 E2 = tdLightIncidentOfType(L, type, tri.p2, toLight, dist);
    vec3 L2 = tdShadeLight(p.C, p.ks, p.ns, p.model, p.N2, normalize(p.origin - tri.p2), E2, toLight, 0.0);
    Lj = p.b.x * L0 + p.b.y * L1 + p.b.z * L2;
  } else {
    vec3 E = tdLightIncidentOfType(L, type, p.posW, toLight, dist);
    float level = kUseToon && p.model == TD_MODEL_TOON ? toonLevel(m, dot(p.Ns, toLight)) : 0.0;
    Lj = tdShadeLight(p.C, p.ks, p.ns, p.model, p.Ns, p.V, E, toLight, level);
  }
  if (kShadowMaps) {
    // A light that adds nothing here needs no map lookup (a GPU skips it where a whole warp agrees; llvmpipe
    // runs both sides); skipping it is exact, since vis · 0 would add nothing either.
    if (L.radiance.w > 0.5 && (Lj.x != 0.0 || Lj.y != 0.0 || Lj.z != 0.0)) vis = rasterShadow(j, p.posW, p.Ng, p.pTop);
    if (vis <= 0.0) return vec3(0.0);
  }
  return vis * Lj;
}

// The area lights' share of the last localLight (with the spatiotemporal filter's guides: what the frame
// samples, which the filter smooths; the rest is exact for the pixel's hit and goes past it).
vec3 areaLightShare = vec3(0.0);
// With the filter's guides, on a surface without a glossy lobe: the area lights' light unshadowed (the filter
// smooths areaLightShare / areaLightUnshadowed, the visible fraction, and multiplies it back), else 0.
vec3 areaLightUnshadowed = vec3(0.0);
bool areaLightsAsVisibility = false;
float surfaceRoughness = 0.0;  // with the filter's guides: the last localLight's material's (0: not glossy)

#if TD_DENOISE_GUIDES
// The filter's form of area light j's term (docs/denoise.md): the light unshadowed, from kUnshadowedSamples
// samples of it (shading only: no rays), times the fraction of the frame's samples that reached it (the rays',
// the shadow mask's or the shadow maps', as directLight reads them). The filter smooths only the visible
// fraction; the unshadowed light, a highlight that moves with the view included, is this frame's and is never
// reprojected. directLight's estimate on a coarser ray grid is this product already; with full-resolution
// rays it is the ratio estimator's (Heitz et al. 2018) form of the per-sample sum.
const int kUnshadowedSamples = 4;
vec3 areaLightAsVisibility(int j, LightingPoint p, Triangle tri, GpuMaterial m, RaySample rays, out vec3 unshadowed) {
  GpuLight L = lights[j];
  unshadowed = areaLightSum(j, p, tri, m, kUnshadowedSamples, sampleBase * uint(kUnshadowedSamples), 0xFFFFFFFFu);
  bool rayShadowed = ((rayInputs & TD_RAY_LIGHT_MASK) != 0 || kShadowMask) && L.radiance.w > 0.5;
  float vis = rayShadowed ? rays.vis[j] : 1.0;
  if (kShadowMaps && L.radiance.w > 0.5) vis = rasterShadow(j, p.posW, p.Ng, p.pTop);
  return vis > 0.0 ? vis * unshadowed : vec3(0.0);  // (as directLight: no 0 · inf where the light overflows)
}
#else
vec3 areaLightAsVisibility(int j, LightingPoint p, Triangle tri, GpuMaterial m, RaySample rays, out vec3 unshadowed) {
  unshadowed = vec3(0.0);
  return vec3(0.0);
}
#endif

// The surface's own light (docs/shading.md): emission, the ambient term or the radiosity solution, and every
// direct light with its visibility.
vec3 localLight(Surface s, RaySample rays, uvec2 id, ivec2 pTop) {
  areaLightShare = vec3(0.0);
  areaLightUnshadowed = vec3(0.0);
  // (a glossy lobe's samples are filtered with the area lights' light, both divided by the surface colour)
  surfaceRoughness = kDenoiseGuides ? materialRoughness(s.hit.tri.material) : 0.0;
  areaLightsAsVisibility = kDenoiseGuides && !(surfaceRoughness > 0.0);
  GpuMaterial m = s.m;
  Triangle tri = s.hit.tri;
  vec3 b = s.hit.b, posW = s.hit.posW, origin = s.hit.origin;
  uint instance = s.hit.instance;
  vec3 V = s.V, N = s.N, Ng = s.Ng;
  float side = s.side;
  bool hasNormals = s.hasNormals;
  vec2 uv = s.uv;
  vec3 tint = s.tint, emission = s.emission;
  float pattern = s.pattern;
  vec3 C = tdSurfaceColor(m, uv, pattern, tint);
  int model = int(m.krKtIorModel.w + 0.5);
  vec3 local;
  if (m.emissionFlags.w > 0.5) {
    local = C + emission;
  } else {
    // Diffuse interreflection: the radiosity solution where it covers the surface, else the ambient term (the
    // environment's light at the normal the lights see: a flat face's own).
    vec3 H;
    local = emission + (kUseRadiosity && radiosityAt(instance, id.y, b, side < 0.0, H)
                            ? tdRadiosityTerm(m, H, uv, pattern, tint)
                            : tdAmbient(m, kUseEnvAmbient ? ambientIa + environmentAmbient(model == TD_MODEL_FLAT ? Ng : N)
                                                          : ambientIa,
                                        uv, pattern, tint));
    vec3 ks = vec3(m.ksNs);
    float ns = m.ksNs.w;
    vec3 Ns = model == TD_MODEL_FLAT ? Ng : N;
    vec3 N0 = Ng, N1 = Ng, N2 = Ng;
    if (kUseGouraud && model == TD_MODEL_GOURAUD && hasNormals) {
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
#define TD_ADD_LIGHT(J)                                                        \
  if (J < TD_LIGHT_COUNT) {                                                    \
    vec3 lightJ, unshadowedJ;                                                  \
    if (kUseAreaLights && kDenoiseGuides && lightIsArea(J)) {                 \
      lightJ = areaLightAsVisibility(J, lp, tri, m, rays, unshadowedJ);        \
      areaLightUnshadowed += unshadowedJ;                                      \
    } else {                                                                   \
      lightJ = directLight(J, lp, tri, m, rays);                               \
    }                                                                          \
    local += lightJ;                                                           \
    if (kDenoiseGuides && lightIsArea(J)) areaLightShare += lightJ;            \
  }
    TD_ADD_LIGHT(0) TD_ADD_LIGHT(1) TD_ADD_LIGHT(2) TD_ADD_LIGHT(3)
    TD_ADD_LIGHT(4) TD_ADD_LIGHT(5) TD_ADD_LIGHT(6) TD_ADD_LIGHT(7)
#undef TD_ADD_LIGHT
  }
  return local;
}
