// Procedural 3D textures (shaders/procedural.glsl, docs/procedural.md), the C++ twin: improved Perlin noise is
// 0 at every lattice point with its corner's gradient there, the analytic gradients of noise, fBm, turbulence
// and every pattern match finite differences, noise's gradient and Hessian are continuous across cell faces (the
// quintic fade), values change along lines only as their gradients say (no jumps), patterns stay in [0, 1] and
// are continuous across cells, far from the origin and for negative coordinates, every input gives finite values,
// and bump mapping tilts a normal by the closed-form angle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
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

TEST(Procedural, ContinuousAcrossCellFaces) {
  // Across a face x = n (then y, z) for random integers n, negative ones too: a corner hashed with the wrong
  // coordinates, or a floor() that truncates towards 0, breaks it (those stay smooth inside a cell).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 1500; ++i) {
    const int axis = i % 3;
    glm::vec3 lo(50.0f * u(rng) - 25.0f, 50.0f * u(rng) - 25.0f, 50.0f * u(rng) - 25.0f);
    lo[axis] = static_cast<float>(static_cast<int>(u(rng) * 200.0f) - 100);
    glm::vec3 hi = lo;
    lo[axis] -= 1e-4f;
    hi[axis] += 1e-4f;
    EXPECT_NEAR(tdNoiseGrad(lo).x, tdNoiseGrad(hi).x, 1e-3f) << "axis " << axis << " at " << hi[axis];
    // Every pattern, its step bounded by its slope (marble's and wood's are steep).
    const int type = TD_PATTERN_NOISE + i % 6;
    const glm::vec4 a = tdPattern(type, lo, 1.0f, 2.0f, 5), b = tdPattern(type, hi, 1.0f, 2.0f, 5);
    const float slope = std::max(glm::length(glm::vec3(a.y, a.z, a.w)), glm::length(glm::vec3(b.y, b.z, b.w)));
    EXPECT_LE(std::abs(a.x - b.x), 2.0f * (hi[axis] - lo[axis]) * slope + 1e-5f) << "type " << type;
  }
}

TEST(Procedural, NoiseGradientAndHessianAreContinuousAcrossFaces) {
  // Perlin 2002's quintic fade has zero first and second derivatives at 0 and 1, so noise's gradient and its
  // derivative are continuous across every cell face; Perlin 1985's cubic 3t² − 2t³ leaves the Hessian jumping
  // (its second derivative is ±6 there). One-sided differences of the analytic gradient, h and 2h off each side.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-8.0f, 8.0f);
  const float h = 1e-3f;
  float gradJump = 0.0f, hessianJump = 0.0f;
  for (int i = 0; i < 3000; ++i) {
    const int axis = i % 3;
    glm::vec3 p(u(rng), u(rng), u(rng));
    p[axis] = std::floor(p[axis]);
    auto grad = [&](float d) {
      glm::vec3 q = p;
      q[axis] += d;
      const glm::vec4 n = tdNoiseGrad(q);
      return glm::vec3(n.y, n.z, n.w);
    };
    gradJump = std::max(gradJump, glm::length(grad(h * 0.01f) - grad(-h * 0.01f)));
    const glm::vec3 right = (grad(2.0f * h) - grad(h)) / h, left = (grad(-h) - grad(-2.0f * h)) / h;
    hessianJump = std::max(hessianJump, glm::length(right - left));
  }
  EXPECT_LT(gradJump, 1e-3f);
  EXPECT_LT(hessianJump, 1.0f);
}

TEST(Procedural, ValuesChangeAlongLinesOnlyAsTheirGradientsSay) {
  // Step by step along random lines, the change of the value against the trapezoid rule of the analytic
  // gradient. A smooth step agrees to δ³; a crease (|noise| through 0, a clamp's edge) costs at most
  // ½·δ·(|g_a| + |g_b|) (0.65 of the bound below at worst); a jump — a fract() sawtooth instead of wood's smooth
  // ring profile, a cell that disagrees with its neighbour — costs far more. It finds the jumps that random
  // finite differences rarely straddle; the slopes themselves are the finite differences' test.
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  for (int type = TD_PATTERN_NOISE; type <= TD_PATTERN_GRANITE; ++type)
    for (float scale : {0.5f, 3.0f})
      for (float turbulence : {0.7f, 4.0f}) {
        const float finest = scale * 8.0f;  // 4 octaves
        int bad = 0;
        float worst = 0.0f;
        for (int line = 0; line < 4; ++line) {
          const glm::vec3 start(u(rng), u(rng), u(rng));
          const glm::vec3 dir = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
          const int steps = static_cast<int>(300.0f * finest);  // 300 steps a finest feature, a unit long
          glm::vec3 pa = start;
          glm::vec4 a = tdPattern(type, pa, scale, turbulence, 4);
          for (int i = 1; i <= steps; ++i) {
            const glm::vec3 pb = start + (static_cast<float>(i) / static_cast<float>(steps)) * dir;
            const glm::vec4 b = tdPattern(type, pb, scale, turbulence, 4);
            const glm::vec3 ga(a.y, a.z, a.w), gb(b.y, b.z, b.w), d = pb - pa;
            const float err = std::abs(b.x - a.x - 0.5f * glm::dot(ga + gb, d));
            const float allowed = 0.55f * glm::length(d) * (glm::length(ga) + glm::length(gb)) + 2e-6f;
            bad += err > allowed ? 1 : 0;
            worst = std::max(worst, err);
            pa = pb;
            a = b;
          }
        }
        EXPECT_EQ(bad, 0) << "type " << type << " scale " << scale << " turbulence " << turbulence << ": worst "
                          << worst;
      }
}

