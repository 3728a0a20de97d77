#include "tandem/Image.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>

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

namespace {
// An untrusted image file's size, refused when it is not a regular file or is over kMaxImageFileBytes.
Result<std::uint64_t> imageFileBytes(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{"cannot read " + path + ": not a regular file"};
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) return Error{"cannot read " + path + ": " + ec.message()};
  if (bytes > kMaxImageFileBytes)
    return Error{"cannot read " + path + ": " + std::to_string(bytes) + " bytes, more than the limit of " +
                 std::to_string(kMaxImageFileBytes)};
  return std::uint64_t(bytes);
}
}  // namespace

Result<Image> readPng(const std::string& path, std::uint64_t maxPixels) {
  // Untrusted files: the size and the declared dimensions are checked before anything is decoded, and the
  // decoder's memory is capped (a zlib stream can inflate far past its rows).
  Result<std::uint64_t> size = imageFileBytes(path);
  if (!size) return size.error();
  const std::uint64_t fileBytes = *size;
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

namespace {

// Radiance RGBE (Greg Ward's format, the one .hdr environment images use), decoded here rather than by
// stb_image: Debian's stb_image 2.27 loops for ever on a run-length scanline cut off by the end of the file
// (a zero count advances nothing), and a hostile file must not hang the loader. Every read is bounded here.
class HdrReader {
 public:
  explicit HdrReader(const std::string& bytes) : b_(bytes) {}

  Result<ImageF> read() {
    std::string line;
    if (!nextLine(line) || (line != "#?RADIANCE" && line != "#?RGBE"))
      return Error{"not a Radiance .hdr image (environment images are .hdr files)"};
    for (;;) {  // header lines up to an empty one
      if (!nextLine(line)) return Error{"the header has no end"};
      if (line.empty()) break;
      if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe") {
        const std::string shown = line.substr(0, 60);
        return Error{"'" + shown + "': only FORMAT=32-bit_rle_rgbe is read"};
      }
    }
    if (!nextLine(line)) return Error{"no resolution line"};
    char ySign = 0, xSign = 0, yAxis = 0, xAxis = 0;
    long h = 0, w = 0;
    char rest = 0;
    if (std::sscanf(line.c_str(), "%c%c %ld %c%c %ld %c", &ySign, &yAxis, &h, &xSign, &xAxis, &w, &rest) != 6 ||
        ySign != '-' || yAxis != 'Y' || xSign != '+' || xAxis != 'X') {
      const std::string shown = line.substr(0, 60);
      return Error{"resolution '" + shown + "': only the standard orientation (-Y height +X width) is read"};
    }
    // (h bounded by the pixels over w before any product: a height near 2^61 would wrap it to nothing)
    if (w <= 0 || h <= 0 || w > kMaxHdrWidth || std::uint64_t(h) > kMaxHdrPixels / std::uint64_t(w))
      return Error{std::to_string(w) + "x" + std::to_string(h) + " texels, more than the limit of " +
                   std::to_string(kMaxHdrWidth) + " wide and " + std::to_string(kMaxHdrPixels) + " in all"};
    ImageF img;
    img.width = int(w);
    img.height = int(h);
    img.rgb.resize(std::size_t(w) * std::size_t(h));
    std::vector<std::uint8_t> scan(std::size_t(w) * 4);
    for (long y = 0; y < h; ++y) {
      if (auto r = scanline(scan, int(w)); !r) return Error{"row " + std::to_string(y) + ": " + r.error().message};
      for (long x = 0; x < w; ++x) {
        const std::uint8_t* e = &scan[std::size_t(x) * 4];
        const float f = e[3] == 0 ? 0.0f : std::ldexp(1.0f, int(e[3]) - 136);
        img.rgb[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
            glm::min(glm::vec3(float(e[0]), float(e[1]), float(e[2])) * f, glm::vec3(1e6f));
      }
    }
    return img;
  }

 private:
  bool nextLine(std::string& line) {
    const std::size_t end = b_.find('\n', at_);
    if (end == std::string::npos || end - at_ > 4096) return false;
    line.assign(b_, at_, end - at_);
    if (!line.empty() && line.back() == '\r') line.pop_back();  // written on Windows
    at_ = end + 1;
    return true;
  }
  bool byte(std::uint8_t& out) {
    if (at_ >= b_.size()) return false;
    out = static_cast<std::uint8_t>(b_[at_++]);
    return true;
  }
  // One row as RGBE quadruples: run-length encoded per channel (rows 8..32767 wide that start 2, 2), else flat.
  Result<void> scanline(std::vector<std::uint8_t>& scan, int w) {
    const Error cut{"the texels are cut short"};
    if (at_ + 4 > b_.size()) return cut;
    const auto* p = reinterpret_cast<const std::uint8_t*>(b_.data() + at_);
    const bool rle = w >= 8 && w <= 32767 && p[0] == 2 && p[1] == 2 && (p[2] & 0x80) == 0;
    if (!rle) {
      if (b_.size() - at_ < std::size_t(w) * 4) return cut;
      std::memcpy(scan.data(), b_.data() + at_, std::size_t(w) * 4);
      at_ += std::size_t(w) * 4;
      return {};
    }
    if ((int(p[2]) << 8 | int(p[3])) != w) return Error{"a run-length row's width is not the image's"};
    at_ += 4;
    for (int c = 0; c < 4; ++c)
      for (int x = 0; x < w;) {
        std::uint8_t count = 0, value = 0;
        if (!byte(count)) return cut;
        const bool run = count > 128;
        const int n = run ? count - 128 : count;
        if (n == 0 || n > w - x) return Error{"a run-length count of " + std::to_string(n) + " where " +
                                              std::to_string(w - x) + " texels are left"};
        if (run && !byte(value)) return cut;
        for (int k = 0; k < n; ++k, ++x) {
          if (!run && !byte(value)) return cut;
          scan[std::size_t(x) * 4 + std::size_t(c)] = value;
        }
      }
    return {};
  }

  const std::string& b_;
  std::size_t at_ = 0;
};

}  // namespace

Result<ImageF> readHdr(const std::string& path) {
  Result<std::uint64_t> size = imageFileBytes(path);
  if (!size) return size.error();
  const std::uint64_t fileBytes = *size;
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<std::size_t>(fileBytes), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    return Error{"cannot read " + path + ": the file could not be read"};
  Result<ImageF> img = HdrReader(bytes).read();
  if (!img) return Error{"cannot read " + path + ": " + img.error().message};
  return img;
}

}  // namespace tandem
