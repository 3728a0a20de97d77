#version 450 core
// The background pixels of a shade pass's target where a software GL's early depth test keeps shade.frag off
// them (ShadePass::draw): the environment along each pixel's camera ray, with everything shade.frag writes on a
// background pixel (its id-0 branch, which a GPU runs instead): the display value, the filter's background
// guides and its radiance past the filter. Outputs the target has no buffer for are dropped.
#define TD_OUT(T) out T
#include "bindings.glsl"
#include "shading.glsl"

layout(location = TD_LOC_CAMERA_POS) uniform vec3 cameraPosW;
layout(location = TD_LOC_CAMERA_FORWARD) uniform vec3 cameraForward;
layout(location = TD_LOC_CAMERA_RIGHT) uniform vec3 cameraRight;  // scaled, as shade.frag's
layout(location = TD_LOC_CAMERA_UP) uniform vec3 cameraUp;
layout(location = TD_LOC_ORTHOGRAPHIC) uniform int orthographic;
layout(location = TD_LOC_FRAME_SIZE) uniform ivec2 frameSize;
layout(location = TD_LOC_BACKGROUND) uniform vec3 background;
layout(location = TD_LOC_FUSED_EXPOSURE) uniform float exposure;
layout(location = TD_LOC_FUSED_TONE_MAP) uniform int toneMap;
layout(location = TD_LOC_FUSED_PASS_THROUGH) uniform int passThrough;
#include "environment.glsl"
#include "camera_ray.glsl"

layout(location = 0) out TD_OUTPUT_LINEAR outColor;
layout(location = 1) out TD_OUTPUT_DISPLAY outDisplay;
layout(location = 2) out TD_OUTPUT_DENOISE_GUIDE outGuide;
layout(location = 3) out TD_OUTPUT_DENOISE_MOTION outMotion;
layout(location = 4) out TD_OUTPUT_DENOISE_EXACT outExact;

void main() {
  vec3 origin, dir;
  cameraRay(gl_FragCoord.xy, origin, dir);
  vec3 sky = environmentRadiance(dir);
  outColor = vec4(sky, 1.0);
  outDisplay = vec4(tdDisplay(sky, exposure, toneMap, passThrough != 0), 1.0);
  outGuide = uvec4(0u);
  outMotion = vec4(0.0, 0.0, 0.0, -1.0);  // (w -1: the background)
  outExact = vec4(sky, 0.0);
}
