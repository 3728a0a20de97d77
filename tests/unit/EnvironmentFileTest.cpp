// Environment images and the scene file's "environment" (docs/environment.md, docs/scene-format.md): readHdr
// reads what stb_image_write's Radiance writer wrote, refuses other formats, cut and oversized files by name; the
// scene file's sky and image, and its errors by JSON path. A JSON scene without the key keeps its background.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <stb/stb_image_write.h>

#include "support/TestSupport.h"
#include "tandem/Image.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

std::string outPath(const std::string& name) { return test::outputDir() + "/" + name; }

// A w x h Radiance file whose texel (x, y) is (x + 1, y + 1, 0.5) / 4.
std::string writeHdr(const std::string& name, int w, int h) {
  std::vector<float> rgb;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) rgb.insert(rgb.end(), {float(x + 1) / 4.0f, float(y + 1) / 4.0f, 0.125f});
  const std::string path = outPath(name);
  EXPECT_TRUE(stbi_write_hdr(path.c_str(), w, h, 3, rgb.data()));
  return path;
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

TEST(EnvironmentFile, ARadianceImageReadsBackItsTexelsTopRowFirst) {
  const std::string path = writeHdr("env-8x4.hdr", 8, 4);
  Result<ImageF> img = readHdr(path);
  ASSERT_TRUE(img) << img.error().message;
  ASSERT_EQ(img->width, 8);
  ASSERT_EQ(img->height, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const glm::vec3 want(float(x + 1) / 4.0f, float(y + 1) / 4.0f, 0.125f);
      // RGBE keeps 8 bits of mantissa under a shared exponent.
      EXPECT_LT(glm::length(img->at(x, y) - want), 0.01f * glm::length(want)) << x << "," << y;
    }
  Result<std::shared_ptr<const EnvironmentMap>> map = loadEnvironmentMap(path);
  ASSERT_TRUE(map) << map.error().message;
  EXPECT_EQ((*map)->width(), 8);
  EXPECT_EQ((*map)->texels().size(), 32u);
}

TEST(EnvironmentFile, OtherFormatsCutFilesAndHugeImagesAreRefusedByName) {
  Image png;
  png.width = png.height = 2;
  png.rgba.assign(16, 200);
  const std::string pngPath = outPath("env-not-hdr.png");
  ASSERT_TRUE(writePng(pngPath, png));
  Result<ImageF> r = readHdr(pngPath);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("not a Radiance .hdr image"), std::string::npos) << r.error().message;

  EXPECT_FALSE(readHdr(outPath("env-missing.hdr")));

  // The header of a real file, its texels cut off half way.
  const std::string whole = bytesOf(writeHdr("env-64x32.hdr", 64, 32));
  const std::string cut = outPath("env-cut.hdr");
  writeBytes(cut, whole.substr(0, whole.size() / 2));
  r = readHdr(cut);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("cut short"), std::string::npos) << r.error().message;
  // Cut right after a run-length row's start, where its first count is due.
  const std::string cutAtCount = outPath("env-cut-at-count.hdr");
  writeBytes(cutAtCount, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n" + std::string("\x02\x02\x00\x08", 4));
  r = readHdr(cutAtCount);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("row 0: the texels are cut short"), std::string::npos) << r.error().message;
  // A run-length row whose count is zero (stb_image 2.27 loops on it for ever): refused, naming the row.
  const std::string zero = outPath("env-zero-run.hdr");
  writeBytes(zero, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n" + std::string("\x02\x02\x00\x08\x00", 5));
  r = readHdr(zero);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("row 0: a run-length count of 0"), std::string::npos) << r.error().message;

  // A header declaring 100000 x 100000 texels over a few bytes: refused before any is decoded.
  const std::string huge = outPath("env-huge.hdr");
  writeBytes(huge, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n" + std::string(64, '\x01'));
  r = readHdr(huge);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("more than the limit"), std::string::npos) << r.error().message;
  // A height whose product with the width wraps a 64-bit count to nothing (2^61 x 8 = 2^64).
  const std::string wraps = outPath("env-wraps.hdr");
  writeBytes(wraps, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2305843009213693952 +X 8\n" + std::string(64, '\x01'));
  r = readHdr(wraps);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("more than the limit"), std::string::npos) << r.error().message;
  // Written on Windows: CRLF line ends are read.
  const std::string crlf = outPath("env-crlf.hdr");
  writeBytes(crlf, "#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 1 +X 2\r\n" + std::string("\x80\x80\x80\x81\x80\x80\x80\x81", 8));
  r = readHdr(crlf);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->at(1, 0), glm::vec3(1.0f));
  // Wider than a texture may be, though few texels in all.
  const std::string wide = outPath("env-wide.hdr");
  writeBytes(wide, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 9000\n" + std::string(64, '\x01'));
  r = readHdr(wide);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("8192 wide"), std::string::npos) << r.error().message;
}

