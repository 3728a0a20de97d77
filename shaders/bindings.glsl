// The one table of GL binding points, texture units, channel formats and channel bits. Included by every
// shader that binds something, and by C++ (engine/src/gl/Bindings.h) as plain #defines, so a number or a
// format is written once. Channels and formats: docs/gbuffer.md.
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
#define TD_BIND_RESOLVED 10     // the resolve step's records (core/ResolvedPixel.h), read by resolve.vert

// ---- uniform blocks ----
#define TD_BLOCK_LIGHTS 0
#define TD_BLOCK_MATERIALS 1
#define TD_BLOCK_SHADOWS 2
#define TD_BLOCK_PROOF_MAPS 3    // the shadow-proof pass's maps (ShadowProofPass)

// ---- texture units: the shade pass's frame inputs (CompositePass) ----
#define TD_UNIT_IDS 0           // visibility ids, RG32UI
#define TD_UNIT_DEPTH 1         // a copy of the visibility depth (never the attached one)
#define TD_UNIT_KD 2            // sRGB texture array (base colour, emissive); the visibility pass's too
#define TD_UNIT_RAMPS 3         // toon ramps, R32F
#define TD_UNIT_LIGHT_MASK 4    // ray grid, R8UI
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
#define TD_UNIT_SHADOW_CUBES_DEPTH 22  // the cube maps again, without depth compare (soft shadows' blocker search)

// ---- texture units: normal maps (GpuScene) ----
#define TD_UNIT_TANGENTS_TEX 19
#define TD_UNIT_NORMAL_MAPS 20

// ---- texture units: area lights' sample visibility (ShadePass) ----
#define TD_UNIT_AREA_SAMPLES 21

// ---- texture units: the radiosity solution (GpuScene::uploadRadiosity; core/Radiosity.h) ----
#define TD_UNIT_RADIOSITY_TABLE_TEX 23  // RG32UI: per instance (first triangle entry, count), per triangle (first value, n)
#define TD_UNIT_RADIOSITY_TEX 24        // RGB32F: indirect irradiance per grid vertex and side

// ---- texture units: exact solids' hits (VisibilityPass::patch; docs/csg.md) ----
#define TD_UNIT_EXACT_HITS 25  // RGBA32F, full res: a solid's outward normal and t along the camera ray
// ---- texture units: raster shadows on the ray grid (ShadePass's shadow-mask pass) ----
#define TD_UNIT_SHADOW_MASK 26  // RGBA16 array, ray grid: visibility of lights 0-3 (layer 0) and 4-7 (layer 1)
// ---- texture units: motion (the motion view; docs/motion.md) — the same numbers as the proofs' units,
// which belong to another program ----
#define TD_UNIT_MOTION_INSTANCES 27  // RGBA32F buffer: per instance 4 texels, previous-from-current render space
#define TD_UNIT_PREVIOUS_IDS 28      // RG32UI: the last frame's ids (GL rows)
#define TD_UNIT_PREVIOUS_DEPTH 29    // the last frame's visibility depth
// ---- texture units: the environment (GpuScene; docs/environment.md) — the proofs' number, another program's ----
#define TD_UNIT_ENVIRONMENT 30       // RGB32F: the environment's equirectangular image (TD_ENV_MAP), top row first
// ---- texture units: the view behind see-through surfaces (gl/BehindView.h) — the proofs' number, another program's ----
#define TD_UNIT_BEHIND 31            // RGBA16F, the frame's size: what lies behind the nearest see-through surface
#define TD_UNIT_PEEL_DEPTH 1         // the visibility pass's (TD_PEEL): the nearest see-through surface's depth
// ---- texture units: the hybrid shadows' maps in the GL (ShadowProofPass; shadow_proof.frag) ----
#define TD_UNIT_PROOF_TEXELS 27     // R32UI: texel records, TD_PROOF_RECORD words each
#define TD_UNIT_PROOF_TRIANGLES 28  // RGBA32F: 5 per triangle (plane, edges, magnitude / valid / blocks)
#define TD_UNIT_PROOF_NEAR 29       // R32UI: the point lights' near-light triangle ids
#define TD_UNIT_PROOF_INSTANCES 30  // R32UI: per instance, its first global triangle id (~0: not proved)
#define TD_UNIT_PROOF_FLAGS 31      // R32UI: per instance, this frame's TD_PROOF_PLAIN / TD_PROOF_FLAT
// Instance flags: its material spawns no ray (no kr, no kt, not BLEND) and its shading normal is the geometric
// or the interpolated vertex normal (no normal map, no bump); its model is flat (lights are tested on Ng).
#define TD_PROOF_PLAIN 1u
#define TD_PROOF_FLAT 2u
// A proof word: bits 0-7 the answers, 8-15 the lights whose shadow ray is decided, 16-23 those whose ray the
// ray pass would trace (the light reaches the point); TD_PROOF_COMPLETE: every light decided and the hit
// spawns nothing, so bits 0-7 are the pixel's light mask and the ray pass need not resolve the hit at all.
#define TD_PROOF_DECIDED_SHIFT 8
#define TD_PROOF_NEEDED_SHIFT 16
#define TD_PROOF_COMPLETE 0x80000000u
// rt::ShadowCertainty's texel records: candidates per texel, words per record (ids, depths, rest), block side.
// Their buffer textures' formats (C++ only): 32-bit words, and the triangles' vec4s.
#define TD_FORMAT_PROOF_WORDS GL_R32UI
#define TD_FORMAT_PROOF_TRIANGLES GL_RGBA32F
#define TD_PROOF_CANDIDATES 6
#define TD_PROOF_RECORD 13
#define TD_PROOF_BLOCK 16

