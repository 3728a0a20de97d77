// The ray pass's results reach the shade pass by the channel table (gl/RayChannels.h, ShadePass::uploadRays):
// the tiled channels tile by tile (only tiles that hold something are sent, and tiles that held something
// last time are zeroed), the light mask whole, the area lights' samples one layer per light. Whatever the
// sequence of frames, each texture must equal what was last uploaded, to the bit; a channel a frame leaves
// out keeps what it held.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "GlTestUtil.h"
#include "gl/ShadePass.h"

namespace tandem {
namespace {

struct Grid {
  int width = 0, height = 0, tile = 16;
  std::vector<glm::vec4> texels;
  std::vector<std::uint8_t> flags;  // per tile: holds a texel that is not all +0
};

// A grid where each tile is, at random, all zero or holds values (a few tiles only -0.0, which is not +0).
Grid randomGrid(std::mt19937& rng, int width, int height, float fill) {
  Grid g{width, height, 16, std::vector<glm::vec4>(static_cast<std::size_t>(width) * height, glm::vec4(0.0f)), {}};
  const int tilesX = (width + g.tile - 1) / g.tile, tilesY = (height + g.tile - 1) / g.tile;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int ty = 0; ty < tilesY; ++ty)
    for (int tx = 0; tx < tilesX; ++tx) {
      const float pick = u(rng);
      const bool full = pick < fill, negativeZero = !full && pick < fill + 0.05f;
      g.flags.push_back(full || negativeZero ? 1 : 0);
      if (!full && !negativeZero) continue;
      for (int y = ty * g.tile; y < std::min((ty + 1) * g.tile, height); ++y)
        for (int x = tx * g.tile; x < std::min((tx + 1) * g.tile, width); ++x)
          g.texels[static_cast<std::size_t>(y) * width + x] =
              full ? glm::vec4(u(rng), u(rng) * 3.0f, u(rng) * 1e-6f, 1.0f) : glm::vec4(-0.0f, 0.0f, 0.0f, 0.0f);
    }
  return g;
}

void expectTextureHolds(const gl::Texture& texture, const Grid& g, const char* what) {
  std::vector<glm::vec4> got(g.texels.size(), glm::vec4(7.0f));
  glGetTextureImage(texture.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(got.size() * sizeof(glm::vec4)), got.data());
  int wrong = 0;
  for (std::size_t i = 0; i < got.size(); ++i)
    if (std::memcmp(&got[i], &g.texels[i], sizeof(glm::vec4)) != 0 && ++wrong <= 5)
      ADD_FAILURE() << what << ": texel " << i % g.width << "," << i / g.width << " is (" << got[i].x << ", " << got[i].y
                    << ", " << got[i].z << ", " << got[i].w << ")";
  EXPECT_EQ(wrong, 0) << what;
}

TEST(RayUpload, TileByTileUploadsLeaveTheTextureEqualToTheGrid) {
  TD_REQUIRE_GL_CONTEXT();
  auto pass = gl::ShadePass::create();
  ASSERT_TRUE(pass.ok());
  std::mt19937 rng(7);
  // Partial tiles at the right and bottom edges; frames that fill more, less, then nothing; a size change;
  // a whole-grid upload (no flags) followed by tiled ones.
  struct Step {
    int width, height;
    float fill;
    bool tiled;
  } steps[] = {{75, 41, 0.3f, true},  {75, 41, 0.6f, true}, {75, 41, 0.1f, true}, {75, 41, 0.0f, true},
               {75, 41, 0.4f, false}, {75, 41, 0.2f, true}, {50, 50, 0.5f, true}, {50, 50, 0.2f, true}};
  for (const Step& step : steps) {
    SCOPED_TRACE(std::to_string(step.width) + "x" + std::to_string(step.height) + " fill " + std::to_string(step.fill) +
                 (step.tiled ? " tiled" : " whole"));
    const Grid r = randomGrid(rng, step.width, step.height, step.fill);
    const Grid t = randomGrid(rng, step.width, step.height, step.fill);
    const gl::GridTiles rt = step.tiled ? gl::GridTiles{r.flags, r.tile} : gl::GridTiles{};
    const gl::GridTiles tt = step.tiled ? gl::GridTiles{t.flags, t.tile} : gl::GridTiles{};
    const std::size_t n = static_cast<std::size_t>(step.width) * static_cast<std::size_t>(step.height);
    std::vector<std::uint8_t> mask(n);
    for (std::uint8_t& m : mask) m = static_cast<std::uint8_t>(rng() & 0xFFu);
    const int areaLights = step.width == 50 ? 3 : 2;  // the layer count changes with the size
    std::vector<std::uint32_t> samples(n * static_cast<std::size_t>(areaLights));
    for (std::uint32_t& b : samples) b = static_cast<std::uint32_t>(rng());
    gl::RayGrid grid;
    grid[std::size_t(gl::RayChannelId::Reflected)] = {r.texels.data(), 1, rt};
    grid[std::size_t(gl::RayChannelId::Transmitted)] = {t.texels.data(), 1, tt};
    grid[std::size_t(gl::RayChannelId::LightMask)] = {mask.data(), 1, {}};
    grid[std::size_t(gl::RayChannelId::AreaSamples)] = {samples.data(), areaLights, {}};
    auto sent = pass->uploadRays(step.width, step.height, grid);
    ASSERT_TRUE(sent.ok());
    EXPECT_EQ(*sent, gl::kRayLightMask | gl::kRayReflected | gl::kRayTransmitted);
    expectTextureHolds(pass->rayTexture(gl::RayChannelId::Reflected), r, "reflected");
    expectTextureHolds(pass->rayTexture(gl::RayChannelId::Transmitted), t, "transmitted");
    std::vector<std::uint8_t> gotMask(n, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);  // 75 one-byte texels a row: no padding
    glGetTextureImage(pass->rayTexture(gl::RayChannelId::LightMask).id(), 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE,
                      static_cast<GLsizei>(gotMask.size()), gotMask.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    EXPECT_TRUE(gotMask == mask) << "light mask";
    std::vector<std::uint32_t> gotSamples(samples.size(), 0);
    glGetTextureImage(pass->rayTexture(gl::RayChannelId::AreaSamples).id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT,
                      static_cast<GLsizei>(gotSamples.size() * sizeof(std::uint32_t)), gotSamples.data());
    EXPECT_TRUE(gotSamples == samples) << "area-light samples, " << areaLights << " layers";
  }
  // A frame without reflections or area lights: those channels are left as they were, the others sent.
  const Grid keep = randomGrid(rng, 50, 50, 0.5f);
  gl::RayGrid some;
  some[std::size_t(gl::RayChannelId::Transmitted)] = {keep.texels.data(), 1, {}};
  auto sent = pass->uploadRays(50, 50, some);
  ASSERT_TRUE(sent.ok());
  EXPECT_EQ(*sent, gl::kRayTransmitted);
  expectTextureHolds(pass->rayTexture(gl::RayChannelId::Transmitted), keep, "transmitted, alone");
}

}  // namespace
}  // namespace tandem