Result<Scene> parse(const std::string& environment) {
  const std::string text = R"({"meshes": {"s": {"primitive": "sphere"}}, "materials": {"m": {}},
      "instances": [{"mesh": "s", "material": "m"}], "background": [0.1, 0.2, 0.3])" +
                           (environment.empty() ? std::string() : ", \"environment\": " + environment) + "}";
  return parseSceneJson(text, "t.json", test::outputDir());
}

void expectError(const std::string& environment, const std::string& path, const std::string& reason) {
  Result<Scene> r = parse(environment);
  ASSERT_FALSE(r) << environment;
  EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find(reason), std::string::npos) << r.error().message;
}

TEST(EnvironmentFile, TheSceneFileGivesASkyOrAnImageAndKeepsItsBackgroundWithoutOne) {
  Result<Scene> plain = parse("");
  ASSERT_TRUE(plain) << plain.error().message;
  EXPECT_EQ(plain->environment.kind, Environment::Kind::Background);

  Result<Scene> sky = parse(R"({"zenith": [0.2, 0.3, 0.9], "intensity": 2, "rotation": -45, "ambient": false})");
  ASSERT_TRUE(sky) << sky.error().message;
  EXPECT_EQ(sky->environment.kind, Environment::Kind::Sky);
  EXPECT_EQ(sky->environment.zenith, glm::vec3(0.2f, 0.3f, 0.9f));
  EXPECT_EQ(sky->environment.horizon, Environment{}.horizon);
  EXPECT_EQ(sky->environment.intensity, 2.0f);
  EXPECT_EQ(sky->environment.rotationDeg, -45.0f);
  EXPECT_FALSE(sky->environment.lightsAmbient);

  writeHdr("env-scene.hdr", 16, 8);
  Result<Scene> image = parse(R"({"image": "env-scene.hdr", "rotation": 90})");
  ASSERT_TRUE(image) << image.error().message;
  EXPECT_EQ(image->environment.kind, Environment::Kind::Map);
  ASSERT_TRUE(image->environment.map);
  EXPECT_EQ(image->environment.map->width(), 16);
  EXPECT_TRUE(image->environment.lightsAmbient);

  expectError(R"({"image": "env-scene.hdr", "zenith": [1, 1, 1]})", "/environment/zenith", "no sky colours");
  expectError(R"({"image": "env-absent.hdr"})", "/environment/image", "not a regular file");
  expectError(R"({"image": "env-not-hdr.png"})", "/environment/image", "not a Radiance .hdr image");
  expectError(R"({"sun": true})", "/environment", "sun");
  expectError(R"({"intensity": -1})", "/environment/intensity", "must be in [0, 1e+06], got -1");
  expectError(R"({"horizon": [1, -1, 0]})", "/environment/horizon/1", "must be >= 0, got -1");
  expectError(R"("sky")", "/environment", "expected an object");
}

}  // namespace
}  // namespace tandem
