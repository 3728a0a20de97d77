#pragma once
// The hybrid shadows' maps (rt::ShadowCertainty, the CPU's) as the GL's shadow-proof pass copies them
// (gl::ProofSource): plain spans of the maps' records and the triangles' tests, packed as the shader reads them.
#include "gl/ShadowProofPass.h"
#include "rt/ShadowCertainty.h"
#include <cstdint>
#include <vector>

#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem {

/// `maps` must outlive the result (its texel records are referenced, not copied). Instances of exact solids
/// are never proved (their pixels' hits are the resolve step's, not the raster's triangle).
gl::ProofSource proofSource(const rt::ShadowCertainty& maps, const Scene& scene);

/// Per instance, TD_PROOF_PLAIN where its material spawns no ray (no kr, no kt, not BLEND) and shades with the
/// geometric or interpolated vertex normal (no normal map, no bump), and TD_PROOF_FLAT where its model (or
/// the frame's override) is flat: what the proof pass needs to give a pixel's whole light mask.
std::vector<std::uint32_t> proofInstanceFlags(const Scene& scene, const FrameSettings& settings);

}  // namespace tandem
