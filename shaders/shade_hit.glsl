// The shade pass (shade.frag): the exact hit a pixel shows, rebuilt from its camera ray and the visible triangle.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.

// ---- the visible triangle ----
struct Triangle {
  uint v0, v1, v2;  // absolute vertex numbers
  vec3 p0, p1, p2;  // world space
  uint flags;
  uint material;
  uint probe;  // reflection-probe slot + 1, 0 = none
  mat3 normalFromObject;
  mat3 worldLinear;  // upper 3×3 of worldFromObject: tangents transform with it
};

mat4 instanceWorldFromObject(uint instance) {
  int base = 9 * int(instance);
  return mat4(texelFetch(instancesBuf, base), texelFetch(instancesBuf, base + 1), texelFetch(instancesBuf, base + 2),
              texelFetch(instancesBuf, base + 3));
}

// The instance's part of a Triangle (material, probe, transforms; no vertices, no attribute flags), and its
// record's transform and mesh/material texel for loadTriangle, fetched once.
Triangle loadInstance(uint instance, out mat4 worldFromObject, out uvec4 meshMaterial) {
  Triangle t;
  int base = 9 * int(instance);
  worldFromObject = instanceWorldFromObject(instance);
  meshMaterial = texelFetch(instanceIdsBuf, base + 8);
  t.v0 = t.v1 = t.v2 = 0u;
  t.flags = 0u;
  t.material = meshMaterial.y;
  t.probe = meshMaterial.z;
  t.normalFromObject = mat3(texelFetch(instancesBuf, base + 4).xyz, texelFetch(instancesBuf, base + 5).xyz,
                            texelFetch(instancesBuf, base + 6).xyz);
  t.worldLinear = mat3(worldFromObject);
  return t;
}

Triangle loadTriangle(uint instance, uint primitive) {
  mat4 worldFromObject;
  uvec4 meshMaterial;
  Triangle t = loadInstance(instance, worldFromObject, meshMaterial);
  uvec4 mesh = texelFetch(meshesBuf, int(meshMaterial.x));
  int i = int(mesh.y + 3u * primitive);
  t.v0 = texelFetch(indicesBuf, i).x;
  t.v1 = texelFetch(indicesBuf, i + 1).x;
  t.v2 = texelFetch(indicesBuf, i + 2).x;
  t.p0 = (worldFromObject * vec4(positionO(t.v0), 1.0)).xyz;
  t.p1 = (worldFromObject * vec4(positionO(t.v1), 1.0)).xyz;
  t.p2 = (worldFromObject * vec4(positionO(t.v2), 1.0)).xyz;
  t.flags = mesh.z;
  return t;
}

vec3 geometricNormal(Triangle t) {
  vec3 n = cross(t.p1 - t.p0, t.p2 - t.p0);
  float len = length(n);
  return len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}

// Barycentrics (b0, b1, b2) where the ray meets the triangle's plane (Möller–Trumbore without the
// inside test: the rasterizer already decided this pixel sees this triangle). Unclamped, for ray
// differentials; hitBarycentrics clamps onto the triangle as the CPU's resolveHit does, so a pixel whose
// centre grazes past an edge still shades a point of the triangle.
vec3 rayBarycentrics(vec3 origin, vec3 dir, Triangle t) {
  vec3 e1 = t.p1 - t.p0;
  vec3 e2 = t.p2 - t.p0;
  vec3 pv = cross(dir, e2);
  float det = dot(e1, pv);
  if (abs(det) <= 1e-20 * dot(e1, e1) * dot(e2, e2) || det == 0.0) return vec3(1.0 / 3.0);
  float inv = 1.0 / det;
  vec3 tv = origin - t.p0;
  float b1 = dot(tv, pv) * inv;
  float b2 = dot(dir, cross(tv, e1)) * inv;
  return vec3(1.0 - b1 - b2, b1, b2);
}

vec3 hitBarycentrics(vec3 origin, vec3 dir, Triangle t) {
  vec3 b = rayBarycentrics(origin, dir, t);
  if (min(b.x, min(b.y, b.z)) >= 0.0) return b;
  b = max(b, vec3(0.0));
  float sum = b.x + b.y + b.z;
  return sum > 0.0 ? b / sum : vec3(1.0 / 3.0);
}


// ---- the exact hit of a pixel's camera ray (rt::resolveHit's twin) ----
struct PrimaryHit {
  vec3 origin, dir;  // the pixel's camera ray
  uint instance;
  Triangle tri;
  vec3 b;            // barycentrics on tri
  vec3 posW;
  vec3 ngRaw;        // the unflipped geometric normal
  bool onSolid;      // a point on an exact solid (ids.y = TD_EXACT_TRIANGLE)
};

// The hit that pixel `pix` (GL rows) shows, with its ids `id` (id.x > 0): rebuilt from the camera ray through
// the pixel's centre, as the CPU ray pass does.
PrimaryHit primaryHit(ivec2 pix, uvec2 id) {
  PrimaryHit h;
  cameraRay(vec2(pix) + 0.5, h.origin, h.dir);
  h.instance = id.x - 1u;
  h.onSolid = false;
  if (kUseExact && id.y == TD_EXACT_TRIANGLE) {
    h.onSolid = true;
    // A point on an exact solid (rt::resolveHit's twin): no vertices or attributes, the solid's own normal;
    // its "triangle" is the point itself, so Gouraud and flat shade it per pixel with that normal.
    vec4 exact = texelFetch(exactHitsTex, pix, 0);
    mat4 worldFromObject;
    uvec4 meshMaterial;
    h.tri = loadInstance(h.instance, worldFromObject, meshMaterial);
    h.posW = h.origin + exact.w * h.dir;
    h.tri.p0 = h.posW;
    h.tri.p1 = h.posW;
    h.tri.p2 = h.posW;
    h.b = vec3(1.0, 0.0, 0.0);
    h.ngRaw = exact.xyz;
    return h;
  }
  h.tri = loadTriangle(h.instance, id.y);
  h.b = hitBarycentrics(h.origin, h.dir, h.tri);
  h.posW = h.b.x * h.tri.p0 + h.b.y * h.tri.p1 + h.b.z * h.tri.p2;
  h.ngRaw = geometricNormal(h.tri);
  return h;
}
