// The environment as the GL reads it (docs/environment.md; core/Environment.h's EnvironmentLookup is the C++
// twin, from the same record): its uniforms, what a ray leaving the scene sees and the ambient term's share.
// Included by shade.frag and sky.frag after their `background` uniform; not standalone.
layout(location = TD_LOC_ENV_KIND) uniform int envKind;
layout(location = TD_LOC_ENV_PARAMS) uniform vec4 envParams;  // xy its turn's cos, sin; z the image's scale; w lights ambient
layout(location = TD_LOC_ENV_SKY) uniform vec3 envSky[3];     // zenith, horizon, ground
layout(location = TD_LOC_ENV_SH) uniform vec3 envSh[9];
layout(binding = TD_UNIT_ENVIRONMENT) uniform sampler2D envMap;  // linear filtering, u repeats, v clamped
// What a ray leaving the scene along unit dirW sees. (A level-0 lookup: no derivatives where pixels branch.)
vec3 environmentRadiance(vec3 dirW) {
  if (envKind == TD_ENV_BACKGROUND) return background;
  vec3 d = tdEnvironmentFrame(dirW, envParams.xy);
  if (envKind == TD_ENV_SKY) return tdEnvironmentClamp(tdSkyRadiance(d, envSky[0], envSky[1], envSky[2]));
  return tdEnvironmentClamp(envParams.z * textureLod(envMap, tdEquirectUv(d), 0.0).rgb);
}
// The environment's share of the ambient term at a surface facing unit nW.
vec3 environmentAmbient(vec3 nW) {
  return envParams.w > 0.5 ? tdShAmbient(tdEnvironmentFrame(nW, envParams.xy), envSh) : vec3(0.0);
}
