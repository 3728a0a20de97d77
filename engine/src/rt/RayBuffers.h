#pragma once
// What the ray pass reads and writes per frame: the visibility ids in, the ray results out (RayTracer,
// PixelTrace and the Renderer share them).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/FrameStats.h"
#include "tandem/Scene.h"

namespace tandem::rt {

/// The raster pass's visibility channel read back to memory: per pixel (row 0 = top),
/// x = instance index + 1 (0 = background), y = triangle index within that instance's mesh.
struct VisibilityBuffer {
  int width = 0;
  int height = 0;
  std::vector<glm::uvec2> ids;
  /// The GL's shadow proofs (gl/ShadowProofPass.h) of each pixel's primary hit, beside its id: bit 8 + j set
  /// where light j's shadow ray is decided, bit j its answer (lit); kProofComplete: bits 0-7 are the pixel's
  /// whole light mask, bits 16-23 the lights whose ray it answers, and the hit spawns no ray (shaders/
  /// bindings.glsl, TD_PROOF_*). Empty: none (every ray is the pass's).
  std::vector<std::uint32_t> proofs;
};

/// VisibilityBuffer::proofs: the word's layout (bindings.glsl's TD_PROOF_*, checked where the GL reads them).
inline constexpr int kProofDecidedShift = 8, kProofNeededShift = 16;
inline constexpr std::uint32_t kProofComplete = 0x80000000u;

/// Bit j: direct light j visible. Eight bits are enough: a scene has at most kMaxLights (8) lights, and
/// the GL channel is 8 bits too (bindings.glsl), a quarter of the bytes a 32-bit mask would upload.
using LightMask = std::uint8_t;
static_assert(kMaxLights <= 8, "a light mask holds one bit per light");

/// Ray results on the ray grid. A vector is empty when its effect traced no ray this frame
/// (cost follows the scene and the settings).
struct RayOutputs {
  int width = 0;
  int height = 0;
  // bit j: direct light j (Scene::directLights()) unoccluded. Set without a ray where no ray is needed:
  // lights with castShadows = false, and lights that cannot reach the point (behind the surface, outside
  // a spot cone, beyond range: the shading formula gives them nothing anyway, toon's lowest band aside,
  // which therefore looks as with shadows off). So an empty mask means exactly "all lights visible".
  std::vector<LightMask> lightMask;
  // Area lights' sample bits, one plane of the grid per area light (FrameShading::areaSlot): word
  // a·width·height + g has bit k set where sample k of that light is unoccluded at grid pixel g. Filled with
  // lightMask where shadows are by rays and the scene has area lights; empty otherwise.
  std::vector<std::uint32_t> areaSamples;
  int areaLights = 0;
  std::uint32_t areaLightBits = 0;  // bit j: direct light j is an area light (whose plane is its rank among them)
  // rgb: weighted reflected radiance (wR·S), linear; a = 1 where a ray was traced. Zero elsewhere.
  std::vector<glm::vec4> reflected;
  std::vector<glm::vec4> transmitted;    // the same for the weighted transmitted radiance (wT·T)
  // Per kTile × kTile tile of the grid (rt/Parallel.h; row-major, tileCount(width) tiles a row), whether
  // the tile holds a non-zero texel in reflected / transmitted: the rest of the channel is exactly zero, so
  // the upload sends only these tiles (reflective surfaces cover a fraction of a frame). Sized with
  // their channel; empty when the channel is, or when whoever filled the channel did not say.
  std::vector<std::uint8_t> reflectedTiles;
  std::vector<std::uint8_t> transmittedTiles;
  int tileSize = 0;  // texels per tile side (kTile)
  RayCounts counts;
  int threads = 0;
};

}  // namespace tandem::rt
