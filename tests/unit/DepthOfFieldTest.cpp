// The thin lens (Camera::aperture, focusDistance, lensUv; core/Sampling.h lensSample, squareToDisk,
// nestedShuffle): a lens point's pinhole keeps the plane in focus on its pixels and moves everything else by
// the circle of confusion's geometry, at every scale and far from the origin; the lens samples cover the lens
// as a net in every prefix, unrelated to the sub-pixel offsets drawn with them.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/RenderSpace.h"
#include "core/Sampling.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem {
namespace {

// Where a world point lands in a camera's frame of `size`, in pixels (y down), as the rasterizer puts it: in
// render space around `anchor` (core/RenderSpace.h), as the frame does far from the origin.
glm::dvec2 projectPx(const Camera& world, glm::ivec2 size, glm::vec3 pointW, glm::vec3 anchor = glm::vec3(0.0f)) {
  const Camera c = toRenderSpace(world, anchor);
  const glm::vec3 p = toRenderSpace(pointW, anchor);
  const glm::dvec4 clip = glm::dmat4(c.clipFromView(size)) * glm::dmat4(c.viewFromWorld()) * glm::dvec4(p, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {(ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y};
}

struct Basis {
  glm::vec3 forward, right, up;
};
Basis basis(const Camera& c) {
  Basis b;
  b.forward = glm::normalize(c.targetW - c.posW);
  b.right = glm::normalize(glm::cross(b.forward, c.upW));
  b.up = glm::cross(b.right, b.forward);
  return b;
}

TEST(NestedShuffle, KeepsEveryAlignedBlockAndShufflesWithinIt) {
  for (std::uint32_t seed : {0u, 1u, 0x6A09E667u, 0xFFFFFFFFu}) {
    for (int k = 0; k <= 10; ++k) {
      const std::uint32_t n = 1u << k;
      for (std::uint32_t start : {0u, n, 7u * n, 0xFFFFFFFFu - (n - 1u)}) {
        std::set<std::uint32_t> low;
        const std::uint32_t high = nestedShuffle(start, seed) >> k << k;
        for (std::uint32_t i = start; i - start < n; ++i) {
          const std::uint32_t v = nestedShuffle(i, seed);
          EXPECT_EQ(v >> k << k, high) << "k " << k << " index " << i;  // the same aligned block
          low.insert(v & (n - 1u));
        }

        EXPECT_EQ(low.size(), n) << "k " << k << ": a permutation of the block";
      }
    }
  }
  // And it does shuffle: the first 16 are not the identity nor a fixed XOR of it.
  int moved = 0;
  for (std::uint32_t i = 0; i < 16; ++i) moved += nestedShuffle(i, 0x6A09E667u) != (nestedShuffle(0, 0x6A09E667u) ^ i);
  EXPECT_GT(moved, 4);
}

TEST(LensSample, EveryPrefixIsANetOnTheLensSquare) {
  for (int k = 1; k <= 8; ++k) {
    const std::uint32_t n = 1u << k;
    // Every dyadic box shape 2^a × 2^(k-a) holds exactly one of the first n points.
    for (int a = 0; a <= k; ++a) {
      std::set<std::uint32_t> boxes;
      for (std::uint32_t i = 0; i < n; ++i) {
        const glm::vec2 u = lensSample(i);
        ASSERT_GE(u.x, 0.0f);
        ASSERT_LT(u.x, 1.0f);
        ASSERT_GE(u.y, 0.0f);
        ASSERT_LT(u.y, 1.0f);
        const auto bx = static_cast<std::uint32_t>(u.x * float(1u << a));
        const auto by = static_cast<std::uint32_t>(u.y * float(1u << (k - a)));
        boxes.insert(bx << (k - a) | by);
      }
      EXPECT_EQ(boxes.size(), n) << n << " points, boxes " << (1 << a) << " x " << (1 << (k - a));
    }
  }
}

TEST(LensSample, IsNotTiedToTheSubpixelOffsetDrawnWithIt) {
  // Sample i's lens point and sub-pixel offset both come from the (0, 2)-sequence; read in the same order
  // they would pair each lens quadrant with one pixel quadrant (every frame through the lens's left half
  // jittered left: a sheared blur). Over 64 samples every pairing of quadrants must occur.
  std::set<int> pairs;
  for (std::uint32_t i = 0; i < 64; ++i) {
    const glm::vec2 l = lensSample(i), j = subpixelJitter(i) + 0.5f;
    pairs.insert(int(l.x * 2) * 8 + int(l.y * 2) * 4 + int(j.x * 2) * 2 + int(j.y * 2));
  }
  EXPECT_EQ(pairs.size(), 16u);
}

TEST(SquareToDisk, MapsOntoTheDiskKeepingAreas) {
  EXPECT_EQ(squareToDisk(glm::vec2(0.5f)), glm::vec2(0.0f));
  // A 64 × 64 grid of cell centres: inside the unit disk, and as many in each ring of equal area.
  int inner = 0, total = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const glm::vec2 d = squareToDisk((glm::vec2(x, y) + 0.5f) / 64.0f);
      ASSERT_TRUE(std::isfinite(d.x) && std::isfinite(d.y));
      EXPECT_LE(glm::length(d), 1.0f + 1e-6f);
      inner += glm::length(d) < std::sqrt(0.5f) ? 1 : 0;
      ++total;
    }
  EXPECT_NEAR(double(inner) / total, 0.5, 0.02);
  // The square's corners and edge midpoints reach the rim.
  EXPECT_NEAR(glm::length(squareToDisk(glm::vec2(0.0f))), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(squareToDisk(glm::vec2(1.0f, 0.5f))), 1.0f, 1e-6f);
}

TEST(LensPinhole, WithoutALensOrAtItsCentreIsThePinhole) {
  Camera c;
  c.posW = glm::vec3(1.0f, 2.0f, 3.0f);
  c.targetW = glm::vec3(0.0f, 0.5f, -1.0f);
  EXPECT_EQ(c.lensPinhole({64, 48}), c);
  c.aperture = 0.5f;
  Camera centre = c.lensPinhole({64, 48});
  Camera pinhole = c;
  pinhole.aperture = 0.0f;
  EXPECT_EQ(centre.posW, pinhole.posW);
  EXPECT_EQ(centre.jitterPx, pinhole.jitterPx);
  EXPECT_EQ(centre.rayThroughPixel({10.5f, 20.5f}, {64, 48}).dir, pinhole.rayThroughPixel({10.5f, 20.5f}, {64, 48}).dir);
  // An orthographic camera, a NaN or negative aperture: no lens (the scene file refuses them; a frame never fails).
  for (float bad : {-1.0f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
    Camera b = c;
    b.aperture = bad;
    b.lensUv = glm::vec2(0.1f, 0.9f);
    EXPECT_EQ(b.lensOffsetW(), glm::vec3(0.0f)) << bad;
    EXPECT_EQ(b.lensPinhole({64, 48}).posW, b.posW) << bad;
  }
  // A NaN lens point is the centre.
  Camera nan = c;
  nan.lensUv = glm::vec2(std::nanf(""), 0.3f);
  const Camera nanPinhole = nan.lensPinhole({64, 48});
  EXPECT_TRUE(std::isfinite(nanPinhole.posW.x) && std::isfinite(nanPinhole.jitterPx.x) && std::isfinite(nanPinhole.jitterPx.y));
  Camera ortho = c;
  ortho.orthographic = true;
  ortho.lensUv = glm::vec2(0.1f, 0.9f);
  EXPECT_EQ(ortho.lensPinhole({64, 48}), ortho);
}

TEST(LensPinhole, KeepsThePlaneInFocusAndBlursTheRestByTheLensGeometry) {
  // From lens offset d (in the lens plane), a point at depth z moves on the image by d·(1/F − 1/z) in units
  // of the half-height tangent, i.e. d·(1/F − 1/z)·H / (2·tan(fov/2)) pixels (its circle of confusion is
  // aperture·|1/F − 1/z|·H/(2·tan) wide); points on the plane at F stay on their pixels. At scales 1e-4 to
  // 1e4 and 1e5 from the origin.
  const glm::ivec2 size(320, 180);
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    for (glm::vec3 origin : {glm::vec3(0.0f), glm::vec3(1e5f, -1e5f, 3e4f)}) {
      if (origin != glm::vec3(0.0f) && scale < 1.0f) continue;  // 1e-4 features at 1e5 are below float's grain
      Camera c;
      c.yFovDeg = 50.0f;
      c.posW = origin + scale * glm::vec3(0.3f, 1.5f, 6.0f);
      c.targetW = origin + scale * glm::vec3(0.0f, 0.8f, 0.0f);
      c.aperture = 0.4f * scale;
      c.focusDistance = 5.0f * scale;
      c.nearZ = 1e-3f * scale;
      const Basis b = basis(c);
      const double pxPerTan = size.y / (2.0 * std::tan(glm::radians(double(c.yFovDeg)) * 0.5));
      for (glm::vec2 uv : {glm::vec2(0.0f), glm::vec2(0.9f, 0.2f), glm::vec2(0.25f, 0.75f), glm::vec2(1.0f)}) {
        Camera lens = c;
        lens.lensUv = uv;
        const Camera pin = c.lensPinhole(size);
        const Camera moved = lens.lensPinhole(size);
        EXPECT_LE(glm::length(lens.lensOffsetW()), 0.5f * c.aperture * 1.0001f);
        // The move made (far from the origin, the offset rounded to float's grain there).
        const glm::vec3 offset = glm::vec3(glm::dvec3(moved.posW) - glm::dvec3(pin.posW));
        EXPECT_NEAR(glm::dot(lens.lensOffsetW(), b.forward), 0.0f, 1e-5f * scale) << "the lens lies across the view";
        for (float depth : {2.0f, 5.0f, 12.0f}) {
          for (glm::vec2 lateral : {glm::vec2(0.0f), glm::vec2(0.7f, -0.4f), glm::vec2(-1.5f, 0.9f)}) {
            const glm::vec3 p =
                pin.posW + scale * (depth * b.forward + lateral.x * depth * 0.3f * b.right + lateral.y * depth * 0.3f * b.up);
            const glm::dvec2 from = projectPx(pin, size, p, c.posW), to = projectPx(moved, size, p, c.posW);
            const glm::dvec2 d(glm::dot(offset, b.right) / scale, glm::dot(offset, b.up) / scale);
            const double k = (1.0 / 5.0 - 1.0 / depth) * pxPerTan;
            // x right; pixels run down while `up` runs up.
            const glm::dvec2 expected(d.x * k, -d.y * k);
            const double tolerance = origin == glm::vec3(0.0f) ? 2e-3 : 0.05;
            EXPECT_NEAR(to.x - from.x, expected.x, tolerance) << "scale " << scale << " depth " << depth;
            EXPECT_NEAR(to.y - from.y, expected.y, tolerance) << "scale " << scale << " depth " << depth;
            // The pinhole's camera ray through the pixel it lands on passes through the point.
            const Ray r = moved.rayThroughPixel(glm::vec2(to), size);
            const glm::vec3 toPoint = p - r.origin;
            const float miss = glm::length(toPoint - glm::dot(toPoint, r.dir) * r.dir);
            EXPECT_LT(miss, (origin == glm::vec3(0.0f) ? 1e-4f : 5e-2f) * scale * depth) << "scale " << scale;
          }
        }
      }
    }
  }
}

TEST(LensPinhole, FocusesOnTheTargetByDefault) {
  Camera c;
  c.posW = glm::vec3(0.0f, 0.0f, 8.0f);
  c.targetW = glm::vec3(0.0f);
  c.aperture = 1.0f;
  EXPECT_FLOAT_EQ(c.focusPlane(), 8.0f);
  c.lensUv = glm::vec2(0.95f, 0.1f);
  const glm::ivec2 size(100, 100);
  const glm::vec3 onTarget(0.3f, -0.2f, 0.0f);
  const glm::dvec2 from = projectPx(c.lensPinhole(size), size, onTarget);
  Camera centre = c;
  centre.lensUv = glm::vec2(0.5f);
  const glm::dvec2 at = projectPx(centre.lensPinhole(size), size, onTarget);
  EXPECT_NEAR(from.x, at.x, 1e-3);
  EXPECT_NEAR(from.y, at.y, 1e-3);
  c.focusDistance = 4.0f;
  EXPECT_FLOAT_EQ(c.focusPlane(), 4.0f);
  const glm::dvec2 off = projectPx(c.lensPinhole(size), size, onTarget);
  EXPECT_GT(glm::length(off - at), 1.0) << "out of focus now";
}

TEST(LensPinhole, SceneValidationRefusesABadLens) {
  Scene s;
  s.meshes.push_back({});
  s.materials.push_back({});
  s.camera.aperture = -0.1f;
  EXPECT_FALSE(validateScene(s).ok());
  s.camera.aperture = 0.1f;
  s.camera.focusDistance = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(validateScene(s).ok());
  s.camera.focusDistance = 3.0f;
  EXPECT_TRUE(validateScene(s).ok()) << validateScene(s).error().message;
  s.camera.lensUv = glm::vec2(0.5f, std::nanf(""));
  EXPECT_FALSE(validateScene(s).ok());
  s.camera.lensUv = glm::vec2(0.5f);
  s.camera.orthographic = true;
  auto r = validateScene(s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("perspective"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace tandem
