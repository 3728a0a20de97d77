// The shade pass (shade.frag): raster shadows, hard and soft, from the shadow maps.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
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

// A soft-shadow tap: the cube-map direction `radius` along tap i of `count` in the plane (u, v) around rel,
// and in `ref` the depth it is compared with, the receiver's tangent plane (Ng, planeDist) where that
// direction meets it (rel's own depth when it runs along the plane).
vec3 penumbraTap(int i, int count, vec2 turn, float radius, vec3 rel, vec3 u, vec3 v, vec3 Ng, float planeDist,
                 float n, float f, out float ref) {
  vec2 o = vogelTap(i, count, turn) * radius;
  vec3 dir = rel + u * o.x + v * o.y;
  float along = dot(Ng, dir);
  ref = along * planeDist > 0.0 ? cubeDepth(dir * (planeDist / along), n, f) : cubeDepth(rel, n, f);
  return dir;
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
    float ref;
    vec3 dir = penumbraTap(i, kSearch, turn, search, rel, u, v, Ng, planeDist, n, f, ref);
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
    float ref;
    vec3 dir = penumbraTap(i, kFilter, turn, width, rel, u, v, Ng, planeDist, n, f, ref);
    lit += texture(shadowCubes, vec4(dir, layer), ref);
  }
  return lit / float(kFilter);
}

// The extent soft shadows take an area light's size as: a sphere's or disk's radius, half a rect's mean side.
float areaLightSize(GpuLight L, int type) {
  return type == TD_LIGHT_SPHERE ? L.shapeV.w : 0.5 * (length(vec3(L.shapeU)) + length(vec3(L.shapeV)));
}

// Light j's visibility from its shadow map: soft for an area light, else shadowVisibility's.
float rasterShadow(int j, vec3 posW, vec3 Ng, ivec2 pTop) {
  if (kUseAreaLights && kSoftShadows && lightIsArea(j)) {
    int type = lightType(j);
    uint h = tdHash(tdPixelSeed(pTop.x, pTop.y, 0u) ^ tdHash(sampleBase + uint(j)));
    float angle = float(h >> 8u) * (6.28318530718 / 16777216.0);
    return softShadowVisibility(j, posW, Ng, areaLightSize(lights[j], type), vec2(cos(angle), sin(angle)));
  }
  return shadowVisibility(j, posW, Ng);
}
