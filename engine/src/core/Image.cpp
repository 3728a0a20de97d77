#include "tandem/Image.h"

#include <cstring>

#include <stb_image.h>
#include <stb_image_write.h>

namespace tandem {

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

Result<void> writePng(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != std::size_t(image.width) * image.height * 4)
    return Error{"cannot write " + path + ": the image is empty or its size does not match its pixels"};
  if (!stbi_write_png(path.c_str(), image.width, image.height, 4, image.rgba.data(), image.width * 4))
    return Error{"cannot write " + path + ": the file could not be created or written"};
  return {};
}

Result<Image> readPng(const std::string& path) {
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  if (!data) return Error{"cannot read " + path + ": " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown")};
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.assign(data, data + std::size_t(w) * h * 4);
  stbi_image_free(data);
  return img;
}

}  // namespace tandem
