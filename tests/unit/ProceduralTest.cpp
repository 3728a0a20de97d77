// Procedural 3D textures (shaders/procedural.glsl, docs/procedural.md), the C++ twin: improved Perlin noise is
// 0 at every lattice point with its corner's gradient there, the analytic gradients of noise, fBm, turbulence
// and every pattern match finite differences, patterns stay in [0, 1] and are continuous across cells, far from
// the origin and for negative coordinates, and bump mapping tilts a normal by the closed-form angle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/Procedural.h"

namespace tandem::shading {
namespace {

// Central differences of f's value in double around p (h in p's units), against f's own gradient.
template <class F>
glm::dvec3 numericGradient(F f, glm::vec3 p, float h) {
  glm::dvec3 g;
  for (int a = 0; a < 3; ++a) {
    glm::vec3 lo = p, hi = p;
    lo[a] -= h;
    hi[a] += h;
    g[a] = (static_cast<double>(f(hi).x) - static_cast<double>(f(lo).x)) / (static_cast<double>(hi[a]) - lo[a]);
  }
  return g;
}

// The fraction of points where the analytic gradient is within `rel` (relative to the larger of the two and
// `floor`) of finite differences, at random points of [-5, 5]³ with steps of 1/500 of the finest feature
// (`finest` features per unit): small against the features, large against float's spacing there (a step of a
// few ulps would measure rounding, not the slope). Creases (turbulence's |noise| at 0, a clamp's edge) make a
// few points miss.
template <class F>
double agreeing(F f, float finest, int points, double rel, double floor, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  int good = 0;
  for (int i = 0; i < points; ++i) {
    const glm::vec3 p(u(rng), u(rng), u(rng));
    const glm::vec4 v = f(p);
    const glm::dvec3 want = numericGradient(f, p, 2e-3f / finest);
    const glm::dvec3 got(v.y, v.z, v.w);
    const double err = glm::length(got - want);
    good += err <= rel * std::max({glm::length(got), glm::length(want), floor}) ? 1 : 0;
  }
  return static_cast<double>(good) / points;
}

TEST(Procedural, NoiseIsZeroAtLatticePointsWithAnEdgeGradient) {
  for (int x = -5; x <= 5; ++x)
    for (int y = -5; y <= 5; ++y)
      for (int z = -5; z <= 5; ++z) {
        const glm::vec4 n = tdNoiseGrad(glm::vec3(x, y, z));
        EXPECT_EQ(n.x, 0.0f);
        // One of the 12 directions to the cube's edge midpoints: two components ±1, one 0.
        int zeros = 0, ones = 0;
        for (int a = 1; a <= 3; ++a) {
          zeros += n[a] == 0.0f ? 1 : 0;
          ones += std::abs(n[a]) == 1.0f ? 1 : 0;
        }
        EXPECT_EQ(zeros, 1);
        EXPECT_EQ(ones, 2);
        EXPECT_EQ(glm::vec3(n.y, n.z, n.w), tdLatticeGradient(x, y, z));
      }
}

TEST(Procedural, AllTwelveGradientsAppearEvenly) {
  int counts[3][4] = {};
  for (int i = 0; i < 12000; ++i) {
    const glm::vec3 g = tdLatticeGradient(i % 37 - 18, (i / 37) % 29 - 14, i / (37 * 29) - 5);
    const int axis = g.x == 0.0f ? 2 : g.y == 0.0f ? 1 : 0;
    const glm::vec2 ab = axis == 0 ? glm::vec2(g.x, g.y) : axis == 1 ? glm::vec2(g.x, g.z) : glm::vec2(g.y, g.z);
    ++counts[axis][(ab.x < 0.0f ? 1 : 0) + (ab.y < 0.0f ? 2 : 0)];
  }
  for (auto& axis : counts)
    for (int c : axis) EXPECT_NEAR(c, 1000, 150);
}

TEST(Procedural, AnalyticGradientsMatchFiniteDifferences) {
  EXPECT_GT(agreeing([](glm::vec3 p) { return tdNoiseGrad(p); }, 1.0f, 3000, 2e-2, 1e-2), 0.995);
  EXPECT_GT(agreeing([](glm::vec3 p) { return tdFbmGrad(p, 5); }, 16.0f, 3000, 2e-2, 1e-2), 0.995);
  // |noise| creases where an octave crosses 0: a few points straddle one.
  EXPECT_GT(agreeing([](glm::vec3 p) { return tdTurbulenceGrad(p, 4); }, 8.0f, 3000, 2e-2, 1e-2), 0.97);
  for (int type = TD_PATTERN_NOISE; type <= TD_PATTERN_GRANITE; ++type)
    for (float scale : {0.5f, 3.0f})
      for (float turbulence : {0.0f, 0.7f, 4.0f}) {
        auto f = [&](glm::vec3 p) { return tdPattern(type, p, scale, turbulence, 4); };
        EXPECT_GT(agreeing(f, scale * 8.0f, 1500, 2e-2, 1e-2 * scale), 0.97)
            << "type " << type << " scale " << scale << " turbulence " << turbulence;
      }
}

TEST(Procedural, ABrokenGradientIsCaught) {
  // The check above is not blind: noise with its fade derivative left out fails it.
  auto broken = [](glm::vec3 p) {
    glm::vec4 n = tdNoiseGrad(p);
    const glm::vec3 c = glm::floor(p);
    return glm::vec4(n.x, tdLatticeGradient(int(c.x), int(c.y), int(c.z)));
  };
  EXPECT_LT(agreeing(broken, 1.0f, 1000, 2e-2, 1e-2), 0.5);
}

TEST(Procedural, PatternsStayInTheUnitIntervalAndVary) {
  std::mt19937 rng(11);
  for (int type = TD_PATTERN_NOISE; type <= TD_PATTERN_GRANITE; ++type)
    for (float centre : {0.0f, -3000.0f, 1e4f}) {
      std::uniform_real_distribution<float> u(centre - 50.0f, centre + 50.0f);
      double sum = 0, sum2 = 0;
      const int n = 4000;
      for (int i = 0; i < n; ++i) {
        const glm::vec4 v = tdPattern(type, glm::vec3(u(rng), u(rng), u(rng)), 1.7f, 2.0f, 5);
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w));
        ASSERT_GE(v.x, 0.0f) << "type " << type;
        ASSERT_LE(v.x, 1.0f) << "type " << type;
        sum += v.x;
        sum2 += double(v.x) * v.x;
      }
      const double mean = sum / n, sd = std::sqrt(std::max(sum2 / n - mean * mean, 0.0));
      EXPECT_GT(sd, 0.05) << "type " << type << " at " << centre << ": a pattern, not a constant";
    }
  // Noise itself spans about [-1, 1].
  std::uniform_real_distribution<float> u(-100.0f, 100.0f);
  float lo = 0, hi = 0;
  for (int i = 0; i < 100000; ++i) {
    const float v = tdNoiseGrad(glm::vec3(u(rng), u(rng), u(rng))).x;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_LT(lo, -0.6f);
  EXPECT_GT(hi, 0.6f);
  EXPECT_GT(lo, -1.1f);
  EXPECT_LT(hi, 1.1f);
}

TEST(Procedural, ContinuousAcrossCellsAndDeterministic) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 500; ++i) {
    // Across x = n for a random integer n (negative ones too), at a random y, z.
    const float n = static_cast<float>(static_cast<int>(u(rng) * 200.0f) - 100);
    const float y = 50.0f * u(rng) - 25.0f, z = 50.0f * u(rng) - 25.0f;
    const float a = tdNoiseGrad(glm::vec3(n - 1e-4f, y, z)).x, b = tdNoiseGrad(glm::vec3(n + 1e-4f, y, z)).x;
    EXPECT_NEAR(a, b, 1e-3f);
  }
  const glm::vec4 once = tdPattern(TD_PATTERN_MARBLE, glm::vec3(1.3f, -2.7f, 9.1f), 2.0f, 3.0f, 6);
  const glm::vec4 twice = tdPattern(TD_PATTERN_MARBLE, glm::vec3(1.3f, -2.7f, 9.1f), 2.0f, 3.0f, 6);
  EXPECT_EQ(std::memcmp(&once, &twice, sizeof once), 0);
  // Inputs beyond the lattice's reach (and NaN) give finite values, never undefined int conversions.
  for (float big : {1e6f, -1e7f, 3e38f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    const glm::vec4 v = tdPattern(TD_PATTERN_GRANITE, glm::vec3(big, 1.5f, -big), 1.0f, 1.0f, 8);
    EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w)) << big;
  }
}

