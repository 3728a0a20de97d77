#version 450 core
// Visibility pass: positions pulled from the shared SSBO by vertex number (indices are absolute).
#include "scene.glsl"

layout(location = 0) in uint instanceIndex;  // divisor 1, offset by the draw command's baseInstance

// clipFromView · viewFromWorld with the camera translation taken out: positions are made relative to
// the camera before the matrix, which keeps precision for scenes far from the origin.
layout(location = 0) uniform mat4 clipFromWorldRelative;
layout(location = 1) uniform vec3 cameraPosW;

flat out uint vInstance;

void main() {
  vec3 posO = tdPositionO(uint(gl_VertexID));
  vec3 posW = (instances[instanceIndex].worldFromObject * vec4(posO, 1.0)).xyz;
  gl_Position = clipFromWorldRelative * vec4(posW - cameraPosW, 1.0);
  vInstance = instanceIndex;
}
