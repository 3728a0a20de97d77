#version 450 core
// Visibility pass: positions pulled from the shared SSBO by vertex number (indices are absolute).
#include "scene.glsl"
#ifndef TD_ALPHA_MASK
#define TD_ALPHA_MASK 0  // some material is MASK: pass uv and the alpha test to the fragment shader
#endif
#if TD_ALPHA_MASK
#define TD_OUT(T) out T
#include "shading.glsl"
layout(std430, binding = TD_BIND_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, binding = TD_BIND_UV_TRANSFORMS) readonly buffer UvTransforms { mat4 uvTransforms[]; };  // GpuScene: xyz columns
out vec2 vUv;
flat out float vAlphaCode;  // tdCoverage's code when the material is MASK, else 0 (no test)
flat out float vLayer;      // kd texture layer, -1 for none (coverage from the base alpha only)
#endif

layout(location = 0) in uint instanceIndex;  // divisor 1, offset by the draw command's baseInstance
// What the draw's triangle numbers are offset by: 0 for a mesh, its copy's place past the mesh's own triangles
// for a probe face's coarse copy (GpuScene::ensureProbeLod), so the id names the triangle the shade pass reads.
layout(location = 1) in uint primitiveBase;

// clipFromView · viewFromWorld with the camera translation taken out: positions are made relative to
// the camera before the matrix, which keeps precision for scenes far from the origin.
layout(location = TD_LOC_CLIP_FROM_WORLD_RELATIVE) uniform mat4 clipFromWorldRelative;
layout(location = TD_LOC_VISIBILITY_CAMERA_POS) uniform vec3 cameraPosW;
// Instance index + 1 to leave out (0 = none): a reflection probe does not see the object it sits in.
layout(location = TD_LOC_EXCLUDED_PLUS_ONE) uniform uint excludedPlusOne;

flat out uint vInstance;
flat out uint vPrimitiveBase;
// The same depth from every variant of this shader (GLSL 4.50 §4.8.1): the peeling pass (TD_PEEL) compares a
// fragment's depth with the one another variant drew for the same surface.
invariant gl_Position;

void main() {
  vPrimitiveBase = primitiveBase;
#if TD_ALPHA_MASK
  vUv = vec2(0.0);
  vAlphaCode = 0.0;
  vLayer = -1.0;
#endif
  if (instanceIndex + 1u == excludedPlusOne) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the whole triangle is culled
    vInstance = instanceIndex;
    return;
  }
  vec3 posO = tdPositionO(uint(gl_VertexID));
  vec3 posW = (instances[instanceIndex].worldFromObject * vec4(posO, 1.0)).xyz;
  gl_Position = clipFromWorldRelative * vec4(posW - cameraPosW, 1.0);
  vInstance = instanceIndex;
#if TD_ALPHA_MASK
  uvec4 meshMaterial = instances[instanceIndex].meshMaterial;
  GpuMaterial m = materials[meshMaterial.y];
  if (m.texAlpha.w > 0.0) {
    vAlphaCode = m.texAlpha.w;
    // The shade pass samples the kd texture only on meshes with uvs; without them the texture is not
    // applied there either, so coverage comes from the base alpha alone.
    if ((meshes[meshMaterial.x].firstIndexFlags.z & TD_MESH_HAS_UVS) != 0u && m.kdTex.w >= 0.0) {
      vLayer = float(int(m.kdTex.w + 0.5));
      vUv = (mat3(uvTransforms[meshMaterial.y]) * vec3(uvs[gl_VertexID], 1.0)).xy;
    }
  }
#endif
}
