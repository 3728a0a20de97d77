#pragma once
// CPU images. Image is 8-bit RGBA (display-encoded, what a PNG holds); ImageF is linear float RGB.
// Row 0 is the top of the image.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Result.h"

namespace tandem {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // width*height*4
  glm::u8vec4 at(int x, int y) const;
  void set(int x, int y, glm::u8vec4 c);
};

struct ImageF {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> rgb;  // width*height, linear
  glm::vec3& at(int x, int y) { return rgb[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec3& at(int x, int y) const { return rgb[static_cast<std::size_t>(y) * width + x]; }
};

/// Image file formats the writers produce.
enum class ImageFormat : std::uint8_t { Png, Jpeg };

/// The format a file name asks for, by its extension in any case: .png → PNG, .jpg / .jpeg → JPEG.
/// Any other extension (or none) is an error naming the path, so a caller can refuse an output name
/// before spending time on the image, instead of writing bytes its extension misdescribes.
Result<ImageFormat> imageFormatForPath(const std::string& path);
/// Writes `image` in the format its path's extension names (imageFormatForPath). JPEG has no alpha
/// channel (it is dropped) and is written at quality 95.
Result<void> writeImage(const std::string& path, const Image& image);
/// Writes PNG bytes whatever the extension (for callers that choose their own names, e.g. goldens).
Result<void> writePng(const std::string& path, const Image& image);
/// Files larger than this are refused by readPng before reading.
constexpr std::uint64_t kMaxImageFileBytes = 256ull << 20;
/// Reads a PNG (or any 8-bit image stb_image decodes: JPEG, BMP, TGA...). The file may be hostile: its size,
/// its declared dimensions (at most maxPixels) and the decoder's memory (imageDecodeBytes) are bounded, so
/// peak memory is at most the file plus 16 bytes per declared pixel plus 1 MiB (docs/scene-format.md).
Result<Image> readPng(const std::string& path, std::uint64_t maxPixels = 16384ull * 16384ull);
/// Largest environment image readHdr takes: 8192 texels wide (an "8k" equirectangular image; GL's smallest
/// texture limit in practice) and 8192 × 4096 texels in all.
constexpr int kMaxHdrWidth = 8192;
constexpr std::uint64_t kMaxHdrPixels = 8192ull * 4096ull;
/// Reads a Radiance .hdr (RGBE, flat or run-length rows, the standard -Y H +X W orientation) as linear float
/// RGB, row 0 at the top. The file's size and declared dimensions are bounded before any texel is decoded and
/// every read is checked (a cut or corrupt file is an error naming the row); other formats are refused by
/// name. Texels are kept within [0, 1e6] (an RGBE exponent reaches 1e38, which sums would overflow).
Result<ImageF> readHdr(const std::string& path);
/// The memory cap for decoding an image of `pixels` declared pixels from `encodedBytes` bytes.
std::uint64_t imageDecodeBytes(std::uint64_t pixels, std::uint64_t encodedBytes);

}  // namespace tandem
