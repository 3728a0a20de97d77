// The shade pass (shade.frag): the surface at a pixel: its hit, normals, material and texture inputs.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
// What the shade pass knows of the surface a pixel shows (loadSurface); its normals face the viewer once
// orientTwoSided has run.
// Whether a material has a glossy lobe (docs/glossy.md): its roughness, in the uv-transform record's fourth
// texel (shade_probes).
float materialRoughness(uint material) { return texelFetch(uvTransformsBuf, 4 * int(material) + 3).a; }

struct Surface {
  PrimaryHit hit;
  vec3 V;          // towards the eye
  vec3 Ng, N;      // geometric and shading normal
  float side;      // -1 on a back face (two-sided: lit like a front), else 1 (orientTwoSided)
  bool hasNormals;
  GpuMaterial m;
  vec2 uv;
  vec3 tint;       // kd texture × vertex colour
  vec3 emission;
  float pattern;   // the procedural texture's value (0 without one)
  float coverage;  // BLEND coverage, 1 otherwise
};

// The surface pixel `pix` (GL rows) shows, with its ids `id` (id.x > 0): the exact hit, the shading normal
// (interpolated, normal-mapped, bumped by a procedural texture), the material, uv, tint, emission and coverage.
Surface loadSurface(ivec2 pix, uvec2 id) {
  PrimaryHit hit = primaryHit(pix, id);
  vec3 origin = hit.origin, dir = hit.dir;
  uint instance = hit.instance;
  Triangle tri = hit.tri;
  vec3 b = hit.b;
  vec3 posW = hit.posW;
  vec3 ngRaw = hit.ngRaw;
  bool onSolid = hit.onSolid;
  vec3 V = -dir;
  vec3 Ng = ngRaw;
  vec3 N = Ng;
  bool hasNormals = (tri.flags & TD_MESH_HAS_NORMALS) != 0u;
  if (hasNormals) {
    vec3 nO = b.x * objectNormal(tri.v0) + b.y * objectNormal(tri.v1) + b.z * objectNormal(tri.v2);
    vec3 n = tri.normalFromObject * nO;
    float len = length(n);
    if (len > 0.0) N = n / len;
  }
  GpuMaterial m = materials[tri.material];

  // ---- surface inputs: uv, texture × vertex colour, coverage, emissive and normal maps ----
  vec2 uv = vec2(0.0);
  vec3 tint = vec3(1.0);
  vec3 emission = vec3(m.emissionFlags);
  float texA = 1.0;  // kd texture alpha (coverage)
  if (kUseUvs && (tri.flags & TD_MESH_HAS_UVS) != 0u) {
    vec2 uv0 = texelFetch(uvsBuf, int(tri.v0)).xy, uv1 = texelFetch(uvsBuf, int(tri.v1)).xy,
         uv2 = texelFetch(uvsBuf, int(tri.v2)).xy;
    int ut = 4 * int(tri.material);  // Material::uvTransform, its upper 3×3
    mat3 uvFromMesh = mat3(texelFetch(uvTransformsBuf, ut).xyz, texelFetch(uvTransformsBuf, ut + 1).xyz,
                           texelFetch(uvTransformsBuf, ut + 2).xyz);
    uv = (uvFromMesh * vec3(b.x * uv0 + b.y * uv1 + b.z * uv2, 1.0)).xy;
    bool kdTex = kUseKdTextures && m.kdTex.w >= 0.0;
    bool emTex = kUseEmissive && m.texAlpha.x >= 0.0;
    bool nmTex = kUseNormalMaps && m.texAlpha.y >= 0.0 && (tri.flags & TD_MESH_HAS_TANGENTS) != 0u;
    if (kdTex || emTex || nmTex) {
      // Ray differentials: where the neighbouring pixels' rays meet this triangle's plane gives exact
      // uv derivatives (screen-space dFdx would mix triangles at edges in a full-screen pass).
      vec3 ox, dx, oy, dy;
      cameraRay(gl_FragCoord.xy + vec2(1.0, 0.0), ox, dx);
      cameraRay(gl_FragCoord.xy + vec2(0.0, 1.0), oy, dy);
      vec3 bx = rayBarycentrics(ox, dx, tri);
      vec3 by = rayBarycentrics(oy, dy, tri);
      vec2 duvx = (uvFromMesh * vec3(bx.x * uv0 + bx.y * uv1 + bx.z * uv2, 1.0)).xy - uv;
      vec2 duvy = (uvFromMesh * vec3(by.x * uv0 + by.y * uv1 + by.z * uv2, 1.0)).xy - uv;
      if (kdTex) {
        vec4 texel = textureGrad(kdTextures, vec3(uv, float(int(m.kdTex.w + 0.5))), duvx, duvy);
        tint = texel.rgb;
        texA = texel.a;
      }
      if (emTex) emission *= textureGrad(kdTextures, vec3(uv, float(int(m.texAlpha.x + 0.5))), duvx, duvy).rgb;
      if (nmTex) {
        // The CPU twin's frame (rt::resolveHit): interpolated tangent through the upper 3×3, the shared
        // perturbation, before the two-sided flip.
        vec4 t4 = b.x * texelFetch(tangentsBuf, int(tri.v0)) + b.y * texelFetch(tangentsBuf, int(tri.v1)) +
                  b.z * texelFetch(tangentsBuf, int(tri.v2));
        vec3 tn = textureGrad(normalMaps, vec3(uv, float(int(m.texAlpha.y + 0.5))), duvx, duvy).xyz * 2.0 - 1.0;
        N = tdPerturbNormal(N, tri.worldLinear * t4.xyz, t4.w, tn, m.texAlpha.z);
      }
    }
  }
  if (kUseColors && (tri.flags & TD_MESH_HAS_COLORS) != 0u)
    tint *= (b.x * texelFetch(colorsBuf, int(tri.v0)) + b.y * texelFetch(colorsBuf, int(tri.v1)) +
             b.z * texelFetch(colorsBuf, int(tri.v2))).rgb;
  // The procedural texture (rt::resolveHit's twin): its value mixes kd and kd2, its gradient bumps N. The point
  // in the pattern's space: world (render space + the anchor), or object space, the vertices' positions
  // interpolated, or a solid's point brought back through the inverse of the instance's transform.
  float pattern = 0.0;
  if (kUseProcedural && m.pattern.x > 0.5) {
    bool world = m.patternSpace.x > 0.5;
    vec3 p = world ? posW + renderAnchor
           : onSolid ? transpose(tri.normalFromObject) * (posW - instanceWorldFromObject(instance)[3].xyz)
                     : b.x * positionO(tri.v0) + b.y * positionO(tri.v1) + b.z * positionO(tri.v2);
    vec4 v = tdPattern(int(m.pattern.x + 0.5), p, m.pattern.y, m.pattern.z, int(m.pattern.w + 0.5));
    pattern = v.x;
    if (m.patternSpace.y > 0.0) N = tdBumpNormal(N, world ? v.yzw : tri.normalFromObject * v.yzw, m.patternSpace.y);
  }
  // BLEND coverage (MASK was decided by the visibility pass's discard: a pixel here is covered).
  float coverage = kUseAlphaBlend && m.texAlpha.w < 0.0 ? tdCoverage(m, texA) : 1.0;
  Surface s;
  s.hit = hit;
  s.V = V;
  s.Ng = Ng;
  s.N = N;
  s.side = 1.0;
  s.hasNormals = hasNormals;
  s.m = m;
  s.uv = uv;
  s.tint = tint;
  s.emission = emission;
  s.pattern = pattern;
  s.coverage = coverage;
  return s;
}

// Two-sided lighting: a back face is lit like a front, so both normals turn towards the viewer.
void orientTwoSided(inout Surface s) {
  s.side = dot(s.Ng, s.V) < 0.0 ? -1.0 : 1.0;
  s.Ng *= s.side;
  s.N *= s.side;
}