// ---- uniform locations (explicit, so C++ sets them without looking names up) ----
// The shade pass (shade.frag; ShadePass::shade).
#define TD_LOC_CAMERA_POS 0
#define TD_LOC_CAMERA_FORWARD 1
#define TD_LOC_CAMERA_RIGHT 2        // scaled: tan(fov/2)·aspect (perspective) or half width (ortho)
#define TD_LOC_CAMERA_UP 3           // scaled: tan(fov/2) or half height
#define TD_LOC_ORTHOGRAPHIC 4
#define TD_LOC_FRAME_SIZE 5
#define TD_LOC_BACKGROUND 6
#define TD_LOC_AMBIENT 7
#define TD_LOC_LIGHT_SAMPLES 8
#define TD_LOC_SAMPLE_BASE 9
#define TD_LOC_RAY_SCALE 11
#define TD_LOC_RAY_GRID_SIZE 12
#define TD_LOC_RAY_PRESENT 13
#define TD_LOC_FUSED_EXPOSURE 14     // TD_FUSED_OUTPUT: the output pass's three, in the shade pass
#define TD_LOC_FUSED_TONE_MAP 15
#define TD_LOC_FUSED_PASS_THROUGH 16
#define TD_LOC_RADIOSITY_AMBIENT 17
#define TD_LOC_RADIOSITY_INSTANCES 18
#define TD_LOC_RENDER_ANCHOR 19
#define TD_LOC_CLIP_FROM_VIEW_ROTATION 20           // the motion view: this frame's projection and rotation (4 locations)
#define TD_LOC_PREVIOUS_CLIP_FROM_VIEW_ROTATION 24  // and the last frame's (4 locations)
#define TD_LOC_PREVIOUS_CAMERA_POS 28               // the last frame's camera, render space
#define TD_LOC_MOTION_HISTORY 29                    // 1: the last frame's ids, depth and transforms are bound
#define TD_LOC_ENV_KIND 30    // the environment (core/Environment.h EnvironmentLookup): TD_ENV_*
#define TD_LOC_ENV_PARAMS 31  // xy cos, sin of its turn about +Y; z the image's scale; w 1: it lights the ambient term
#define TD_LOC_ENV_SKY 32     // the sky's zenith, horizon and ground, scaled (3 locations)
#define TD_LOC_ENV_SH 35      // the ambient term's nine coefficients, scaled (9 locations, 35-43)
#define TD_MAX_MOVED_BOXES 8         // the filter's boxes of what moved since the last frame (denoise.frag)
#define TD_LOC_PREVIOUS_CAMERA_FORWARD 47  // the filter's guides: the last frame's camera axis (unit, render space)
#define TD_LOC_SAMPLE_OFFSET 48            // the filter's guides: the frame's sub-pixel offset (pixels, GL rows)
// The spatiotemporal filter (denoise.frag; DenoisePass, docs/denoise.md): its own program's units and
// locations. The camera's right and up axes, orthographic and the frame size (TD_LOC_CAMERA_RIGHT ..
// TD_LOC_FRAME_SIZE, 2-5) are camera_ray.glsl's, from the same vectors (ShadePass's cameraVectors).
#define TD_UNIT_DENOISE_NOISY 0          // the shade pass's sampled radiance / its modulation this frame
#define TD_UNIT_DENOISE_GUIDE 1          // this frame's guide (depth, normal + instance, modulation)
#define TD_UNIT_DENOISE_MOTION 2         // this frame's motion (pixels), the point's depth before, in view before
#define TD_UNIT_DENOISE_HISTORY 3        // the last frame's filter texels after the first a-trous iteration
#define TD_UNIT_DENOISE_MOMENTS 4        // the last frame's luminance moments and history length
#define TD_UNIT_DENOISE_INPUT 5          // an a-trous iteration's input filter texels
#define TD_UNIT_DENOISE_EXACT 6          // this frame's radiance past the filter, added back by the final stage
#define TD_UNIT_DENOISE_FILTERED 7       // the filtered frame (linear radiance), the anti-aliasing stage's input
#define TD_UNIT_DENOISE_TAA_HISTORY 8    // the last frame's anti-aliased radiance (linear filtering: reprojected)
#define TD_UNIT_DENOISE_IDS 11           // this frame's visibility ids (the temporal stage: the instance, whole)
#define TD_LOC_DENOISE_STEP 6            // the a-trous iteration's tap spacing in pixels
#define TD_LOC_DENOISE_HISTORY 7         // 1: the last frame's history and moments hold
#define TD_LOC_DENOISE_MAX_HISTORY 8     // frames the temporal mean spans at most
#define TD_LOC_DENOISE_EXPOSURE 9        // the anti-aliasing writes the display too (tdDisplay)
#define TD_LOC_DENOISE_TONE_MAP 10
#define TD_LOC_DENOISE_GRID_SCALE 12     // the ray grid's divisor (rayScale): the filter's own pixels are the grid's
#define TD_LOC_DENOISE_GRID_SIZE 13      // the grid's size in pixels
#define TD_LOC_DENOISE_CAMERA_POS 14     // the camera, render space (the temporal stage rebuilds points)
#define TD_LOC_DENOISE_MOVED_COUNTS 15   // ivec2: moved boxes, area lights (DenoisePass's MovedInstances)
#define TD_LOC_DENOISE_MOVED_BOXES 16    // TD_MAX_MOVED_BOXES pairs of vec4 (lo + instance, hi): locations 16-31
#define TD_LOC_DENOISE_AREA_LIGHTS 32    // TD_MAX_LIGHTS vec4 (centre, radius): locations 32-39
#define TD_LOC_DENOISE_JITTER 40         // this frame's sub-pixel offset (pixels, x right, y up: GL rows)
#define TD_LOC_DENOISE_AXIS 41           // the camera's unjittered forward axis, unit (the guide's depth is along it)
#define TD_LOC_DENOISE_MOVED_REACH 42    // the farthest corner of a moved box from the camera (render space)
#define TD_LOC_DENOISE_LOBES_STALE 43    // 1: a light the filter does not smooth changed (glossy lobes' history goes)
// The output pass (tonemap.frag; OutputPass).
#define TD_LOC_EXPOSURE 0
#define TD_LOC_TONE_MAP 1
#define TD_LOC_PASS_THROUGH 2
// The visibility pass (visibility.vert; VisibilityPass::draw) and its resolve patch (resolve.vert).
#define TD_LOC_CLIP_FROM_WORLD_RELATIVE 0
#define TD_LOC_VISIBILITY_CAMERA_POS 1
#define TD_LOC_EXCLUDED_PLUS_ONE 2
#define TD_LOC_RESOLVE_FRAME_SIZE 0

