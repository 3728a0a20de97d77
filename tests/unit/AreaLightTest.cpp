// Area lights' sampling and radiometry (shaders/shading.glsl through core/Shading.h; docs/area-lights.md):
// the point-light limit, closed-form irradiance, stratification of the sample sequence, and finite results
// at the extremes of scale and position.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/Shading.h"

namespace tandem {
namespace {

using namespace shading;

Light areaLight(LightType type, glm::vec3 posW, glm::vec3 dirW, float size, glm::vec3 attenuation) {
  Light l;
  l.type = type;
  l.posW = posW;
  l.dirW = dirW;
  l.size = glm::vec2(size);
  l.radius = size;
  l.intensity = 2.0f;
  l.color = glm::vec3(1.0f, 0.5f, 0.25f);
  l.attenuation = attenuation;
  return l;
}

// The mean over n samples of the light's estimate times cos at a receiver with normal nW, in double: the
// irradiance the light gives the receiver (per colour channel).
glm::dvec3 irradiance(const GpuLight& g, int type, glm::vec3 posW, glm::vec3 nW, int n, std::uint32_t seed = 7) {
  glm::dvec3 sum(0.0);
  for (int i = 0; i < n; ++i) {
    glm::vec3 toLight;
    float dist;
    const glm::vec3 e = tdAreaLightSample(g, type, posW, tdLightSampleU(seed, 0, static_cast<std::uint32_t>(i)), toLight, dist);
    EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z) && std::isfinite(dist));
    sum += glm::dvec3(e) * static_cast<double>(std::max(glm::dot(nW, toLight), 0.0f));
  }
  return sum / static_cast<double>(n);
}

glm::dvec3 pointIrradiance(const Light& l, glm::vec3 posW, glm::vec3 nW) {
  Light p = l;
  p.type = LightType::Point;
  const GpuLight g = packLight(p);
  glm::vec3 toLight;
  float dist;
  const glm::vec3 e = tdLightIncident(g, posW, toLight, dist);
  return glm::dvec3(e) * static_cast<double>(std::max(glm::dot(nW, toLight), 0.0f));
}

double relativeError(glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) / glm::length(b); }

TEST(AreaLight, ShrunkToAPointItIsThePointLight) {
  // A sphere of radius → 0 is the point light at its centre; a rect or disk is the point light times the
  // cosine to its normal (a Lambertian emitter). Both attenuation models: none, and physical 1/d².
  const glm::vec3 receiver(0.3f, 0.0f, -0.2f), up(0.0f, 1.0f, 0.0f);
  const glm::vec3 at(-1.0f, 3.0f, 1.5f);
  const glm::vec3 facing = glm::normalize(glm::vec3(0.4f, -1.0f, -0.3f));
  for (glm::vec3 attenuation : {glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0.5f, 0.2f, 0.1f)})
    for (LightType type : {LightType::Sphere, LightType::Rect, LightType::Disk}) {
      const Light l = areaLight(type, at, facing, 1e-4f, attenuation);
      const GpuLight g = packLight(l);
      glm::dvec3 expected = pointIrradiance(l, receiver, up);
      if (type != LightType::Sphere)
        expected *= static_cast<double>(glm::dot(facing, glm::normalize(receiver - at)));
      const glm::dvec3 got = irradiance(g, static_cast<int>(g.posType.w + 0.5f), receiver, up, 64);
      EXPECT_LT(relativeError(got, expected), 1e-3) << "type " << static_cast<int>(type) << " attenuation "
                                                    << attenuation.x << "," << attenuation.y << "," << attenuation.z;
    }
}

