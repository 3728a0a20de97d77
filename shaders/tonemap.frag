#version 450 core
// The one place radiance becomes display values: exposure, tone map, sRGB encode (docs/shading.md,
// "Output"). Debug views that are already display values pass through.
#define TD_OUT(T) out T
#include "bindings.glsl"
#include "shading.glsl"

layout(binding = TD_UNIT_LINEAR) uniform TD_SAMPLER_LINEAR linearColor;
layout(location = TD_LOC_EXPOSURE) uniform float exposure;
layout(location = TD_LOC_TONE_MAP) uniform int toneMap;
layout(location = TD_LOC_PASS_THROUGH) uniform int passThrough;

layout(location = 0) out TD_OUTPUT_DISPLAY outColor;

void main() {
  vec3 c = texelFetch(linearColor, ivec2(gl_FragCoord.xy), 0).rgb;
  outColor = vec4(tdDisplay(c, exposure, toneMap, passThrough != 0), 1.0);
}
