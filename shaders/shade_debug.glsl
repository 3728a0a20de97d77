// The shade pass (shade.frag): the debug views and toon outlines.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
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
  if (kUseExact && id.y == TD_EXACT_TRIANGLE) return texelFetch(exactHitsTex, p, 0).xyz;
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

// The id views (depth, instance, primitive), which need no surface: true, with `shown`, in one of them.
bool idView(ivec2 pix, uvec2 id, out vec3 shown) {
  shown = vec3(0.0);
  // Reversed-Z depth crowds towards 0 with distance; the fourth root spreads it over the grey ramp.
  if (debugView == TD_VIEW_DEPTH) shown = vec3(pow(texelFetch(depthTex, pix, 0).r, 0.25));
  else if (debugView == TD_VIEW_INSTANCE) shown = hashColor(id.x);
  else if (debugView == TD_VIEW_PRIMITIVE) shown = hashColor(id.x * 2654435761u + id.y);
  else return false;
  return true;
}

// The ray views (light mask, reflection, transmission) of the gathered rays: true, with `shown`, in one of
// them.
bool rayView(Surface s, ivec2 pTop, RaySample rays, out vec3 shown) {
  shown = vec3(0.0);
  if (debugView == TD_VIEW_LIGHT_MASK) {
    // Raster shadows stand where the ray pass's light mask would (the two are never both on). The final
    // view looks a map up only where its light adds something (directLight), as the ray pass traces a
    // shadow ray only where the light can reach.
    if (kShadowMaps)
      for (int j = 0; j < TD_LIGHT_COUNT; ++j)
        rays.vis[j] = lights[j].radiance.w > 0.5 ? rasterShadow(j, s.hit.posW, s.Ng, pTop) : 1.0;
    float visible = 1.0;
    if (((rayInputs & TD_RAY_LIGHT_MASK) != 0 || kShadowMaps || kShadowMask) && TD_LIGHT_COUNT > 0) {
      visible = 0.0;
      for (int j = 0; j < TD_LIGHT_COUNT; ++j) visible += rays.vis[j];
      visible /= float(TD_LIGHT_COUNT);
    }
    shown = vec3(visible);
    return true;
  }
  if (debugView == TD_VIEW_REFLECTION || debugView == TD_VIEW_TRANSMISSION) {
    shown = debugView == TD_VIEW_REFLECTION ? rays.reflected : rays.transmitted;
    return true;
  }
  return false;
}
