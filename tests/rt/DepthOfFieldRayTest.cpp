// The reference frame's lens rays (rt/SurfaceShading.h CameraRays::throughLens, referenceRay): every lens
// point's ray through a pixel meets the centre's on the plane in focus, starts on the lens disk, and is the
// ray of that lens point's pinhole (Camera::lensPinhole), which the hybrid frame draws.
#include <gtest/gtest.h>

#include <cmath>

#include "core/Sampling.h"
#include "rt/SurfaceShading.h"

namespace tandem::rt {
namespace {

Camera lensCamera(float scale, glm::vec3 origin) {
  Camera c;
  c.yFovDeg = 45.0f;
  c.posW = origin + scale * glm::vec3(-0.5f, 1.2f, 7.0f);
  c.targetW = origin + scale * glm::vec3(0.2f, 0.6f, 0.0f);
  c.aperture = 0.5f * scale;
  c.focusDistance = 6.0f * scale;
  return c;
}

TEST(LensRays, MeetOnThePlaneInFocusFromPointsOfTheLens) {
  const glm::ivec2 size(96, 54);
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    const Camera c = lensCamera(scale, glm::vec3(0.0f));
    const CameraRays rays(c, size);
    ASSERT_TRUE(rays.hasLens());
    const glm::vec3 forward = glm::normalize(c.targetW - c.posW);
    for (glm::vec2 px : {glm::vec2(0.5f), glm::vec2(47.3f, 20.9f), glm::vec2(95.5f, 53.5f)}) {
      const Ray centre = rays.through(px);
      const glm::vec3 focusW = centre.origin + centre.dir * (c.focusDistance / glm::dot(centre.dir, forward));
      for (std::uint32_t i = 0; i < 32; ++i) {
        const Ray r = rays.throughLens(px, lensSample(i));
        ASSERT_TRUE(std::isfinite(r.dir.x) && std::isfinite(r.dir.y) && std::isfinite(r.dir.z));
        EXPECT_NEAR(glm::length(r.dir), 1.0f, 1e-6f);
        const glm::vec3 onLens = r.origin - c.posW;
        EXPECT_LE(glm::length(onLens), 0.5f * c.aperture * 1.0001f);
        EXPECT_NEAR(glm::dot(onLens, forward), 0.0f, 1e-5f * scale);
        // Where it crosses the plane in focus: the centre ray's point.
        const glm::vec3 crossW = r.origin + r.dir * (glm::dot(focusW - r.origin, forward) / glm::dot(r.dir, forward));
        EXPECT_LT(glm::length(crossW - focusW), 2e-6f * c.focusDistance) << "scale " << scale;
      }
    }
  }
}

TEST(LensRays, AreTheRaysOfTheLensPointsPinhole) {
  // The reference's lens ray and the hybrid frame's pinhole camera at the same lens point see the same
  // direction through every pixel (to float rounding), near the origin and 1e5 away from it.
  const glm::ivec2 size(64, 36);
  for (glm::vec3 origin : {glm::vec3(0.0f), glm::vec3(1e5f, 2e4f, -1e5f)}) {
    Camera c = lensCamera(1.0f, origin);
    for (glm::vec2 uv : {glm::vec2(0.1f, 0.3f), glm::vec2(0.8f, 0.95f)}) {
      c.lensUv = uv;
      // In render space around the camera, as both frames draw.
      const Camera lens = toRenderSpace(c, c.posW);
      const Camera pin = toRenderSpace(c.lensPinhole(size), c.posW);
      const CameraRays lensRays(lens, size);
      for (glm::vec2 px : {glm::vec2(3.5f, 2.5f), glm::vec2(60.5f, 30.5f)}) {
        const Ray a = lensRays.throughLens(px, uv);
        const Ray b = pin.rayThroughPixel(px, size);
        // 1e5 away the pinhole stands where float's grain there (2^-7) puts the lens point: up to half a step
        // per axis from it, and so its directions differ by that over the focus distance.
        const bool far = origin != glm::vec3(0.0f);
        EXPECT_LT(glm::length(a.dir - b.dir), far ? 2e-3f : 1e-5f) << "lens " << uv.x << "," << uv.y;
        EXPECT_LT(glm::length(a.origin - b.origin), far ? 0.5f * std::sqrt(3.0f) / 128.0f : 1e-5f)
            << "lens " << uv.x << "," << uv.y;
      }
      // With one sample per pixel the reference samples the pixel centre from the camera's own lens point.
      const Ray one = referenceRay(lensRays, 10, 20, 0, 0, 1);
      const Ray expected = lensRays.throughLens(glm::vec2(10.5f, 20.5f), uv);
      EXPECT_EQ(one.dir, expected.dir);
      EXPECT_EQ(one.origin, expected.origin);
    }
  }
}

TEST(LensRays, TheReferenceSpreadsItsSamplesOverTheLens) {
  // spp × spp samples of a pixel start from as many points spread over the whole lens disk.
  const Camera c = lensCamera(1.0f, glm::vec3(0.0f));
  const CameraRays rays(c, {64, 36});
  const glm::vec3 forward = glm::normalize(c.targetW - c.posW);
  const glm::vec3 right = glm::normalize(glm::cross(forward, c.upW));
  int left = 0, n = 0;
  float farthest = 0.0f;
  for (int sy = 0; sy < 8; ++sy)
    for (int sx = 0; sx < 8; ++sx) {
      const Ray r = referenceRay(rays, 5, 7, sx, sy, 8);
      const glm::vec3 onLens = r.origin - c.posW;
      left += glm::dot(onLens, right) < 0.0f ? 1 : 0;
      farthest = std::max(farthest, glm::length(onLens));
      ++n;
    }
  EXPECT_GT(left, n / 4);
  EXPECT_LT(left, 3 * n / 4);
  EXPECT_GT(farthest, 0.6f * 0.5f * c.aperture);
  // Without an aperture, the pinhole's rays, bit for bit.
  Camera pinhole = c;
  pinhole.aperture = 0.0f;
  const CameraRays plain(pinhole, {64, 36});
  EXPECT_FALSE(plain.hasLens());
  const Ray a = referenceRay(plain, 5, 7, 3, 2, 4);
  const Ray b = plain.through(referenceSamplePoint(5, 7, 3, 2, 4, plain.jitter()));
  EXPECT_EQ(a.dir, b.dir);
}

}  // namespace
}  // namespace tandem::rt