// The triangle field of an id whose hit lies on an exact solid (core/ResolvedPixel.h, kExactTriangle).
#define TD_EXACT_TRIANGLE 0xFFFFFFFFu

// ---- frame channels (docs/gbuffer.md) ----
// TD_CHANNEL_X: the GL internal format, and the pixel format and type its CPU copies (uploads and
// read-backs) travel in; C++ only (GLSL never expands them). TD_SAMPLER_X / TD_OUTPUT_X: the type the
// shaders declare the channel with, which must match the format (unsigned integer, float or depth).
#define TD_CHANNEL_IDS GL_RG32UI, GL_RG_INTEGER, GL_UNSIGNED_INT     // visibility ids, full res
#define TD_SAMPLER_IDS usampler2D
#define TD_OUTPUT_IDS uvec2
#define TD_CHANNEL_DEPTH GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT  // reversed-Z, and its sampled copy
#define TD_SAMPLER_DEPTH sampler2D
#define TD_CHANNEL_LIGHT_MASK GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE  // ray grid, bit j = light j (≤ 8)
#define TD_SAMPLER_LIGHT_MASK usampler2D
#define TD_CHANNEL_AREA_SAMPLES GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT  // ray grid, layer = area light, bit k = sample k
#define TD_SAMPLER_AREA_SAMPLES usampler2DArray
#define TD_CHANNEL_REFLECTED GL_RGBA32F, GL_RGBA, GL_FLOAT       // ray grid, wR·S
#define TD_SAMPLER_REFLECTED sampler2D
#define TD_CHANNEL_TRANSMITTED GL_RGBA32F, GL_RGBA, GL_FLOAT     // ray grid, wT·T
#define TD_SAMPLER_TRANSMITTED sampler2D
#define TD_CHANNEL_EXACT_HITS GL_RGBA32F, GL_RGBA, GL_FLOAT        // full res, where ids.y = TD_EXACT_TRIANGLE
#define TD_SAMPLER_EXACT_HITS sampler2D
#define TD_OUTPUT_EXACT_HITS vec4
#define TD_CHANNEL_SHADOW_MASK GL_RGBA16, GL_RGBA, GL_UNSIGNED_SHORT  // ray grid, 2 layers: raster shadows' visibility per light
#define TD_SAMPLER_SHADOW_MASK sampler2DArray
#define TD_OUTPUT_SHADOW_MASK vec4                                 // its second layer (the first: the pass's outColor)
#define TD_CHANNEL_SHADOW_PROOFS GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT  // full res: a proof word (above)
#define TD_OUTPUT_SHADOW_PROOFS uint
#define TD_CHANNEL_LINEAR GL_RGBA32F, GL_RGBA, GL_FLOAT          // linear radiance, full res
#define TD_SAMPLER_LINEAR sampler2D
#define TD_OUTPUT_LINEAR vec4                                     // the shade pass's output (probes' too)
// The filter's channels (frame size): the shade pass writes the first three when the filter is on.
// Packed texels: shaders/denoise.glsl.
#define TD_CHANNEL_DENOISE_NOISY GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT  // the shade pass's sampled radiance / modulation
#define TD_SAMPLER_DENOISE_NOISY sampler2D
#define TD_CHANNEL_DENOISE_GUIDE GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT  // depth, normal + instance, modulation
#define TD_SAMPLER_DENOISE_GUIDE usampler2D
#define TD_OUTPUT_DENOISE_GUIDE uvec4
#define TD_CHANNEL_DENOISE_MOTION GL_RGBA32F, GL_RGBA, GL_FLOAT  // motion (pixels, GL rows), depth before, 1: in the last frame's view (-1: the background)
#define TD_SAMPLER_DENOISE_MOTION sampler2D
#define TD_OUTPUT_DENOISE_MOTION vec4
#define TD_CHANNEL_DENOISE_EXACT GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT  // radiance past the filter (sharp mirrors, glass)
#define TD_SAMPLER_DENOISE_EXACT sampler2D
#define TD_OUTPUT_DENOISE_EXACT vec4
#define TD_CHANNEL_DENOISE_TEXEL GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT  // illumination, variance, depth, normal
#define TD_SAMPLER_DENOISE_TEXEL usampler2D
#define TD_OUTPUT_DENOISE_TEXEL uvec4
#define TD_CHANNEL_DENOISE_MOMENTS GL_RGBA32F, GL_RGBA, GL_FLOAT      // luminance, its square, history length
#define TD_SAMPLER_DENOISE_MOMENTS sampler2D
#define TD_OUTPUT_DENOISE_MOMENTS vec4
#define TD_CHANNEL_DENOISE_RADIANCE GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT // the filtered frame; the anti-aliased one
#define TD_SAMPLER_DENOISE_RADIANCE sampler2D
#define TD_OUTPUT_DENOISE_RADIANCE vec4
#define TD_CHANNEL_DISPLAY GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE   // tone-mapped sRGB, full res
#define TD_OUTPUT_DISPLAY vec4
#define TD_CHANNEL_PROBES GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT     // reflection probe cubes
#define TD_SAMPLER_PROBES samplerCubeArray
#define TD_CHANNEL_SHADOW_MAPS GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT  // maps and cube maps
#define TD_SAMPLER_SHADOW_MAPS sampler2DArrayShadow
#define TD_SAMPLER_SHADOW_CUBES samplerCubeArrayShadow
#define TD_SAMPLER_SHADOW_CUBES_DEPTH samplerCubeArray

// ---- channel bits the shade pass is compiled for ----
#define TD_RAY_LIGHT_MASK 1     // TD_RAY_INPUTS: which ray results were uploaded
#define TD_RAY_REFLECTED 2
#define TD_RAY_TRANSMITTED 4
#define TD_PROBE_REFLECT 1      // TD_PROBES: which effects the probes stand in for
#define TD_PROBE_REFRACT 2
#define TD_PROBE_BEHIND 4       // IOR-1 transmission reads the view behind (TD_UNIT_BEHIND) at its own pixel
#define TD_DISTANCE_FAR 65504.0  // TD_DISTANCE_ALPHA's distance of the sky: half precision's largest

#endif
