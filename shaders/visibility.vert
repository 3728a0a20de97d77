#version 450 core
// Visibility pass: positions pulled from the shared SSBO by vertex number (indices are absolute).
#include "scene.glsl"

layout(location = 0) in uint instanceIndex;  // divisor 1, offset by the draw command's baseInstance

// clipFromView · viewFromWorld with the camera translation taken out: positions are made relative to
// the camera before the matrix, which keeps precision for scenes far from the origin.
layout(location = 0) uniform mat4 clipFromWorldRelative;
layout(location = 1) uniform vec3 cameraPosW;
// Instance index + 1 to leave out (0 = none): a reflection probe does not see the object it sits in.
layout(location = 2) uniform uint excludedPlusOne;

flat out uint vInstance;

void main() {
  if (instanceIndex + 1u == excludedPlusOne) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the whole triangle is culled
    vInstance = instanceIndex;
    return;
  }
  vec3 posO = tdPositionO(uint(gl_VertexID));
  vec3 posW = (instances[instanceIndex].worldFromObject * vec4(posO, 1.0)).xyz;
  gl_Position = clipFromWorldRelative * vec4(posW - cameraPosW, 1.0);
  vInstance = instanceIndex;
}
