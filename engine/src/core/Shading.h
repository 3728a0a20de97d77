#pragma once
// The C++ twin of shaders/shading.glsl: the same source text compiled with glm, so the CPU ray pass
// and the GLSL shade every point with one definition of each formula.
#include <cmath>
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::shading {

using uint = std::uint32_t;  // GLSL's uint: the hashes and sample sequences wrap the same way
using glm::clamp;
using glm::cross;
using glm::dot;
using glm::floor;
using glm::ivec3;
using glm::normalize;
using glm::max;
using glm::min;
using glm::mix;
using glm::pow;
using glm::reflect;
using glm::smoothstep;
using glm::sqrt;
using glm::uvec2;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using std::sqrt;
using std::pow;
using std::abs;
using std::cos;
using std::sin;
using std::exp;
using std::acos;
// GLSL's two-argument atan.
inline float atan(float y, float x) { return std::atan2(y, x); }

#define TD_OUT(T) T&
#define TD_FN inline
#include "../../../shaders/shading.glsl"
#undef TD_FN
#undef TD_OUT

static_assert(sizeof(GpuLight) == 7 * 16, "GpuLight must match its std430 layout");
static_assert(sizeof(GpuMaterial) == 9 * 16, "GpuMaterial must match its std430 layout");

/// Packs the scene's records the same way for GL (SSBO upload) and the CPU twin.
/// `areaSlot`: an area light's place among the frame's area lights (Scene::areaLightSlots), the layer of
/// its sample visibility.
GpuLight packLight(const Light& light, int areaSlot = 0);
/// The radius of a sphere about an area light's posW that holds every point of it: a shadow ray from a point to
/// any of them stays within that radius times its fraction of the way from the ray to posW (the filter's test
/// of what moved, render/Motion.cpp). A rect's corners lie half its diagonal away, bounded here by half the sum
/// of its sides (half the longer side does not reach them: the filter's square pyramid still covers the corners
/// of a rect along the frame's axes, not those of one turned in its plane); a disk's bound is twice its
/// radius, a sphere's its radius. 0 for a light without extent.
float areaLightReach(const Light& light);
GpuMaterial packMaterial(const Material& material, int materialIndex, std::optional<ShadingModel> override);
/// The toon ramp of a material sampled at TD_TOON_RAMP_SIZE points over N·L in [-1, 1]: the 1D texture
/// GL samples with nearest filtering, and the table the CPU reads.
void bakeToonRamp(const Material& material, float* out /* TD_TOON_RAMP_SIZE */);
/// Index into a baked ramp for N·L, the same texel GL's nearest filtering picks.
inline int toonRampIndex(float nl) {
  float t = glm::clamp(nl * 0.5f + 0.5f, 0.0f, 1.0f);
  int i = static_cast<int>(t * TD_TOON_RAMP_SIZE);
  return i >= TD_TOON_RAMP_SIZE ? TD_TOON_RAMP_SIZE - 1 : i;
}
inline int toneMapOp(ToneMap t) { return static_cast<int>(t); }

}  // namespace tandem::shading
