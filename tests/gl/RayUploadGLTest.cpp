// The ray pass's results reach the shade pass tile by tile (ShadePass::uploadReflected with GridTiles):
// only tiles that hold something are sent, and tiles that held something last time are zeroed. Whatever
// the sequence of frames, the texture must equal the grid last uploaded, to the bit.
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
    ASSERT_TRUE(pass->uploadReflected(r.width, r.height, r.texels.data(), rt).ok());
    ASSERT_TRUE(pass->uploadTransmitted(t.width, t.height, t.texels.data(), tt).ok());
    expectTextureHolds(pass->reflectedTexture(), r, "reflected");
    expectTextureHolds(pass->transmittedTexture(), t, "transmitted");
  }
}

}  // namespace
}  // namespace tandem
