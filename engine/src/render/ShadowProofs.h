#pragma once
// The hybrid shadows' maps (rt::ShadowCertainty, the CPU's) as the GL's shadow-proof pass copies them
// (gl::ProofSource): plain spans of the maps' records and the triangles' tests, packed as the shader reads them.
#include "gl/ShadowProofPass.h"
#include "rt/ShadowCertainty.h"
#include "tandem/Scene.h"

namespace tandem {

/// `maps` must outlive the result (its texel records are referenced, not copied). Instances of exact solids
/// are never proved (their pixels' hits are the resolve step's, not the raster's triangle).
gl::ProofSource proofSource(const rt::ShadowCertainty& maps, const Scene& scene);

}  // namespace tandem