TEST(AreaLight, IrradianceMeetsTheClosedForms) {
  // Physical attenuation (1/d²), radiance L = I / A⊥:
  //  - a sphere above a receiver facing its centre gives πL·sin²α = I / D², whatever its radius;
  //  - a disk of radius r facing a receiver on its axis at height h gives πL·r²/(r² + h²) = I / (r² + h²).
  const glm::vec3 attenuation(0.0f, 0.0f, 1.0f);
  const glm::vec3 receiver(2.0f, -1.0f, 0.5f), up(0.0f, 1.0f, 0.0f);
  const float D = 2.0f;
  for (float r : {0.25f, 1.0f, 1.9f}) {
    const Light l = areaLight(LightType::Sphere, receiver + up * D, -up, r, attenuation);
    const glm::dvec3 got = irradiance(packLight(l), TD_LIGHT_SPHERE, receiver, up, 4096);
    const glm::dvec3 expected = glm::dvec3(l.color * l.intensity) / static_cast<double>(D * D);
    EXPECT_LT(relativeError(got, expected), 5e-3) << "sphere radius " << r;
  }
  for (float r : {0.25f, 1.0f, 4.0f}) {
    const float h = 1.5f;
    const Light l = areaLight(LightType::Disk, receiver + up * h, -up, r, attenuation);
    const glm::dvec3 got = irradiance(packLight(l), TD_LIGHT_DISK, receiver, up, 4096);
    const glm::dvec3 expected = glm::dvec3(l.color * l.intensity) / static_cast<double>(r * r + h * h);
    EXPECT_LT(relativeError(got, expected), 5e-3) << "disk radius " << r;
  }
  // A square of side a on the axis at height h: πL·F with the square's form factor to a parallel
  // differential area on its axis, 4 × the corner formula (Howell's catalogue, C-12).
  for (float a : {0.5f, 2.0f}) {
    const float h = 1.25f;
    const Light l = areaLight(LightType::Rect, receiver + up * h, -up, a, attenuation);
    const double x = (a / 2.0) / h, y = (a / 2.0) / h;
    const double corner = (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                           y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
                          (2.0 * M_PI);
    const double radiance = 1.0 / static_cast<double>(a * a);  // per unit of color·intensity
    const glm::dvec3 expected = glm::dvec3(l.color * l.intensity) * (M_PI * radiance * 4.0 * corner);
    const glm::dvec3 got = irradiance(packLight(l), TD_LIGHT_RECT, receiver, up, 4096);
    EXPECT_LT(relativeError(got, expected), 5e-3) << "square side " << a;
  }
}

TEST(AreaLight, EachFramesSamplesAreStratifiedAndSoAreTheFramesTogether) {
  // K = 4 samples a frame: each frame's 4 fall in 4 distinct quarter-columns and quarter-rows, and 4 frames'
  // 16 in the 16 cells of a 4 × 4 grid (a (0, 4, 2)-net), for any seed.
  for (std::uint32_t seed : {0u, 1u, 12345u, 0xFFFFFFFFu}) {
    std::set<int> cells;
    for (std::uint32_t frame = 0; frame < 4; ++frame) {
      std::set<int> columns, rows;
      for (std::uint32_t k = 0; k < 4; ++k) {
        const glm::vec2 u = tdLightSampleU(seed, 3, frame * 4 + k);
        ASSERT_TRUE(u.x >= 0.0f && u.x < 1.0f && u.y >= 0.0f && u.y < 1.0f);
        columns.insert(static_cast<int>(u.x * 4.0f));
        rows.insert(static_cast<int>(u.y * 4.0f));
        cells.insert(static_cast<int>(u.x * 4.0f) + 4 * static_cast<int>(u.y * 4.0f));
      }
      EXPECT_EQ(columns.size(), 4u);
      EXPECT_EQ(rows.size(), 4u);
    }
    EXPECT_EQ(cells.size(), 16u);
  }
  // Different pixels and lights draw different points.
  EXPECT_NE(tdLightSampleU(tdPixelSeed(10, 20, 0), 0, 0), tdLightSampleU(tdPixelSeed(11, 20, 0), 0, 0));
  EXPECT_NE(tdLightSampleU(tdPixelSeed(10, 20, 0), 0, 0), tdLightSampleU(tdPixelSeed(10, 20, 0), 1, 0));
}

TEST(AreaLight, StaysFiniteAtTheExtremes) {
  // Scales 1e-4 … 1e4, far from the origin, receivers grazing, behind a rect, inside a sphere, on the light.
  for (float scale : {1e-4f, 1.0f, 1e4f})
    for (float offset : {0.0f, 1e5f})
      for (LightType type : {LightType::Sphere, LightType::Rect, LightType::Disk})
        for (glm::vec3 attenuation : {glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)}) {
          const glm::vec3 base(offset, -offset, offset * 0.5f);
          const Light l = areaLight(type, base + glm::vec3(0, scale, 0), glm::vec3(0, -1, 0), scale * 0.5f, attenuation);
          const GpuLight g = packLight(l);
          const int t = static_cast<int>(g.posType.w + 0.5f);
          const glm::vec3 receivers[] = {base, base + glm::vec3(scale * 10.0f, scale * 0.999f, 0.0f),
                                         base + glm::vec3(0, scale * 2.0f, 0), base + glm::vec3(0, scale, 0),
                                         base + glm::vec3(scale * 0.1f, scale * 1.05f, 0)};
          for (const glm::vec3& p : receivers)
            for (std::uint32_t i = 0; i < 64; ++i) {
              glm::vec3 toLight;
              float dist;
              const glm::vec3 e = tdAreaLightSample(g, t, p, tdLightSampleU(i * 77u, 0, i), toLight, dist);
              ASSERT_TRUE(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z) && e.x >= 0.0f)
                  << "scale " << scale << " offset " << offset << " type " << t;
              ASSERT_TRUE(std::isfinite(dist) && dist >= 0.0f);
              ASSERT_NEAR(glm::length(toLight), 1.0f, 1e-4f);
            }
        }
  // Inside a sphere light its surface faces away: nothing; behind a rect: nothing.
  const Light sphere = areaLight(LightType::Sphere, glm::vec3(0), glm::vec3(0, -1, 0), 1.0f, glm::vec3(1, 0, 0));
  glm::vec3 toLight;
  float dist;
  EXPECT_EQ(tdAreaLightSample(packLight(sphere), TD_LIGHT_SPHERE, glm::vec3(0.2f, 0, 0), glm::vec2(0.3f), toLight, dist),
            glm::vec3(0.0f));
  const Light rect = areaLight(LightType::Rect, glm::vec3(0), glm::vec3(0, -1, 0), 1.0f, glm::vec3(1, 0, 0));
  EXPECT_EQ(tdAreaLightSample(packLight(rect), TD_LIGHT_RECT, glm::vec3(0, 1, 0), glm::vec2(0.3f), toLight, dist),
            glm::vec3(0.0f));
  EXPECT_GT(tdAreaLightSample(packLight(rect), TD_LIGHT_RECT, glm::vec3(0, -1, 0), glm::vec2(0.3f), toLight, dist).x, 0.0f);
}

