// The anti-aliasing sample sequence (core/Sampling.h): inside the pixel, stratified in every aligned block
// (the property the adaptive test's first four samples and any accumulation length rely on).
#include <gtest/gtest.h>

#include <set>

#include "core/Sampling.h"
#include "tandem/Camera.h"

namespace tandem {
namespace {

TEST(Sampling, SubpixelJitterStaysInsideThePixel) {
  for (std::uint32_t i = 0; i < 4096; ++i) {
    const glm::vec2 j = subpixelJitter(i);
    EXPECT_GE(j.x, -0.5f);
    EXPECT_LT(j.x, 0.5f);
    EXPECT_GE(j.y, -0.5f);
    EXPECT_LT(j.y, 0.5f);
  }
}

TEST(Sampling, EveryAlignedBlockIsANet) {
  // 4^k samples from a multiple of 4^k: one in each of the 2^k × 2^k cells, one in each of the 4^k columns
  // and one in each of the 4^k rows.
  for (int k = 1; k <= 3; ++k) {
    const std::uint32_t n = 1u << (2 * k), side = 1u << k;
    for (std::uint32_t start = 0; start < 4 * n; start += n) {
      std::set<std::uint32_t> cells, columns, rows;
      for (std::uint32_t i = start; i < start + n; ++i) {
        const glm::vec2 u = subpixelJitter(i) + 0.5f;
        const auto fs = static_cast<float>(side), fn = static_cast<float>(n);
        cells.insert(static_cast<std::uint32_t>(u.x * fs) * side + static_cast<std::uint32_t>(u.y * fs));
        columns.insert(static_cast<std::uint32_t>(u.x * fn));
        rows.insert(static_cast<std::uint32_t>(u.y * fn));
      }
      EXPECT_EQ(cells.size(), n) << "k " << k << " from " << start;
      EXPECT_EQ(columns.size(), n) << "k " << k << " from " << start;
      EXPECT_EQ(rows.size(), n) << "k " << k << " from " << start;
    }
  }
}

TEST(Sampling, TheFirstFourAreOffTheCentreAndTheCorners) {
  // A pattern through the centre or a corner would sample a corner shared by four pixels, or leave a
  // third of the pixel between samples; these four are a quarter pixel apart in x and in y.
  std::set<float> xs, ys;
  for (std::uint32_t i = 0; i < 4; ++i) {
    const glm::vec2 j = subpixelJitter(i);
    EXPECT_EQ(std::abs(j.x) == 0.125f || std::abs(j.x) == 0.375f, true) << j.x;
    EXPECT_EQ(std::abs(j.y) == 0.125f || std::abs(j.y) == 0.375f, true) << j.y;
    xs.insert(j.x);
    ys.insert(j.y);
  }
  EXPECT_EQ(xs.size(), 4u);
  EXPECT_EQ(ys.size(), 4u);
}

TEST(Sampling, AJitteredCameraProjectsItsRaysOntoTheirSamplePoints) {
  // The rasterizer's projection (clipFromView(size)) and the camera ray (rayThroughPixel) move together:
  // a point on the jittered ray through pixel centre c lands at c + jitter in pixels.
  for (bool ortho : {false, true}) {
    Camera c;
    c.orthographic = ortho;
    c.posW = glm::vec3(1.0f, 2.0f, 3.0f);
    c.targetW = glm::vec3(0.0f, 0.5f, -1.0f);
    c.jitterPx = glm::vec2(0.3f, -0.45f);
    const glm::ivec2 size(64, 48);
    for (glm::vec2 px : {glm::vec2(0.5f), glm::vec2(31.5f, 20.5f), glm::vec2(63.5f, 47.5f)}) {
      const Ray r = c.rayThroughPixel(px, size);
      const glm::vec4 clip = c.clipFromView(size) * c.viewFromWorld() * glm::vec4(r.origin + 7.0f * r.dir, 1.0f);
      const glm::vec2 ndc = glm::vec2(clip) / clip.w;
      const glm::vec2 landed((ndc.x + 1.0f) * 0.5f * float(size.x), (1.0f - ndc.y) * 0.5f * float(size.y));
      EXPECT_NEAR(landed.x, px.x, 2e-3f) << (ortho ? "ortho" : "perspective");
      EXPECT_NEAR(landed.y, px.y, 2e-3f) << (ortho ? "ortho" : "perspective");
      Camera plain = c;
      plain.jitterPx = glm::vec2(0.0f);
      const Ray moved = plain.rayThroughPixel(px + c.jitterPx, size);
      EXPECT_EQ(moved.dir, r.dir);
      EXPECT_EQ(moved.origin, r.origin);
    }
  }
}

}  // namespace
}  // namespace tandem
