// The scene as the GL passes see it: shared vertex / index buffers and per-instance records in SSBOs,
// uploaded once per scene by engine/src/gl/GpuScene.cpp (which owns the binding numbers below).
// Absent channels are never read: GpuMesh.flags says which attributes a mesh has.
#define TD_MESH_HAS_NORMALS 1u
#define TD_MESH_HAS_UVS 2u
#define TD_MESH_HAS_COLORS 4u
#define TD_MESH_HAS_TANGENTS 8u  // and drawn with a normal-mapped material

struct GpuInstance {
  mat4 worldFromObject;
  mat4 normalFromObject;  // inverse transpose of worldFromObject (upper 3×3 used)
  uvec4 meshMaterial;     // x mesh, y material, z reflection-probe slot + 1 (0 = none)
};

struct GpuMesh {
  uvec4 firstIndexFlags;  // x first vertex, y first index, z flags (TD_MESH_HAS_*), w triangle count
};

// xyz packed as floats: a vec3 array would pad every element to 16 bytes.
#include "bindings.glsl"
layout(std430, binding = TD_BIND_POSITIONS) readonly buffer Positions { float positions[]; };
layout(std430, binding = TD_BIND_NORMALS) readonly buffer Normals { float normals[]; };
layout(std430, binding = TD_BIND_UVS) readonly buffer Uvs { vec2 uvs[]; };
layout(std430, binding = TD_BIND_COLORS) readonly buffer Colors { vec4 colors[]; };
layout(std430, binding = TD_BIND_INDICES) readonly buffer Indices { uint indices[]; };  // absolute vertex numbers
layout(std430, binding = TD_BIND_MESHES) readonly buffer Meshes { GpuMesh meshes[]; };
layout(std430, binding = TD_BIND_INSTANCES) readonly buffer Instances { GpuInstance instances[]; };

vec3 tdPositionO(uint v) { return vec3(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]); }
vec3 tdNormalO(uint v) { return vec3(normals[3u * v], normals[3u * v + 1u], normals[3u * v + 2u]); }
