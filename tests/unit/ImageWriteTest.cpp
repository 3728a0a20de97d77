// writeImage: the bytes on disk are the format the file name says (tandem-render -o x.jpg used to write
// PNG bytes under a .jpg name), and a name whose format no writer produces is refused before writing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "support/TestSupport.h"
#include "tandem/Image.h"

namespace tandem {
namespace {

namespace fs = std::filesystem;

Image gradient(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.set(x, y, {static_cast<std::uint8_t>(x * 255 / (w - 1)), static_cast<std::uint8_t>(y * 255 / (h - 1)), 96, 255});
  return img;
}

std::vector<unsigned char> fileBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::string fresh(const std::string& name) {
  std::string path = test::outputDir() + "/" + name;
  fs::remove(path);
  return path;
}

TEST(ImageWrite, FormatFollowsTheExtensionInAnyCase) {
  EXPECT_EQ(*imageFormatForPath("a/b.png"), ImageFormat::Png);
  EXPECT_EQ(*imageFormatForPath("b.PNG"), ImageFormat::Png);
  EXPECT_EQ(*imageFormatForPath("b.jpg"), ImageFormat::Jpeg);
  EXPECT_EQ(*imageFormatForPath("b.JPEG"), ImageFormat::Jpeg);
  EXPECT_EQ(*imageFormatForPath("dir.png/b.Jpg"), ImageFormat::Jpeg);
}

TEST(ImageWrite, UnknownOrMissingExtensionIsAnErrorNamingThePath) {
  auto bmp = imageFormatForPath("out/frame.bmp");
  ASSERT_FALSE(bmp);
  EXPECT_NE(bmp.error().message.find("out/frame.bmp"), std::string::npos) << bmp.error().message;
  EXPECT_NE(bmp.error().message.find("'.bmp'"), std::string::npos) << bmp.error().message;
  auto none = imageFormatForPath("out/frame");
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("no file extension"), std::string::npos) << none.error().message;
}

TEST(ImageWrite, JpgNameGetsJpegBytesThatDecodeToTheImage) {
  const Image img = gradient(64, 32);
  for (const char* name : {"image-write.jpg", "image-write.JPEG"}) {
    std::string path = fresh(name);
    ASSERT_TRUE(writeImage(path, img)) << name;
    std::vector<unsigned char> bytes = fileBytes(path);
    ASSERT_GE(bytes.size(), 3u);
    EXPECT_EQ(bytes[0], 0xFF);  // JPEG SOI marker, then the first segment's marker
    EXPECT_EQ(bytes[1], 0xD8);
    EXPECT_EQ(bytes[2], 0xFF);
    auto back = readPng(path);  // stb_image decodes JPEG too
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->width, 64);
    ASSERT_EQ(back->height, 32);
    // Lossy, so close rather than equal: a smooth gradient at quality 95 stays within a few levels.
    int worst = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(back->rgba[i + c]) - int(img.rgba[i + c])));
    EXPECT_LE(worst, 12) << name;
  }
}

TEST(ImageWrite, PngNameGetsPngBytes) {
  std::string path = fresh("image-write.png");
  ASSERT_TRUE(writeImage(path, gradient(8, 8)));
  std::vector<unsigned char> bytes = fileBytes(path);
  const unsigned char signature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  ASSERT_GE(bytes.size(), sizeof signature);
  EXPECT_TRUE(std::equal(std::begin(signature), std::end(signature), bytes.begin()));
}

TEST(ImageWrite, RefusedNameWritesNothing) {
  std::string path = fresh("image-write.bmp");
  auto r = writeImage(path, gradient(8, 8));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace tandem
