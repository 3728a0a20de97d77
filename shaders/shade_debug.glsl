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

// ---- the motion view (docs/motion.md) ----
// Window coordinates (pixels, GL rows) and depth where a camera at camPos with `clipFromViewRotation` sees
// the render-space point p: the visibility pass's projection, camera-relative.
vec3 projectPixel(mat4 clipFromViewRot, vec3 camPos, vec3 p) {
  vec4 clip = clipFromViewRot * vec4(p - camPos, 1.0);
  vec3 ndc = clip.xyz / clip.w;
  return vec3((ndc.xy * 0.5 + 0.5) * vec2(frameSize), ndc.z);
}

// Where instance id.x - 1 had the render-space point posR in the last frame (render space).
vec3 previousPoint(uvec2 id, vec3 posR) {
  uint i = id.x - 1u;
  mat4 previousFromCurrent = mat4(texelFetch(motionInstancesBuf, int(4u * i)), texelFetch(motionInstancesBuf, int(4u * i + 1u)),
                                  texelFetch(motionInstancesBuf, int(4u * i + 2u)), texelFetch(motionInstancesBuf, int(4u * i + 3u)));
  return (previousFromCurrent * vec4(posR, 1.0)).xyz;
}

// Where the point lay in the last frame (`pointR`, render space), where that frame saw it (`window`:
// projectPixel's), and whether that was within its view (in front of its camera, inside its frame): the motion
// view and the filter's motion (denoiseMotion) both from here.
struct PointBefore {
  vec3 pointR;
  vec3 window;
  bool inView;
};
PointBefore pointBefore(uvec2 id, vec3 posR) {
  PointBefore b;
  b.pointR = previousPoint(id, posR);
  b.window = projectPixel(previousClipFromViewRotation, previousCameraPos, b.pointR);
  b.inView = b.window.z > 0.0 && all(greaterThanEqual(b.window.xy, vec2(0.0))) &&
             all(lessThan(b.window.xy, vec2(frameSize)));
  return b;
}

// The pixel's motion since the last frame, the point it shows moved back by its instance's previous-from-
// current transform (identity for what did not move): red and green 0.5 + motion / 64 pixels (this frame's
// position less the last's, unjittered), blue 1 where the last frame did not see this point (off screen,
// another instance there, or the same instance at another depth: disoccluded) or no last frame is known.
vec3 motionView(uvec2 id, vec3 posR) {
  vec3 now = projectPixel(clipFromViewRotation, cameraPosW, posR);
  if (motionHistory == 0) return vec3(0.5, 0.5, 1.0);
  PointBefore then = pointBefore(id, posR);
  vec3 before = then.window;
  vec2 motion = now.xy - before.xy;
  ivec2 at = ivec2(floor(before.xy));
  bool seen = then.inView;
  if (seen) {
    seen = texelFetch(previousIdsTex, at, 0).x == id.x;
    // Reversed-Z depth is 1/z-like: a relative tolerance for the surface's slope across the texel.
    float depthThen = texelFetch(previousDepthTex, at, 0).r;
    seen = seen && abs(depthThen - before.z) <= 0.02 * before.z;
  }
  return vec3(0.5 + motion / 64.0, seen ? 0.0 : 1.0);
}

// ---- the spatiotemporal filter's guides (docs/denoise.md; TD_DENOISE_GUIDES) ----
// Motion as the motion view measures it (now − before, unjittered, GL rows), the point's view depth in the
// last frame, and whether it lay in that frame (w). The filter's reprojection checks the last frame's guide
// there (the last frame's ids and depth are the filter's own: its previous guide), and its temporal stage
// whether an instance that moved may have changed the point's light (denoise.frag's mayHaveChanged).
vec4 denoiseMotion(uvec2 id, vec3 posR) {
  if (motionHistory == 0) return vec4(0.0);
  // Where the point is now, unjittered: where this pixel's sample lies, since the point is on its ray (the
  // jitter shifts every pixel's ray by the same offset in the image plane). A projection less a pixel.
  vec2 now = gl_FragCoord.xy + sampleOffset;
  PointBefore then = pointBefore(id, posR);
  // The point's view depth then, as the last frame's guide holds it.
  float depthThen = dot(then.pointR - previousCameraPos, previousCameraForward);
  return vec4(now - then.window.xy, depthThen, then.inView ? 1.0 : 0.0);
}
