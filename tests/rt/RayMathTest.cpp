// The ray pass's numerics held to their numbers: refraction/Fresnel at the critical angle, the IOR-1
// identity, the exact primary hit (watertight, clamped), origin offsets that never re-hit their surface.
#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include "rt/RayMath.h"

namespace tandem::rt {
namespace {

// Transmittance from the Fresnel transmission coefficients (independent of tdFresnelExact's R):
// T = (etaT cosT)/(etaI cosI) · (t∥² + t⊥²)/2.
double transmittanceExact(double cosI, double etaI, double etaT) {
  double sinT = etaI / etaT * std::sqrt(1.0 - cosI * cosI);
  double cosT = std::sqrt(1.0 - sinT * sinT);
  double tPar = 2.0 * etaI * cosI / (etaT * cosI + etaI * cosT);
  double tPerp = 2.0 * etaI * cosI / (etaI * cosI + etaT * cosT);
  return (etaT * cosT) / (etaI * cosI) * 0.5 * (tPar * tPar + tPerp * tPerp);
}

glm::vec3 toEyeAt(double theta) { return glm::vec3(static_cast<float>(std::sin(theta)), static_cast<float>(std::cos(theta)), 0.0f); }

TEST(Refraction, TotalInternalReflectionJustPastTheCriticalAngle) {
  const glm::vec3 normal(0, 1, 0);
  for (float ior : {1.5f, 1.333f, 2.4f}) {
    const double critical = std::asin(1.0 / ior);  // leaving the dense medium into air
    for (FresnelMode mode : {FresnelMode::Exact, FresnelMode::Schlick}) {
      for (double delta : {1e-4, 1e-5}) {
        Refraction past = refractDielectric(toEyeAt(critical + delta), normal, ior, 1.0f, mode);
        EXPECT_TRUE(past.totalInternal) << "ior " << ior << " +" << delta;
        EXPECT_EQ(past.fresnel, 1.0f);

        Refraction before = refractDielectric(toEyeAt(critical - delta), normal, ior, 1.0f, mode);
        ASSERT_FALSE(before.totalInternal) << "ior " << ior << " -" << delta;
        EXPECT_LT(before.fresnel, 1.0f);
        // Snell: etaI sinI = etaT sinT, the refracted ray on the far side, unit length.
        double sinT = std::sqrt(double(before.dirW.x) * before.dirW.x + double(before.dirW.z) * before.dirW.z);
        EXPECT_NEAR(sinT, ior * std::sin(critical - delta), 1e-5);
        EXPECT_LT(before.dirW.y, 0.0f);
        EXPECT_NEAR(glm::length(before.dirW), 1.0f, 1e-6f);
      }
    }
  }
}

TEST(Refraction, ReflectedPlusTransmittedIsOne) {
  const glm::vec3 normal(0, 1, 0);
  for (auto [etaI, etaT] : {std::pair{1.0f, 1.5f}, std::pair{1.5f, 1.0f}, std::pair{1.0f, 4.0f}, std::pair{1.333f, 1.0f}}) {
    double limit = etaI > etaT ? std::asin(etaT / etaI) - 1e-3 : 1.5;
    for (double theta = 0.0; theta < limit; theta += 0.01) {
      Refraction r = refractDielectric(toEyeAt(theta), normal, etaI, etaT, FresnelMode::Exact);
      ASSERT_FALSE(r.totalInternal);
      double t = transmittanceExact(double(float(std::cos(theta))), etaI, etaT);  // the cosine the routine sees
      EXPECT_NEAR(double(r.fresnel) + t, 1.0, 2e-5) << etaI << " -> " << etaT << " at " << theta;
    }
  }
}

TEST(Refraction, IorOneIsAnExactIdentity) {
  for (double theta : {0.0, 0.3, 1.0, 1.5}) {
    glm::vec3 v = toEyeAt(theta);
    Refraction r = refractDielectric(v, glm::vec3(0, 1, 0), 1.0f, 1.0f, FresnelMode::Exact);
    EXPECT_FALSE(r.totalInternal);
    EXPECT_EQ(r.fresnel, 0.0f);
    EXPECT_EQ(r.dirW, -v);
  }
}

TEST(ExactHit, BarycentricsReproduceTheRayPoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    glm::vec3 p0(u(rng), u(rng), u(rng)), p1(u(rng), u(rng), u(rng)), p2(u(rng), u(rng), u(rng));
    float a = std::abs(u(rng)), b = std::abs(u(rng)) * (1.0f - a);
    glm::vec3 target = (1.0f - a - b) * p0 + a * p1 + b * p2;
    glm::vec3 origin(u(rng) * 5.0f, u(rng) * 5.0f, 5.0f + u(rng));
    glm::vec3 dir = glm::normalize(target - origin);
    glm::vec3 bary = triangleBarycentrics(origin, dir, p0, p1, p2);
    EXPECT_GE(glm::min(bary.x, glm::min(bary.y, bary.z)), 0.0f);
    EXPECT_NEAR(bary.x + bary.y + bary.z, 1.0f, 1e-6f);
    glm::vec3 hit = bary.x * p0 + bary.y * p1 + bary.z * p2;
    // On the ray: the distance from the line is rounding only.
    glm::vec3 rel = hit - origin;
    EXPECT_LT(glm::length(rel - glm::dot(rel, dir) * dir), 1e-5f);
  }
}

TEST(ExactHit, RayGrazingPastAnEdgeIsClampedOntoTheTriangle) {
  glm::vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
  // Just outside the hypotenuse, and far outside beyond p1: the nearest triangle points.
  glm::vec3 b = triangleBarycentrics({0.5f, 0.5001f, 1.0f}, {0, 0, -1}, p0, p1, p2);
  glm::vec3 hit = b.x * p0 + b.y * p1 + b.z * p2;
  EXPECT_NEAR(hit.x, 0.49995f, 1e-6f);
  EXPECT_NEAR(hit.y, 0.50005f, 1e-6f);
  EXPECT_GE(glm::min(b.x, glm::min(b.y, b.z)), 0.0f);
  b = triangleBarycentrics({3.0f, -1.0f, 1.0f}, {0, 0, -1}, p0, p1, p2);
  EXPECT_NEAR(b.y, 1.0f, 1e-6f);
  // Parallel to the plane and a zero-area triangle: still a point of the triangle, finite.
  b = triangleBarycentrics({0.2f, 0.2f, 1.0f}, {1, 0, 0}, p0, p1, p2);
  EXPECT_TRUE(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
  EXPECT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
  b = triangleBarycentrics({0.2f, 0.2f, 1.0f}, {0, 0, -1}, p0, p0, p0);
  EXPECT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
}

// pbrt-v4's shapes test, on Embree: random triangles with coordinates log-uniform over many scales;
// rays spawned from hit points (position from barycentrics, offset as the ray pass offsets them: the
// scale-aware offsetRayOrigin with the interpolation's magnitude bound, spawnOrigin's) never re-hit their
// triangle.
TEST(OriginOffset, SpawnedRaysNeverReintersectTheirTriangle) {
  RTCDevice device = rtcNewDevice(nullptr);
  ASSERT_NE(device, nullptr);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  auto logUniform = [&] {
    float mag = std::pow(10.0f, -4.0f + 9.0f * u01(rng));  // 1e-4 .. 1e5
    return u01(rng) < 0.5f ? -mag : mag;
  };
  int reHits = 0, rays = 0;
  for (int t = 0; t < 200; ++t) {
    glm::vec3 center(logUniform(), logUniform(), logUniform());
    float size = std::pow(10.0f, -3.0f + 5.0f * u01(rng));
    glm::vec3 p[3];
    for (auto& v : p) v = center + size * glm::vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f);
    glm::vec3 ng = glm::cross(p[1] - p[0], p[2] - p[0]);
    if (!(glm::length(ng) > 0.0f)) continue;
    ng = glm::normalize(ng);
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 3));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, 1));
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) vb[3 * i + k] = p[i][k];
    ib[0] = 0, ib[1] = 1, ib[2] = 2;
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    for (int h = 0; h < 50; ++h) {
      float a = u01(rng), b = u01(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      glm::vec3 pos = (1.0f - a - b) * p[0] + a * p[1] + b * p[2];
      for (int d = 0; d < 10; ++d) {
        glm::vec3 dir = glm::normalize(glm::vec3(u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f) + glm::vec3(1e-6f));
        glm::vec3 side = glm::dot(dir, ng) >= 0.0f ? ng : -ng;
        const glm::vec3 mag = interpolationMagnitude(glm::vec3(1.0f - a - b, a, b), glm::abs(p[0]), glm::abs(p[1]),
                                                     glm::abs(p[2]));
        glm::vec3 o = offsetRayOrigin(pos, side, mag);
        RTCRay ray{};
        ray.org_x = o.x, ray.org_y = o.y, ray.org_z = o.z;
        ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
        ray.tnear = 0.0f;
        ray.tfar = std::numeric_limits<float>::infinity();
        ray.mask = ~0u;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(scene, &ctx, &ray);
        ++rays;
        if (ray.tfar < 0.0f) ++reHits;
      }
    }
    rtcReleaseScene(scene);
  }
  rtcReleaseDevice(device);
  EXPECT_GT(rays, 50000);
  EXPECT_EQ(reHits, 0) << "of " << rays << " rays";
}