TEST(Procedural, DeterministicAndPinned) {
  for (int type = TD_PATTERN_NONE; type <= TD_PATTERN_GRANITE; ++type) {
    const glm::vec4 once = tdPattern(type, glm::vec3(1.3f, -2.7f, 9.1f), 2.0f, 3.0f, 6);
    const glm::vec4 twice = tdPattern(type, glm::vec3(1.3f, -2.7f, 9.1f), 2.0f, 3.0f, 6);
    EXPECT_EQ(std::memcmp(&once, &twice, sizeof once), 0) << "type " << type;
  }
  EXPECT_EQ(tdPattern(TD_PATTERN_NONE, glm::vec3(0.3f), 1.0f, 1.0f, 4), glm::vec4(0.0f));
  // The corner hash is part of every picture (the golden images): pinned, negative and extreme corners too
  // (uint(int) wraps alike in GLSL and C++; the corners are integers, so these are exact on any compiler).
  EXPECT_EQ(tdLatticeGradient(0, 0, 0), glm::vec3(1.0f, 1.0f, 0.0f));
  EXPECT_EQ(tdLatticeGradient(-1, -1, -1), glm::vec3(-1.0f, -1.0f, 0.0f));
  EXPECT_EQ(tdLatticeGradient(-7, 3, -100000), glm::vec3(0.0f, 1.0f, -1.0f));
  EXPECT_EQ(tdLatticeGradient(2147483647, -2147483647 - 1, 5), glm::vec3(1.0f, -1.0f, 0.0f));
  const glm::vec4 n = tdNoiseGrad(glm::vec3(-1.25f, 3.75f, -8.125f));
  EXPECT_NEAR(n.x, -0.446288228f, 1e-6f);
  EXPECT_NEAR(n.y, 0.0562157035f, 1e-5f);
  EXPECT_NEAR(n.z, 0.633713007f, 1e-5f);
  EXPECT_NEAR(n.w, 0.290918827f, 1e-5f);
}

TEST(Procedural, FarVeinsAndRingsAreWhereTheirFloatPointSays) {
  // Far from the origin marble's sine and wood's cosine take large arguments: π·s rounded to float is off by
  // up to half an ulp of it (0.002 at s = 1.5e4), and GPU sines reduce large arguments coarsely. The patterns
  // reduce s exactly before the angle, so each equals the closed form of its own float s in double precision.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-1.0f, 1.0f);
  double worstMarble = 0.0, worstWood = 0.0;
  for (const float far : {1e3f, 1e4f, -3e4f, 2e5f})
    for (int i = 0; i < 200; ++i) {
      const glm::vec3 p(far + jitter(rng), 0.3f * jitter(rng), far * 0.5f + jitter(rng));
      const float scale = 1.5f, turbulence = 1.5f;
      glm::vec3 q = p * scale;
      q = glm::vec3(tdLatticeSafe(q.x), tdLatticeSafe(q.y), tdLatticeSafe(q.z));
      const float s = q.x + turbulence * tdTurbulenceGrad(q, 4).x;
      const double w = 0.5 + 0.5 * std::sin(3.14159265358979 * double(s));
      worstMarble = std::max(worstMarble, std::abs(double(tdPattern(TD_PATTERN_MARBLE, p, scale, turbulence, 4).x) - w * w * w));
      const float rho = std::sqrt(q.x * q.x + q.z * q.z);
      const float r = rho + turbulence * tdNoiseGrad(q * glm::vec3(1.0f, 0.25f, 1.0f)).x;
      const double v = 0.5 + 0.5 * std::cos(6.28318530717959 * double(r));
      worstWood = std::max(worstWood, std::abs(double(tdPattern(TD_PATTERN_WOOD, p, scale, turbulence, 4).x) - v * v));
    }
  // Float sines of reduced arguments are within a few 1e-7; the unreduced angle gave errors of ~1e-3 here.
  EXPECT_LT(worstMarble, 2e-6);
  EXPECT_LT(worstWood, 2e-6);
}