TEST(Procedural, BumpTiltsTheNormalByTheClosedFormAngle) {
  const glm::vec3 N(0.0f, 0.0f, 1.0f);
  EXPECT_EQ(tdBumpNormal(N, glm::vec3(3.0f, 1.0f, 2.0f), 0.0f), N) << "amplitude 0: N itself";
  EXPECT_EQ(tdBumpNormal(N, glm::vec3(0.0f, 0.0f, 5.0f), 0.3f), N) << "a gradient along N moves nothing";
  for (float a : {0.01f, 0.2f, 1.0f, 5.0f})
    for (float g : {0.5f, 2.0f}) {
      const glm::vec3 b = tdBumpNormal(N, glm::vec3(g, 0.0f, 0.7f), a);
      EXPECT_NEAR(glm::length(b), 1.0f, 1e-6f);
      // The height a·h rises along +x at slope a·g: the normal leans back, towards −x, by atan(a·g).
      EXPECT_NEAR(std::atan2(-b.x, b.z), std::atan(a * g), 1e-5f);
      EXPECT_NEAR(b.y, 0.0f, 1e-7f);
    }
  const glm::vec3 tilted = glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(tdBumpNormal(tilted, glm::vec3(std::numeric_limits<float>::infinity()), 1.0f), tilted) << "not finite: N";
}

}  // namespace
}  // namespace tandem::shading