TEST(AreaLight, PackingKeepsTheShapeAndItsSlot) {
  Light rect = areaLight(LightType::Rect, glm::vec3(1, 2, 3), glm::vec3(0, -1, 0), 1.0f, glm::vec3(1, 0, 0));
  rect.size = glm::vec2(4.0f, 2.0f);
  rect.upW = glm::vec3(0, 0, 1);
  const GpuLight g = packLight(rect, 3);
  EXPECT_EQ(static_cast<int>(g.posType.w), TD_LIGHT_RECT);
  EXPECT_FLOAT_EQ(g.shapeU.w, 3.0f);
  EXPECT_NEAR(glm::length(glm::vec3(g.shapeU)), 2.0f, 1e-6f);  // half the width
  EXPECT_NEAR(glm::length(glm::vec3(g.shapeV)), 1.0f, 1e-6f);  // half the height, along up
  EXPECT_NEAR(std::abs(g.shapeV.z), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(glm::vec3(g.shapeU), glm::vec3(g.dirRange)), 0.0f, 1e-6f);
  // An up along the normal still gives a frame in the plane.
  rect.upW = glm::vec3(0, 1, 0);
  const GpuLight h = packLight(rect);
  EXPECT_NEAR(glm::dot(glm::vec3(h.shapeV), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_GT(glm::length(glm::vec3(h.shapeV)), 0.5f);
}

// areaLightReach (the filter's test of what moved takes each area light as a sphere of that radius): every
// point the light is sampled at, its rect's corners and its disk's rim included, lies within it of posW, for
// rects long and square, turned in their plane (a square turned 45 degrees puts its corners where half its
// longer side does not reach), facing any way. The sphere from points around it.
TEST(AreaLight, EveryPointOfTheLightIsWithinItsReach) {
  const glm::vec3 c(1.0f, 2.0f, -3.0f);
  int checked = 0;
  for (const glm::vec3 dir : {glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1, -2, 0.5f)), glm::vec3(0, 0, 1)})
    for (const float turn : {0.0f, 0.3f, 0.785398163f, 1.2f})
      for (const glm::vec2 size : {glm::vec2(2.0f), glm::vec2(4.0f, 0.5f), glm::vec2(0.01f, 3.0f)})
        for (const LightType type : {LightType::Rect, LightType::Disk}) {
          Light l = areaLight(type, c, dir, size.x, glm::vec3(1, 0, 0));
          l.size = size;
          // up turned in the light's plane by `turn` from a fixed perpendicular
          const glm::vec3 a = glm::normalize(glm::cross(dir, std::abs(dir.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0)));
          const glm::vec3 b = glm::cross(dir, a);
          l.upW = std::cos(turn) * a + std::sin(turn) * b;
          const float reach = areaLightReach(l);
          const GpuLight g = packLight(l);
          const int code = type == LightType::Rect ? TD_LIGHT_RECT : TD_LIGHT_DISK;
          // From a point in front of the light (the side it faces), the samples over a grid of u, its corners in.
          const glm::vec3 from = c + 5.0f * dir;
          float most = 0.0f;
          for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j) {
              glm::vec3 toLight;
              float dist;
              (void)tdAreaLightSample(g, code, from, glm::vec2(static_cast<float>(i) / 8.0f, static_cast<float>(j) / 8.0f), toLight, dist);
              most = std::max(most, glm::length(from + toLight * dist - c));
              ++checked;
            }
          EXPECT_LE(most, reach * (1.0f + 1e-5f)) << (type == LightType::Rect ? "rect " : "disk ") << size.x << "x"
                                                  << size.y << " turned " << turn << ": a point " << most << " away";
        }
  Light sphere = areaLight(LightType::Sphere, c, glm::vec3(0, -1, 0), 0.7f, glm::vec3(1, 0, 0));
  for (const glm::vec3 from : {c + glm::vec3(3, 0, 0), c + glm::vec3(-1, 0.5f, 0.2f), c + glm::vec3(0, 0, 40)})
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) {
        glm::vec3 toLight;
        float dist;
        (void)tdAreaLightSample(packLight(sphere), TD_LIGHT_SPHERE, from, glm::vec2(static_cast<float>(i) / 8.0f, static_cast<float>(j) / 8.0f), toLight, dist);
        EXPECT_LE(glm::length(from + toLight * dist - c), areaLightReach(sphere) * (1.0f + 1e-4f));
        ++checked;
      }
  EXPECT_EQ(checked, 3 * 4 * 3 * 2 * 81 + 3 * 81);
  Light point;
  EXPECT_EQ(areaLightReach(point), 0.0f);
}

}  // namespace
}  // namespace tandem
