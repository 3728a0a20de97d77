// Raster shadows on the ray grid (gl/ShadePass.h: the shadow-mask pass, rayScale > 1): every grid pixel holds
// the lookup the full-resolution frame makes at the pixel it stands for, for every light (lights 4-7 in the
// mask's second layer), and the frame between grid pixels stays close to the full-resolution one.
#include <gtest/gtest.h>

#include <cmath>

#include "GlTestUtil.h"

namespace tandem {
namespace {

constexpr int kW = 256, kH = 144;

// A floor with three posts and a ball, lit by seven direct lights of every kind a shadow map serves (points:
// cube maps; spots: 2D maps; a directional; a sphere lamp: soft shadows), each from a place of its own so
// each casts its shadows elsewhere; the fifth and sixth sit in the mask's second layer.
Scene manyLights() {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(10.0f), 10), makeBox(glm::vec3(0.4f, 1.6f, 0.4f)), makeSphere(0.6f, 32, 16)};
  s.materials = {gltest::plainMaterial({0.8f, 0.8f, 0.75f}), gltest::plainMaterial({0.6f, 0.3f, 0.2f}),
                 gltest::plainMaterial({0.2f, 0.4f, 0.7f})};
  s.instances.clear();
  Instance floor;
  s.instances.push_back(floor);
  for (glm::vec3 at : {glm::vec3(-1.5f, 0.8f, 0.0f), glm::vec3(1.2f, 0.8f, -1.0f), glm::vec3(0.3f, 0.8f, 1.6f)}) {
    Instance post;
    post.mesh = 1;
    post.material = 1;
    post.worldFromObject = glm::translate(glm::mat4(1.0f), at);
    s.instances.push_back(post);
  }
  Instance ball;
  ball.mesh = 2;
  ball.material = 2;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.9f, 0.0f));
  s.instances.push_back(ball);

  s.lights.clear();
  auto add = [&](LightType type, glm::vec3 posW, glm::vec3 towards) {
    Light l;
    l.type = type;
    l.intensity = 0.35f;
    l.posW = posW;
    l.dirW = glm::normalize(towards - posW);
    l.innerConeDeg = 30.0f;
    l.outerConeDeg = 40.0f;
    l.radius = 0.4f;
    s.lights.push_back(l);
  };
  add(LightType::Point, {-3.0f, 3.0f, 1.0f}, {});
  add(LightType::Point, {3.0f, 3.0f, -1.0f}, {});
  add(LightType::Spot, {0.0f, 5.0f, 3.0f}, {0.0f, 0.0f, 0.0f});
  add(LightType::Directional, {}, {0.3f, -1.0f, 0.2f});
  s.lights.back().dirW = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  add(LightType::Point, {2.0f, 2.5f, 3.0f}, {});
  add(LightType::Spot, {-2.0f, 4.0f, -2.0f}, {0.5f, 0.0f, 0.5f});
  add(LightType::Sphere, {0.0f, 4.0f, 0.0f}, {});
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.intensity = 0.1f;
  s.lights.push_back(ambient);
  s.camera.posW = {0.0f, 6.0f, 7.0f};
  s.camera.targetW = {0.0f, 0.0f, 0.0f};
  return s;
}

// The raster preset, linear radiance out (no tone map), at ray scale `scale`.
FrameSettings rasterAt(int scale) {
  FrameSettings s = *presetSettings("raster");
  s.width = kW;
  s.height = kH;
  s.toneMap = ToneMap::None;
  s.rayScale = scale;
  return s;
}

ImageF drawLinear(gltest::SceneFrame& f, const FrameSettings& s) {
  gltest::drawFrame(f, s);
  return f.renderer->readLinear();
}

glm::vec3 at(const ImageF& image, int x, int y) {
  return image.rgb[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)];
}

