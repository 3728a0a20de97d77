// The one table of GL binding points, texture units and channel bits. Included by every shader that binds
// something, and by C++ (engine/src/gl/Bindings.h) as plain #defines, so a number is written once.
// Channels and formats: docs/gbuffer.md.
#ifndef TD_BINDINGS_GLSL
#define TD_BINDINGS_GLSL

// ---- shader storage buffers (scene.glsl; GpuScene) ----
#define TD_BIND_POSITIONS 0
#define TD_BIND_NORMALS 1
#define TD_BIND_UVS 2
#define TD_BIND_COLORS 3
#define TD_BIND_INDICES 4
#define TD_BIND_MESHES 5
#define TD_BIND_INSTANCES 6
#define TD_BIND_MATERIALS 7
#define TD_BIND_LIGHTS 8
#define TD_BIND_UV_TRANSFORMS 9

// ---- uniform blocks ----
#define TD_BLOCK_LIGHTS 0
#define TD_BLOCK_MATERIALS 1
#define TD_BLOCK_SHADOWS 2

// ---- texture units: the shade pass's frame inputs (CompositePass) ----
#define TD_UNIT_IDS 0           // visibility ids, RG32UI
#define TD_UNIT_DEPTH 1         // a copy of the visibility depth (never the attached one)
#define TD_UNIT_KD 2            // sRGB texture array (base colour, emissive); the visibility pass's too
#define TD_UNIT_RAMPS 3         // toon ramps, R32F
#define TD_UNIT_LIGHT_MASK 4    // ray grid, R32UI
#define TD_UNIT_REFLECTED 5     // ray grid, RGBA32F
#define TD_UNIT_TRANSMITTED 6   // ray grid, RGBA32F
#define TD_UNIT_LINEAR 0        // the tone-map pass's linear radiance

// ---- texture units: buffer-texture views of the scene's buffers (GpuScene) ----
#define TD_UNIT_POSITIONS_TEX 7
#define TD_UNIT_NORMALS_TEX 8
#define TD_UNIT_UVS_TEX 9
#define TD_UNIT_COLORS_TEX 10
#define TD_UNIT_INDICES_TEX 11
#define TD_UNIT_MESHES_TEX 12
#define TD_UNIT_INSTANCES_TEX 13
#define TD_UNIT_INSTANCE_IDS_TEX 14
#define TD_UNIT_UV_TRANSFORMS_TEX 15

// ---- texture units: raster effects (RasterEffects) ----
#define TD_UNIT_SHADOW_MAPS 16
#define TD_UNIT_SHADOW_CUBES 17
#define TD_UNIT_PROBES 18

// ---- texture units: normal maps (GpuScene) ----
#define TD_UNIT_TANGENTS_TEX 19
#define TD_UNIT_NORMAL_MAPS 20

// ---- channel bits the shade pass is compiled for ----
#define TD_RAY_LIGHT_MASK 1     // TD_RAY_INPUTS: which ray results were uploaded
#define TD_RAY_REFLECTED 2
#define TD_RAY_TRANSMITTED 4
#define TD_PROBE_REFLECT 1      // TD_PROBES: which effects the probes stand in for
#define TD_PROBE_REFRACT 2

#endif
