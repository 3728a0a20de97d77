// Adaptive anti-aliasing's choice of pixels (render/Adaptive.h), from hand-made sample ranges: the pixels
// whose samples disagree by more than the threshold and their 8 neighbours, and the rays grown by a coarse
// grid's reach. Worked out here from the rule docs/antialiasing.md states.
#include <gtest/gtest.h>

#include <string>

#include "render/Adaptive.h"

namespace tandem {
namespace {

struct Samples {
  int w, h;
  std::vector<float> lo, hi;
  std::vector<std::uint32_t> count;
  Samples(int width, int height)
      : w(width), h(height), lo(std::size_t(width * height), 0.3f), hi(std::size_t(width * height), 0.3f),  // agreeing
        count(std::size_t(width * height), 4u) {}
  void spread(int x, int y, float range) { hi[std::size_t(y * w + x)] = lo[std::size_t(y * w + x)] + range; }
};

/// The mask as rows of '#' and '.', for readable failures.
std::string picture(const std::vector<std::uint8_t>& m, int w, int h) {
  std::string s;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) s += m[std::size_t(y * w + x)] ? '#' : '.';
    s += '\n';
  }
  return s;
}

std::vector<std::uint8_t> square(int w, int h, int cx, int cy, int r) {
  std::vector<std::uint8_t> m(std::size_t(w * h), 0);
  for (int y = std::max(0, cy - r); y <= std::min(h - 1, cy + r); ++y)
    for (int x = std::max(0, cx - r); x <= std::min(w - 1, cx + r); ++x) m[std::size_t(y * w + x)] = 1;
  return m;
}

TEST(Adaptive, ARoundRefinesThePixelsThatDisagreeAndTheirNeighbours) {
  // A thin slanted line: in some pixels along it the first four samples caught it (they disagree), in the
  // pixel between two of those they all missed it (it agrees, at the background). The neighbours of the
  // disagreeing pixels are refined, so the missed one is sampled again; nothing farther is.
  Samples s(12, 9);
  s.spread(4, 3, 0.4f);
  s.spread(6, 5, 0.4f);  // (5, 4) between them missed the line
  std::vector<std::uint8_t> refine, traced;
  ASSERT_TRUE(adaptiveRound(s.lo, s.hi, s.count, s.w, s.h, 0.05f, 1, refine, traced));
  std::vector<std::uint8_t> expected = square(s.w, s.h, 4, 3, 1), other = square(s.w, s.h, 6, 5, 1);
  for (std::size_t i = 0; i < expected.size(); ++i) expected[i] |= other[i];
  EXPECT_EQ(picture(refine, s.w, s.h), picture(expected, s.w, s.h));
  EXPECT_TRUE(refine[std::size_t(4 * s.w + 5)]) << "the pixel whose first samples all missed the line";
  EXPECT_EQ(traced, refine) << "a full-resolution ray grid traces exactly the refined pixels";
}

TEST(Adaptive, TheThresholdIsAStrictBoundOnTheSamplesRange) {
  Samples s(5, 5);
  s.spread(2, 2, 0.25f);  // exactly the threshold (0.3 + 0.25 − 0.3 is 0.25 in float): agrees
  std::vector<std::uint8_t> refine, traced;
  EXPECT_FALSE(adaptiveRound(s.lo, s.hi, s.count, s.w, s.h, 0.25f, 1, refine, traced));
  EXPECT_EQ(std::count(refine.begin(), refine.end(), 1), 0);
  s.spread(2, 2, 0.2501f);
  EXPECT_TRUE(adaptiveRound(s.lo, s.hi, s.count, s.w, s.h, 0.25f, 1, refine, traced));
  EXPECT_EQ(std::count(refine.begin(), refine.end(), 1), 9);
  // A pixel with no samples yet says nothing (its range is empty: lo = +inf, hi = -inf in the Renderer).
  Samples none(5, 5);
  none.count[12] = 0;
  none.lo[12] = 0.0f;
  none.hi[12] = 1.0f;
  EXPECT_FALSE(adaptiveRound(none.lo, none.hi, none.count, none.w, none.h, 0.05f, 1, refine, traced));
}

TEST(Adaptive, ACoarseRayGridTracesWhatItBlendsIntoTheRefinedPixels) {
  // At rayScale 2 a pixel's shading blends ray-grid samples up to 2 grid pixels (4 pixels) away: the rays
  // traced are the refined pixels grown by 2·rayScale, clipped at the frame's edges.
  Samples s(20, 15);
  s.spread(10, 7, 0.3f);
  std::vector<std::uint8_t> refine, traced;
  ASSERT_TRUE(adaptiveRound(s.lo, s.hi, s.count, s.w, s.h, 0.05f, 2, refine, traced));
  EXPECT_EQ(picture(refine, s.w, s.h), picture(square(s.w, s.h, 10, 7, 1), s.w, s.h));
  EXPECT_EQ(picture(traced, s.w, s.h), picture(square(s.w, s.h, 10, 7, 1 + 4), s.w, s.h));
  Samples corner(20, 15);
  corner.spread(0, 0, 0.3f);
  ASSERT_TRUE(adaptiveRound(corner.lo, corner.hi, corner.count, corner.w, corner.h, 0.05f, 4, refine, traced));
  EXPECT_EQ(picture(traced, corner.w, corner.h), picture(square(corner.w, corner.h, 0, 0, 1 + 8), corner.w, corner.h));
}

TEST(Adaptive, DisplayLuminanceIsTheToneMappedExposedLuminanceSquareRooted) {
  FrameSettings s;
  s.toneMap = ToneMap::None;
  s.exposure = 2.0f;
  EXPECT_NEAR(displayLuminance(glm::vec3(0.1f, 0.2f, 0.05f), s), std::sqrt(2.0f * (0.2126f * 0.1f + 0.7152f * 0.2f + 0.0722f * 0.05f)), 1e-6f);
  EXPECT_EQ(displayLuminance(glm::vec3(0.0f), s), 0.0f);
}

}  // namespace
}  // namespace tandem
