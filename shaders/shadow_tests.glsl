// The hybrid shadows' exact test of a shadow ray against one triangle (docs/shadows.md, "Why a decided ray
// equals the traced one", 3): the ONE definition, compiled as GLSL by the GL's proof pass (shadow_proof.frag)
// and as C++ by the CPU's maps (rt/ShadowCertainty.cpp, with glm and TD_FN = inline), like shading.glsl.
#ifndef TD_SHADOW_TESTS_GLSL
#define TD_SHADOW_TESTS_GLSL
#ifndef TD_FN
#define TD_FN
#endif

#define TD_SEGMENT_MISSES 0
#define TD_SEGMENT_CROSSES 1
#define TD_SEGMENT_UNSURE 2

// Whether the segment o + t·d, t in [0, tEnd] (tEnd may be +inf), certainly misses the triangle (its plane
// n·x = plane.w with n unit, and its edges: inward unit normals and offsets), certainly crosses its interior,
// or neither, with `margin` (a distance) to spare. Float arithmetic: its rounding (a few ULPs of the
// magnitudes involved) is a hundredth of the margins the callers pass.
TD_FN int tdSegmentVsTriangle(vec4 plane, vec4 edge0, vec4 edge1, vec4 edge2, vec3 o, vec3 d, float tEnd, float margin) {
  vec3 n = vec3(plane);
  // Signed distance of the segment's points from the plane: s(t) = s0 + t·sd, affine, so a segment whose two
  // ends lie on one side beyond the margin lies there whole (the common case: no division).
  float s0 = dot(n, o) - plane.w;
  float sd = dot(n, d);
  bool endless = isinf(tEnd);
  float sEnd = endless ? 0.0f : s0 + tEnd * sd;
  // The far end's side: a ray without end ends where its direction goes (on the plane's side it starts on
  // when parallel to it).
  bool endAbove = endless ? (sd > 0.0f || (sd == 0.0f && s0 > margin)) : sEnd > margin;
  bool endBelow = endless ? (sd < 0.0f || (sd == 0.0f && s0 < -margin)) : sEnd < -margin;
  if ((s0 > margin && endAbove) || (s0 < -margin && endBelow)) return TD_SEGMENT_MISSES;
  // The part of the segment within `margin` of the plane, [t0, t1]: outside it the segment cannot meet the
  // triangle, which lies in the plane.
  float t0 = 0.0f;
  float t1 = tEnd;
  if (sd != 0.0f) {
    float ta = (-margin - s0) / sd;
    float tb = (margin - s0) / sd;
    t0 = max(0.0f, min(ta, tb));
    t1 = min(tEnd, max(ta, tb));
    if (t0 > t1) return TD_SEGMENT_MISSES;  // never within margin of the plane
  }
  if (isinf(t1)) return TD_SEGMENT_UNSURE;
  vec3 q0 = o + t0 * d;
  vec3 q1 = o + t1 * d;
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    vec4 edge = k == 0 ? edge0 : (k == 1 ? edge1 : edge2);
    vec3 in_ = vec3(edge);  // unit, into the triangle
    float e0 = dot(in_, q0) - edge.w;
    float e1 = dot(in_, q1) - edge.w;
    // Both ends of the near-plane part outside one edge: the convex triangle is missed.
    if (e0 < -margin && e1 < -margin) return TD_SEGMENT_MISSES;
    inside = inside && e0 > margin && e1 > margin;
  }
  // A crossing: the segment's ends lie on both sides of the plane beyond the margin, not grazing it (d is
  // unit: the shadow ray's toLight), and the whole near-plane part (which holds the crossing point) inside
  // the triangle by the margin.
  bool endBeyond = endless ? sd != 0.0f : abs(sEnd) > margin;
  bool endPositive = endless ? sd > 0.0f : sEnd > 0.0f;
  if (inside && abs(s0) > margin && endBeyond && (s0 > 0.0f) != endPositive && abs(sd) > 1e-3f)
    return TD_SEGMENT_CROSSES;
  return TD_SEGMENT_UNSURE;
}

#endif