TEST(Procedural, OctavesClampToOneThroughEight) {
  // 0 or negative octaves would divide by a zero amplitude sum; more than 8 cost without showing (the 9th is
  // 1/256 of the first).
  const glm::vec3 p(0.37f, -4.2f, 2.9f);
  auto same = [](glm::vec4 a, glm::vec4 b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  EXPECT_TRUE(same(tdFbmGrad(p, 0), tdFbmGrad(p, 1)));
  EXPECT_TRUE(same(tdFbmGrad(p, -3), tdFbmGrad(p, 1)));
  EXPECT_TRUE(same(tdFbmGrad(p, 20), tdFbmGrad(p, 8)));
  EXPECT_TRUE(same(tdTurbulenceGrad(p, 0), tdTurbulenceGrad(p, 1)));
  EXPECT_TRUE(same(tdTurbulenceGrad(p, 20), tdTurbulenceGrad(p, 8)));
  EXPECT_FALSE(same(tdFbmGrad(p, 7), tdFbmGrad(p, 8))) << "the 8th octave counts";
  for (int type = TD_PATTERN_FBM; type <= TD_PATTERN_GRANITE; ++type) {
    if (type == TD_PATTERN_WOOD) continue;  // one octave of noise, whatever `octaves` says
    EXPECT_TRUE(same(tdPattern(type, p, 1.5f, 1.0f, 0), tdPattern(type, p, 1.5f, 1.0f, 1))) << type;
    EXPECT_TRUE(same(tdPattern(type, p, 1.5f, 1.0f, 99), tdPattern(type, p, 1.5f, 1.0f, 8))) << type;
  }
}

TEST(Procedural, FiniteForEveryInput) {
  // Up to 1e6 the patterns are still patterns: in [0, 1] with finite gradients, for every type and octave count.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(-1e6f, 1e6f);
  for (int i = 0; i < 6000; ++i) {
    const int type = TD_PATTERN_NOISE + i % 6;
    const glm::vec4 v = tdPattern(type, glm::vec3(u(rng), u(rng), u(rng)), 3.0f, 2.0f, 1 + i % 8);
    ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w)) << type;
    ASSERT_GE(v.x, 0.0f);
    ASSERT_LE(v.x, 1.0f);
  }
  // Beyond the lattice's reach (2^23), at float's limit, ∞ and NaN: finite, never an undefined int conversion,
  // and wood's q.x² must not overflow nor marble's sine see ∞.
  for (float big : {1e7f, -1e19f, 1e20f, 3e38f, std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
    for (int type = TD_PATTERN_NOISE; type <= TD_PATTERN_GRANITE; ++type)
      for (float scale : {0.5f, 7.0f}) {
        const glm::vec4 v = tdPattern(type, glm::vec3(big, 1.5f, -big), scale, 1.0f, 8);
        EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w))
            << "type " << type << " at " << big << " scale " << scale;
        const glm::vec4 n = tdNoiseGrad(glm::vec3(big, -big, 0.5f));
        EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) && std::isfinite(n.w)) << big;
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
  // Any frame: N' stays in the plane of N and the tangential gradient g_t, leans away from g_t by atan(a·|g_t|);
  // a negative amplitude (a dent, not a bump) leans towards it by the same angle.
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 200; ++i) {
    const glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
    const glm::vec3 g(3.0f * u(rng), 3.0f * u(rng), 3.0f * u(rng));
    const glm::vec3 gt = g - glm::dot(g, n) * n;
    const float a = (i % 2 == 0 ? 1.0f : -1.0f) * (0.05f + std::abs(u(rng)));
    const glm::vec3 b = tdBumpNormal(n, g, a);
    EXPECT_NEAR(glm::length(b), 1.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(b, glm::cross(n, gt)), 0.0f, 1e-5f) << "out of the plane of N and g_t";
    const float tilt = std::atan2(-glm::dot(b, glm::normalize(gt)), glm::dot(b, n));
    EXPECT_NEAR(tilt, std::atan(a * glm::length(gt)), 2e-5f);
  }
  // Degenerate or not finite: N itself.
  const glm::vec3 tilted = glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f));
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(tdBumpNormal(tilted, glm::vec3(inf), 1.0f), tilted) << "infinite gradient";
  EXPECT_EQ(tdBumpNormal(tilted, glm::vec3(1.0f, nan, 0.0f), 1.0f), tilted) << "NaN gradient";
  EXPECT_EQ(tdBumpNormal(tilted, glm::vec3(1.0f, 0.0f, 0.0f), nan), tilted) << "NaN amplitude";
  EXPECT_EQ(tdBumpNormal(tilted, glm::vec3(1e30f, -1e30f, 0.0f), 1e30f), tilted) << "overflow";
  EXPECT_EQ(tdBumpNormal(glm::vec3(0.0f), glm::vec3(0.0f), 1.0f), glm::vec3(0.0f)) << "zero normal, zero gradient";
}

}  // namespace
}  // namespace tandem::shading