// The interior grid pixels of a 2× grid: full-resolution pixel (2g + 1) stands for grid pixel g.
template <typename F>
void forEachGridPixel(F&& f) {
  for (int gy = 0; gy + 1 < kH / 2; ++gy)
    for (int gx = 0; gx + 1 < kW / 2; ++gx) f(2 * gx + 1, 2 * gy + 1);
}

TEST(ShadowMaskGL, GridPixelsHoldTheFullResolutionLookupOfEveryLight) {
  TD_REQUIRE_GL_CONTEXT();
  auto f = gltest::sceneFrame(*glContext_, manyLights(), kW, kH);
  ASSERT_NE(f.renderer, nullptr);
  const ImageF full = drawLinear(f, rasterAt(1));
  const ImageF grid = drawLinear(f, rasterAt(2));
  ASSERT_EQ(full.rgb.size(), grid.rgb.size());
  int compared = 0, off = 0;
  float worst = 0.0f;
  forEachGridPixel([&](int x, int y) {
    const glm::vec3 a = at(grid, x, y), b = at(full, x, y);
    ++compared;
    for (int c = 0; c < 3; ++c) {
      // The mask holds visibility in 16 bits: at most 2^-17 of each light's contribution off.
      const float d = std::abs(a[c] - b[c]);
      worst = std::max(worst, d);
      if (d > 1e-4f + 1e-4f * std::abs(b[c])) {
        ++off;
        break;
      }
    }
  });
  EXPECT_EQ(off, 0) << "of " << compared << " grid pixels, worst difference " << worst;

  // Each light's shadows reach the compared pixels, those of the second layer's lights too: without its
  // shadows the frame differs there.
  for (std::size_t j : {std::size_t{4}, std::size_t{5}, std::size_t{6}}) {
    Scene unshadowed = manyLights();
    unshadowed.lights[j].castShadows = false;
    auto g = gltest::sceneFrame(*glContext_, std::move(unshadowed), kW, kH);
    ASSERT_NE(g.renderer, nullptr);
    const ImageF without = drawLinear(g, rasterAt(2));
    int differ = 0;
    forEachGridPixel([&](int x, int y) { differ += glm::length(at(without, x, y) - at(grid, x, y)) > 1e-3f ? 1 : 0; });
    EXPECT_GT(differ, 100) << "light " << j << "'s shadows are not in the compared pixels";
  }
}

TEST(ShadowMaskGL, BetweenGridPixelsTheFrameStaysCloseToTheFullResolutionOne) {
  TD_REQUIRE_GL_CONTEXT();
  auto f = gltest::sceneFrame(*glContext_, manyLights(), kW, kH);
  ASSERT_NE(f.renderer, nullptr);
  FrameSettings full = rasterAt(1), grid = rasterAt(2);
  full.toneMap = grid.toneMap = ToneMap::Aces;
  const Image a = gltest::drawFrame(f, grid);
  const Image b = gltest::drawFrame(f, full);
  gltest::savePng("shadow-mask-grid.png", a);
  gltest::savePng("shadow-mask-full.png", b);
  // Shadow edges blur over a grid pixel and soft shadows' per-pixel noise averages over four: the two differ
  // there and nowhere else. Measured 2026-11-27 (llvmpipe): FLIP 0.0039, 0.22 % of pixels more than 8 levels
  // off; a mask read one pixel off its grid centre gives 0.0083 and 0.62 %.
  int far = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      if (std::abs(int(a.rgba[i + c]) - int(b.rgba[i + c])) > 8) {
        ++far;
        break;
      }
  const double farFraction = static_cast<double>(far) / static_cast<double>(kW * kH);
  const double flip = gltest::flipMean(a, b);
  std::printf("shadow mask at 1/2: FLIP %.5f against full resolution, %.3f %% of pixels more than 8 levels off\n",
              flip, 100.0 * farFraction);
  EXPECT_LT(flip, 0.008);
  EXPECT_LT(farFraction, 0.005);
}

}  // namespace
}  // namespace tandem
