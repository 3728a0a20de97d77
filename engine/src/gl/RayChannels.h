#pragma once
// The ray pass's results as the shade pass reads them: one row per channel of the ray grid (docs/gbuffer.md,
// its rows "light mask" to "area-light samples"). The shade pass's textures, their uploads (whole, tile by
// tile, or one layer per area light), the texture units they are bound to, the placeholder an absent one
// gets, the TD_RAY_* bit that tells the shader it is there, and the C++ type its CPU copy must have all
// follow this table.
//
// A new ray-pass channel touches four engine files: its CPU copy in rt::RayOutputs (rt/RayBuffers.h) and
// the ray pass that writes it (rt/RayTracer.cpp's tiles), a row here (with its TD_RAY_* bit below), and
// render/Renderer.cpp (rayGridData hands it over with setRayGrid; the plan's flag sets its bit in
// rayChannels). Beside them: its unit, format, sampler and bit in shaders/bindings.glsl, its sampler and
// use in the shade pass (shade.frag, shade_rays.glsl), and its row in docs/gbuffer.md (cli.channel-table).
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "gl/Bindings.h"
#include "gl/GlObjects.h"
#include "gl/Placeholders.h"

namespace tandem::gl {

/// Which ray results a frame uploaded (ShadeInputs::rayInputs), the shade pass's TD_RAY_INPUTS.
enum RayInput : int { kRayLightMask = TD_RAY_LIGHT_MASK, kRayReflected = TD_RAY_REFLECTED, kRayTransmitted = TD_RAY_TRANSMITTED };

enum class RayChannelId : int { LightMask, AreaSamples, Reflected, Transmitted };

struct RayChannel {
  RayChannelId id;
  const char* label;        // the texture's GL debug label, and what an error names
  int input;                // RayInput bit: the variant reads it (TD_RAY_INPUTS), the frame holds it (rayPresent)
  GLuint unit;              // TD_UNIT_*
  ChannelFormat format;     // TD_CHANNEL_*
  Placeholders::Kind placeholder;  // what the unit holds when the frame has no such data
  bool perAreaLight;        // a 2D array, one layer per area light (present only in scenes with area lights)
  bool tiled;               // sent tile by tile (GridTiles): only the tiles that hold something
  std::size_t texelBytes;   // one texel of the CPU copy: sizeof the element of its RayOutputs vector
};

inline constexpr std::array<RayChannel, 4> kRayChannels{{
    {RayChannelId::LightMask, "ray light mask", kRayLightMask, TD_UNIT_LIGHT_MASK, {TD_CHANNEL_LIGHT_MASK},
     Placeholders::Uint2D, false, false, sizeof(std::uint8_t)},
    {RayChannelId::AreaSamples, "ray area-light samples", kRayLightMask, TD_UNIT_AREA_SAMPLES,
     {TD_CHANNEL_AREA_SAMPLES}, Placeholders::Uint2DArray, true, false, sizeof(std::uint32_t)},
    {RayChannelId::Reflected, "ray reflected", kRayReflected, TD_UNIT_REFLECTED, {TD_CHANNEL_REFLECTED},
     Placeholders::Float2D, false, true, sizeof(float) * 4},
    {RayChannelId::Transmitted, "ray transmitted", kRayTransmitted, TD_UNIT_TRANSMITTED, {TD_CHANNEL_TRANSMITTED},
     Placeholders::Float2D, false, true, sizeof(float) * 4},
}};
inline constexpr std::size_t kRayChannelCount = kRayChannels.size();
constexpr const RayChannel& rayChannel(RayChannelId id) { return kRayChannels[static_cast<std::size_t>(id)]; }

constexpr bool rayChannelsWellFormed() {
  for (std::size_t i = 0; i < kRayChannelCount; ++i) {
    const RayChannel& c = kRayChannels[i];
    if (static_cast<std::size_t>(c.id) != i) return false;  // the uploads index them by RayChannelId
    // The CPU copy is what the transfer format and type say, and the frame-size check can count the texture.
    if (transferBytes(c.format) != c.texelBytes || texelBytes(c.format.internal) == 0) return false;
    if (c.tiled && c.texelBytes != sizeof(float) * 4) return false;  // ShadePass's tile uploads: one vec4 a texel
  }
  return true;
}
static_assert(rayChannelsWellFormed(),
              "kRayChannels: row i is channel i, its CPU texel is its transfer's, a tiled channel travels as vec4s");

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

/// Hands `texels` (a RayOutputs vector: one element per grid pixel, and per layer) to channel `Id` of `grid`;
/// the element's type must be the row's texel, which is checked where the channel is handed over.
template <RayChannelId Id, class T>
void setRayGrid(RayGrid& grid, const std::vector<T>& texels, int layers = 1, GridTiles tiles = {}) {
  static_assert(sizeof(T) == rayChannel(Id).texelBytes, "a ray channel's CPU copy is not its row's texel type");
  grid[static_cast<std::size_t>(Id)] = {texels.data(), layers, tiles};
}

}  // namespace tandem::gl
