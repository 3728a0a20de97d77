#pragma once
// The ray pass's results as the shade pass reads them: one row per channel of the ray grid (docs/gbuffer.md,
// its rows "light mask" to "area-light samples"). The shade pass's textures, their uploads (whole, tile by
// tile, or one layer per area light), the texture units they are bound to, the placeholder an absent one
// gets, and the TD_RAY_* bit that tells the shader it is there all follow this table.
//
// A new ray-pass channel is: its CPU copy in rt::RayOutputs (written by the ray pass), a row here and its
// unit, format and sampler in shaders/bindings.glsl, its data in render's rayGridData (Renderer.cpp), its
// use in shaders/shade_rays.glsl, and its row in docs/gbuffer.md.
#include <array>
#include <cstddef>
#include <span>

#include "gl/Bindings.h"
#include "gl/Placeholders.h"

namespace tandem::gl {

enum class RayChannelId : int { LightMask, AreaSamples, Reflected, Transmitted };

struct RayChannel {
  RayChannelId id;
  const char* label;        // the texture's GL debug label, and what an error names
  int input;                // RayInput bit: the variant reads it (TD_RAY_INPUTS), the frame holds it (rayPresent)
  GLuint unit;
  ChannelFormat format;
  Placeholders::Kind placeholder;  // what the unit holds when the frame has no such data
  bool perAreaLight;        // a 2D array, one layer per area light (present only in scenes with area lights)
  bool tiled;               // sent tile by tile (GridTiles): only the tiles that hold something
};

inline constexpr std::array<RayChannel, 4> kRayChannels{{
    {RayChannelId::LightMask, "ray light mask", kRayLightMask, kUnitLightMask, kChannelLightMask,
     Placeholders::Uint2D, false, false},
    {RayChannelId::AreaSamples, "ray area-light samples", kRayLightMask, kUnitAreaSamples, kChannelAreaSamples,
     Placeholders::Uint2DArray, true, false},
    {RayChannelId::Reflected, "ray reflected", kRayReflected, kUnitReflected, kChannelReflected, Placeholders::Float2D,
     false, true},
    {RayChannelId::Transmitted, "ray transmitted", kRayTransmitted, kUnitTransmitted, kChannelTransmitted,
     Placeholders::Float2D, false, true},
}};
inline constexpr std::size_t kRayChannelCount = kRayChannels.size();

constexpr bool rayChannelsInOrder() {
  for (std::size_t i = 0; i < kRayChannelCount; ++i)
    if (static_cast<std::size_t>(kRayChannels[i].id) != i) return false;
  return true;
}
static_assert(rayChannelsInOrder(), "kRayChannels[i] is channel i: the uploads index them by RayChannelId");
constexpr bool tiledChannelsTravelAsReflectedDoes() {
  for (const RayChannel& c : kRayChannels)
    if (c.tiled && !(c.format.transfer == kChannelReflected.transfer && c.format.type == kChannelReflected.type))
      return false;
  return true;
}
// ShadePass.cpp pins kChannelReflected to one glm::vec4 per grid pixel, which its tile uploads assume.
static_assert(tiledChannelsTravelAsReflectedDoes(), "a tiled channel travels as one glm::vec4 per grid pixel");

/// Which square tiles of a ray grid hold a non-zero value (RayOutputs::reflectedTiles): `size` texels a
/// side, row-major, one flag per tile; the rest of the grid is zero. Empty: unknown, the whole grid is sent.
struct GridTiles {
  std::span<const std::uint8_t> nonZero;
  int size = 0;
};

/// One channel's CPU copy for an upload: its texels on the grid (row 0 = top, as RayOutputs holds them;
/// null: the frame has none), its layers (perAreaLight channels), its tiles (tiled channels).
struct RayGridData {
  const void* texels = nullptr;
  int layers = 1;
  GridTiles tiles;
};
using RayGrid = std::array<RayGridData, kRayChannelCount>;

}  // namespace tandem::gl
