#pragma once
// The GL binding points, texture units, channel formats and channel bits as C++ constants, from the one
// table the shaders include (shaders/bindings.glsl).
#include "gl/Gl.h"
#include "../../../shaders/bindings.glsl"

namespace tandem::gl {

inline constexpr GLuint kBindPositions = TD_BIND_POSITIONS, kBindNormals = TD_BIND_NORMALS, kBindUvs = TD_BIND_UVS,
                        kBindColors = TD_BIND_COLORS, kBindIndices = TD_BIND_INDICES, kBindMeshes = TD_BIND_MESHES,
                        kBindInstances = TD_BIND_INSTANCES, kBindMaterials = TD_BIND_MATERIALS,
                        kBindLights = TD_BIND_LIGHTS, kBindUvTransforms = TD_BIND_UV_TRANSFORMS,
                        kBindResolved = TD_BIND_RESOLVED;
inline constexpr GLuint kBlockLights = TD_BLOCK_LIGHTS, kBlockMaterials = TD_BLOCK_MATERIALS,
                        kBlockShadows = TD_BLOCK_SHADOWS;
inline constexpr GLuint kUnitIds = TD_UNIT_IDS, kUnitDepth = TD_UNIT_DEPTH, kUnitKd = TD_UNIT_KD,
                        kUnitRamps = TD_UNIT_RAMPS, kUnitLinear = TD_UNIT_LINEAR;
inline constexpr GLuint kUnitPositionsTex = TD_UNIT_POSITIONS_TEX, kUnitNormalsTex = TD_UNIT_NORMALS_TEX,
                        kUnitUvsTex = TD_UNIT_UVS_TEX, kUnitColorsTex = TD_UNIT_COLORS_TEX,
                        kUnitIndicesTex = TD_UNIT_INDICES_TEX, kUnitMeshesTex = TD_UNIT_MESHES_TEX,
                        kUnitInstancesTex = TD_UNIT_INSTANCES_TEX, kUnitInstanceIdsTex = TD_UNIT_INSTANCE_IDS_TEX,
                        kUnitUvTransformsTex = TD_UNIT_UV_TRANSFORMS_TEX;
inline constexpr GLuint kUnitShadowMaps = TD_UNIT_SHADOW_MAPS, kUnitShadowCubes = TD_UNIT_SHADOW_CUBES,
                        kUnitShadowCubesDepth = TD_UNIT_SHADOW_CUBES_DEPTH,
                        kUnitProbes = TD_UNIT_PROBES;
inline constexpr GLuint kUnitTangentsTex = TD_UNIT_TANGENTS_TEX, kUnitNormalMaps = TD_UNIT_NORMAL_MAPS;
inline constexpr GLuint kUnitRadiosityTableTex = TD_UNIT_RADIOSITY_TABLE_TEX, kUnitRadiosityTex = TD_UNIT_RADIOSITY_TEX;
inline constexpr GLuint kUnitExactHits = TD_UNIT_EXACT_HITS;
inline constexpr GLuint kUnitMotionInstances = TD_UNIT_MOTION_INSTANCES;
inline constexpr GLuint kUnitPreviousIds = TD_UNIT_PREVIOUS_IDS;
inline constexpr GLuint kUnitPreviousDepth = TD_UNIT_PREVIOUS_DEPTH;
inline constexpr GLuint kUnitShadowMask = TD_UNIT_SHADOW_MASK;
inline constexpr GLuint kUnitEnvironment = TD_UNIT_ENVIRONMENT;
inline constexpr GLuint kUnitBehind = TD_UNIT_BEHIND, kUnitPeelDepth = TD_UNIT_PEEL_DEPTH;
inline constexpr GLuint kUnitProofTexels = TD_UNIT_PROOF_TEXELS, kUnitProofTriangles = TD_UNIT_PROOF_TRIANGLES,
                        kUnitProofNear = TD_UNIT_PROOF_NEAR, kUnitProofInstances = TD_UNIT_PROOF_INSTANCES,
                        kUnitProofFlags = TD_UNIT_PROOF_FLAGS;
inline constexpr GLuint kBlockProofMaps = TD_BLOCK_PROOF_MAPS;

/// A frame channel's GL internal format, and the pixel format and type of its CPU copies (docs/gbuffer.md).
struct ChannelFormat {
  GLenum internal;
  GLenum transfer;
  GLenum type;
};
// The ray grid's channels (light mask, area-light samples, reflected, transmitted) are rows of
// gl/RayChannels.h, which reads their units, formats and bits from the table directly.
inline constexpr ChannelFormat kChannelIds{TD_CHANNEL_IDS}, kChannelDepth{TD_CHANNEL_DEPTH},
                               kChannelLinear{TD_CHANNEL_LINEAR}, kChannelDisplay{TD_CHANNEL_DISPLAY},
                               kChannelProbes{TD_CHANNEL_PROBES}, kChannelShadowMaps{TD_CHANNEL_SHADOW_MAPS},
                               kChannelExactHits{TD_CHANNEL_EXACT_HITS}, kChannelShadowMask{TD_CHANNEL_SHADOW_MASK},
                               kChannelShadowProofs{TD_CHANNEL_SHADOW_PROOFS};
/// Which effects the probes stand in for (ShadeInputs::probeEffects), the shade pass's TD_PROBES.
enum ProbeEffect : int { kProbeReflect = TD_PROBE_REFLECT, kProbeRefract = TD_PROBE_REFRACT, kProbeBehind = TD_PROBE_BEHIND };

}  // namespace tandem::gl
