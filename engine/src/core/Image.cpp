#include "tandem/Image.h"

#include <cctype>
#include <cstring>
#include <filesystem>

#include <stb_image.h>
#include <stb_image_write.h>

#include "core/StbGuard.h"

namespace tandem {

std::uint64_t imageDecodeBytes(std::uint64_t pixels, std::uint64_t encodedBytes) {
  // The RGBA8 result (4/pixel), PNG's inflated rows (up to 8/pixel for 16-bit RGBA, plus a filter byte per
  // row) or a progressive JPEG's coefficients (6/pixel), the encoded bytes, and 1 MiB of tables.
  return 16 * pixels + encodedBytes + (1u << 20);
}

glm::u8vec4 Image::at(int x, int y) const {
  const std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

void Image::set(int x, int y, glm::u8vec4 c) {
  std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  p[0] = c.r;
  p[1] = c.g;
  p[2] = c.b;
  p[3] = c.a;
}

namespace {

Result<void> checkWritable(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != std::size_t(image.width) * image.height * 4)
    return Error{"cannot write " + path + ": the image is empty or its size does not match its pixels"};
  return {};
}

// Quality 95: visually lossless for renders, which are mostly smooth gradients and hard edges.
constexpr int kJpegQuality = 95;

}  // namespace

Result<ImageFormat> imageFormatForPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
  return Error{path + ": " + (ext.empty() ? std::string("no file extension") : "unsupported extension '" + ext + "'") +
               " (expected .png, .jpg or .jpeg)"};
}

Result<void> writeImage(const std::string& path, const Image& image) {
  auto format = imageFormatForPath(path);
  if (!format) return Error{"cannot write " + format.error().message};
  if (*format == ImageFormat::Png) return writePng(path, image);
  if (auto r = checkWritable(path, image); !r) return r;
  if (!stbi_write_jpg(path.c_str(), image.width, image.height, 4, image.rgba.data(), kJpegQuality))
    return Error{"cannot write " + path + ": the file could not be created or written"};
  return {};
}

Result<void> writePng(const std::string& path, const Image& image) {
  if (auto r = checkWritable(path, image); !r) return r;
  if (!stbi_write_png(path.c_str(), image.width, image.height, 4, image.rgba.data(), image.width * 4))
    return Error{"cannot write " + path + ": the file could not be created or written"};
  return {};
}

Result<Image> readPng(const std::string& path, std::uint64_t maxPixels) {
  // Untrusted files: the size and the declared dimensions are checked before anything is decoded, and the
  // decoder's memory is capped (a zlib stream can inflate far past its rows).
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{"cannot read " + path + ": not a regular file"};
  const std::uintmax_t fileBytes = std::filesystem::file_size(path, ec);
  if (ec) return Error{"cannot read " + path + ": " + ec.message()};
  if (fileBytes > kMaxImageFileBytes)
    return Error{"cannot read " + path + ": " + std::to_string(fileBytes) + " bytes, more than the limit of " +
                 std::to_string(kMaxImageFileBytes)};
  int w = 0, h = 0, n = 0;
  if (!stbi_info(path.c_str(), &w, &h, &n))
    return Error{"cannot read " + path + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown")};
  const std::uint64_t pixels = std::uint64_t(w) * std::uint64_t(h);
  if (w <= 0 || h <= 0 || pixels > maxPixels)
    return Error{"cannot read " + path + ": " + std::to_string(w) + "x" + std::to_string(h) +
                 " pixels, more than the limit of " + std::to_string(maxPixels)};
  StbMemoryCap cap(imageDecodeBytes(pixels, fileBytes));
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  if (!data)
    return Error{"cannot read " + path + ": " +
                 (cap.refused() ? std::string("decoding needs more memory than the image's size allows")
                                : std::string(stbi_failure_reason() ? stbi_failure_reason() : "unknown"))};
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.assign(data, data + std::size_t(w) * h * 4);
  stbi_image_free(data);
  return img;
}

}  // namespace tandem