// The bit-arithmetic next float used by the origin offsets is std::nextafter, special values included.
TEST(OriginOffset, NextFloatIsStdNextafter) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> values = {0.0f, -0.0f, inf, -inf, std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                               std::numeric_limits<float>::min(), -std::numeric_limits<float>::min(),
                               std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
                               1.0f, -1.0f, 1e-30f, -3.5e12f};
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::uint32_t> bits;
  for (int i = 0; i < 100000; ++i) values.push_back(std::bit_cast<float>(bits(rng)));
  for (float v : values) {
    if (std::isnan(v)) {
      EXPECT_TRUE(std::isnan(nextFloatUp(v)) && std::isnan(nextFloatDown(v)));
      continue;
    }
    ASSERT_EQ(std::bit_cast<std::uint32_t>(nextFloatUp(v)), std::bit_cast<std::uint32_t>(std::nextafter(v, inf))) << v;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(nextFloatDown(v)), std::bit_cast<std::uint32_t>(std::nextafter(v, -inf))) << v;
  }
}

TEST(PixelRandom, IsAFunctionOfPixelAndSampleOnly) {
  EXPECT_EQ(random01(3, 4, 5, 0), random01(3, 4, 5, 0));
  EXPECT_NE(random01(3, 4, 5, 0), random01(4, 3, 5, 0));
  EXPECT_NE(random01(3, 4, 5, 0), random01(3, 4, 5, 1));
  double sum = 0.0;
  for (std::uint32_t i = 0; i < 10000; ++i) {
    float r = random01(i, 7, 0, 0);
    ASSERT_GE(r, 0.0f);
    ASSERT_LT(r, 1.0f);
    sum += r;
  }
  EXPECT_NEAR(sum / 10000.0, 0.5, 0.01);
}

}  // namespace
}  // namespace tandem::rt
