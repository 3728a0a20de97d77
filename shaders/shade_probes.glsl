// The shade pass (shade.frag): raster reflections and refraction through reflection probes.
// A part of shade.frag, included by it after its resources and variant flags, which it reads; not a
// standalone include.
// Raster reflection and refraction (reflections / refraction = Raster): the surface's probe, added to the
// gathered rays' reflected and transmitted radiance.
void probeLight(Surface s, inout RaySample rays) {
  GpuMaterial m = s.m;
  Triangle tri = s.hit.tri;
  vec3 V = s.V, N = s.N, Ng = s.Ng;
  float side = s.side, coverage = s.coverage;
  if (tri.probe != 0u) {
    // Environment-mapped reflection and refraction through this object's probe, weighted like the ray
    // pass's Whitted::weights (docs/shading.md): Fresnel from the shared formulas, inside/outside from
    // the geometric normal, refraction by Snell at this surface only (no exit through the far side), and
    // the ray pass's directions: reflected over the facet, refracted through it (tdReflectOverFacet,
    // tdRefractOverFacet), so a silhouette's probe lookup is the direction its ray would take.
    float kr = m.krKtIorModel.x, kt = m.krKtIorModel.y, ior = m.krKtIorModel.z;
    bool backFace = side < 0.0;
    float etaI = backFace ? ior : 1.0, etaT = backFace ? 1.0 : ior;
    float cosI = clamp(dot(N, V), 0.0, 1.0);
    float eta = etaI / etaT;
    float cos2T = tdCos2T(cosI, eta);
    float F = 0.0;
    if (kt > 0.0 && etaI != etaT)
      F = cos2T <= 0.0 ? 1.0 : (kFresnelSchlick ? tdFresnelSchlick(cosI, etaI, etaT) : tdFresnelExact(cosI, etaI, etaT));
    vec2 sum = tdWhittedSum(kr, kt, F, etaI != etaT && cos2T <= 0.0, kFresnelWeighted);
    float wR = sum.x, wT = sum.y;
    // Coverage and tint (docs/gltf.md): the covered part reflects and refracts (tinted), the rest passes
    // straight through; BLEND materials have IOR 1, so both go along the same direction.
    wR *= coverage;
    int ut = 4 * int(tri.material) + 3;  // the transmission tint and roughness sit in the uv-transform record
    vec4 tintRough = texelFetch(uvTransformsBuf, ut);
    vec3 wTv = tdTransmitWeight(coverage, wT, tintRough.rgb);
    float layer = float(tri.probe - 1u);
    // A glossy material (docs/glossy.md) reads the probe at the mip level whose texels are as wide as its
    // lobe: about α = roughness² radians, a level-0 texel of an n² face being (π/2)/n.
    float alpha = tintRough.a * tintRough.a;
    float faceSize = float(textureSize(probes, 0).x);
    float lod = alpha > 0.0 ? clamp(log2(alpha * (faceSize * 2.0 / 3.14159265)), 0.0, log2(faceSize)) : 0.0;
    if (kProbeReflect && wR > 0.0) rays.reflected += wR * textureLod(probes, vec4(tdReflectOverFacet(V, N, Ng), layer), lod).rgb;
    if (kProbeRefract && (wTv.x > 0.0 || wTv.y > 0.0 || wTv.z > 0.0)) {
#if (TD_PROBES & TD_PROBE_BEHIND) != 0
      // Straight through (IOR 1: thin-walled transmission, a BLEND surface's uncovered part): what lies behind
      // it along this pixel's own ray, which the view behind holds, instead of the probe seen from the
      // object's centre (a lamp's shade sees its bulb from inside). A rough one spreads it over its lobe, about
      // α radians from the surface: at the distance behind it of what it shows, as seen from the camera,
      // α·(behind − here)/behind radians of the view around the pixel (the view's alpha holds its distance),
      // the mip level whose texels are as wide (an orthographic view read as a 45° one). The uncovered part of
      // a BLEND surface stays sharp.
      if (etaI == etaT) {
        float pixelsPerRadian = float(frameSize.y) / (orthographic != 0 ? 0.785398 : 2.0 * atan(length(cameraUp)));
        float behindDistance = texelFetch(behindView, ivec2(gl_FragCoord.xy), 0).a;
        float here = distance(s.hit.posW, cameraPosW);
        float spread = alpha * max(behindDistance - here, 0.0) / max(behindDistance, 1e-6);
        float behindLod = kt > 0.0 && spread > 0.0 ? max(log2(spread * pixelsPerRadian), 0.0) : 0.0;
        vec2 uv = gl_FragCoord.xy / vec2(textureSize(behindView, 0));
        rays.transmitted += wTv * textureLod(behindView, uv, behindLod).rgb;
        return;
      }
#endif
      vec3 T = etaI == etaT ? -V : tdRefractOverFacet(normalize(eta * -V + (eta * cosI - sqrt(max(cos2T, 0.0))) * N), V, Ng, eta);
      rays.transmitted += wTv * textureLod(probes, vec4(T, layer), kt > 0.0 ? lod : 0.0).rgb;  // pass-through: sharp
    }
  }
}
