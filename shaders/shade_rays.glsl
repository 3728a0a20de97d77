// The shade pass (shade.frag): the ray pass's results (and the raster shadow mask) gathered at a pixel.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
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
      if (kUseAreaLights && lightIsArea(j)) {
        uint bits = texelFetch(areaSamplesTex, ivec3(g, int(lights[j].shapeU.w + 0.5)), 0).x;
        acc.area[j] = bits;
        acc.vis[j] += w * float(bitCount(bits & (lightSamples >= 32 ? 0xFFFFFFFFu : (1u << uint(lightSamples)) - 1u))) /
                      float(lightSamples);
        continue;
      }
      acc.vis[j] += ((mask >> uint(j)) & 1u) != 0u ? w : 0.0;
    }
  }
  if (kShadowMask) {
    vec4 lo = texelFetch(shadowMaskTex, ivec3(g, 0), 0);
    vec4 hi = TD_LIGHT_COUNT > 4 ? texelFetch(shadowMaskTex, ivec3(g, 1), 0) : vec4(1.0);
    // (j < 4 ? lo : hi)[j & 3], not j < 4 ? lo[j] : hi[j - 4]: once the loop unrolls, the untaken arm's
    // hi[-4] is a constant index out of bounds, which NVIDIA's compiler rejects (the program fails to link).
    for (int j = 0; j < TD_LIGHT_COUNT; ++j) acc.vis[j] += w * (j < 4 ? lo : hi)[j & 3];
  }
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
  if (rayInputs == 0 && !kShadowMask) return acc;
  if (!kRaysScaled) {
    // Full-resolution rays: grid pixel = this pixel, which saw this instance by definition.
    accumulate(acc, pTop, 1.0);
    return acc;
  }
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
