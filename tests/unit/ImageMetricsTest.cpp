// Image metrics on pairs with known answers (docs/metrics.md). Where an expected FLIP value is a number, the
// comment says where it comes from: values are derived by hand from the paper's definitions and published
// CIE L*a*b* coordinates, never read back from this implementation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "tandem/ImageMetrics.h"

namespace tandem {
namespace {

Image solid(int w, int h, glm::u8vec4 c) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.set(x, y, c);
  return img;
}

// A textured image with values in [20, 200]: a diagonal gradient plus 8×8 blocks of pseudo-random colour,
// so there are edges, flat areas and colour for every pipeline to see, and room for offsets up to 55.
Image textured(int w, int h) {
  Image img = solid(w, h, {0, 0, 0, 255});
  std::uint32_t state = 12345u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<int>((state >> 24) % 81u);  // 0..80
  };
  std::vector<glm::ivec3> blocks(std::size_t((w / 8 + 1) * (h / 8 + 1)));
  for (auto& b : blocks) b = {next(), next(), next()};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::ivec3 b = blocks[std::size_t((y / 8) * (w / 8 + 1) + x / 8)];
      const int g = 20 + (x + y) * 100 / (w + h);  // 20..120
      img.set(x, y, {std::uint8_t(g + b.x), std::uint8_t(g + b.y), std::uint8_t(g + b.z), 255});
    }
  return img;
}

Image offset(const Image& img, int k) {
  Image out = img;
  for (std::size_t i = 0; i < out.rgba.size(); ++i)
    if (i % 4 != 3) out.rgba[i] = static_cast<std::uint8_t>(out.rgba[i] + k);
  return out;
}

// Black for x < edgeX, white from edgeX on.
Image step(int w, int h, int edgeX) {
  Image img = solid(w, h, {0, 0, 0, 255});
  for (int y = 0; y < h; ++y)
    for (int x = edgeX; x < w; ++x) img.set(x, y, {255, 255, 255, 255});
  return img;
}

// FLIP's colour error for a uniform pair whose (Hunt-adjusted) HyAB distance is d, computed here from the
// paper's equations: cmax = HyAB(green, blue)^qc with green and blue at their published CIE L*a*b* (D65)
// coordinates (Lindbloom's sRGB tables: green 87.7347, −86.1827, 83.1793; blue 32.3026, 79.1967, −107.8637).
double expectedUniformFlip(double hyabDistance) {
  const double gL = 87.7347, ga = -86.1827, gb = 83.1793;
  const double bL = 32.3026, ba = 79.1967, bb = -107.8637;
  const double da = 0.01 * gL * ga - 0.01 * bL * ba, db = 0.01 * gL * gb - 0.01 * bL * bb;
  const double cmax = std::pow(std::abs(gL - bL) + std::sqrt(da * da + db * db), 0.7);
  const double pccmax = 0.4 * cmax;
  const double e = std::pow(hyabDistance, 0.7);
  return e < pccmax ? e * 0.95 / pccmax : 0.95 + (e - pccmax) / (cmax - pccmax) * 0.05;
}

// LDR-FLIP written the slow, obvious way straight from the paper: full 2D kernels (no separation), double
// precision, clamp-to-edge borders. The library separates every filter; this checks that the separation,
// the borders and the feature pipeline agree with the textbook form. It shares only the colour transforms,
// which ColourSpaceConversionsOnKnownValues checks against published values.
std::vector<double> directFlip(const Image& test, const Image& reference, double ppd) {
  using namespace colorspace;
  const double pi = 3.14159265358979323846;
  const int w = test.width, h = test.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  auto at = [&](int x, int y) { return std::size_t(std::clamp(y, 0, h - 1)) * std::size_t(w) + std::size_t(std::clamp(x, 0, w - 1)); };

  // CSF: per channel a1·sqrt(π/b1)·exp(−π²d²/b1) + a2·sqrt(π/b2)·exp(−π²d²/b2), d in degrees, sum 1.
  const double a1[3] = {1.0, 1.0, 34.1}, b1[3] = {0.0047, 0.0053, 0.04};
  const double a2[3] = {0.0, 0.0, 13.5}, b2[3] = {1e-5, 1e-5, 0.025};
  const int r = static_cast<int>(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * pi * pi)) * ppd));
  const int kw = 2 * r + 1;
  std::vector<double> csf[3];
  for (int c = 0; c < 3; ++c) {
    csf[c].resize(std::size_t(kw * kw));
    double sum = 0.0;
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x) {
        const double d2 = double(x * x + y * y) / (ppd * ppd);
        const double v = a1[c] * std::sqrt(pi / b1[c]) * std::exp(-pi * pi * d2 / b1[c]) +
                         a2[c] * std::sqrt(pi / b2[c]) * std::exp(-pi * pi * d2 / b2[c]);
        csf[c][std::size_t((y + r) * kw + x + r)] = v;
        sum += v;
      }
    for (double& v : csf[c]) v /= sum;
  }
  // Feature detectors along x and y: first (edge) and second (point) derivatives of a Gaussian with
  // σ = 0.5·0.082·ppd pixels, positive and negative weights each normalised to ±1.
  const double sd = 0.5 * 0.082 * ppd;
  const int fr = static_cast<int>(std::ceil(3.0 * sd));
  const int fw = 2 * fr + 1;
  std::vector<double> edge[2], point[2];
  for (int axis = 0; axis < 2; ++axis) {
    edge[axis].resize(std::size_t(fw * fw));
    point[axis].resize(std::size_t(fw * fw));
    for (int y = -fr; y <= fr; ++y)
      for (int x = -fr; x <= fr; ++x) {
        const double g = std::exp(-double(x * x + y * y) / (2.0 * sd * sd));
        const double t = axis == 0 ? x : y;
        edge[axis][std::size_t((y + fr) * fw + x + fr)] = -t * g;
        point[axis][std::size_t((y + fr) * fw + x + fr)] = (t * t / (sd * sd) - 1.0) * g;
      }
    for (auto* k : {&edge[axis], &point[axis]}) {
      double pos = 0.0, neg = 0.0;
      for (double v : *k) (v > 0 ? pos : neg) += std::abs(v);
      for (double& v : *k) v /= v > 0 ? pos : neg;
    }
  }

  struct Prepared {
    std::vector<glm::vec3> lab;
    std::vector<double> edges, points;
  };
  auto prepare = [&](const Image& img) {
    std::vector<glm::dvec3> ycc(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t* p = &img.rgba[i * 4];
      const glm::vec3 lin{srgbToLinear(p[0] / 255.0f), srgbToLinear(p[1] / 255.0f), srgbToLinear(p[2] / 255.0f)};
      ycc[i] = glm::dvec3(xyzToYCxCz(linearRgbToXyz(lin)));
    }
    Prepared out{std::vector<glm::vec3>(n), std::vector<double>(n), std::vector<double>(n)};
    for (int py = 0; py < h; ++py)
      for (int px = 0; px < w; ++px) {
        glm::dvec3 f(0.0);
        for (int y = -r; y <= r; ++y)
          for (int x = -r; x <= r; ++x) {
            const glm::dvec3 v = ycc[at(px + x, py + y)];
            const std::size_t k = std::size_t((y + r) * kw + x + r);
            f += glm::dvec3(csf[0][k] * v.x, csf[1][k] * v.y, csf[2][k] * v.z);
          }
        const glm::vec3 rgb = glm::clamp(xyzToLinearRgb(yCxCzToXyz(glm::vec3(f))), glm::vec3(0.0f), glm::vec3(1.0f));
        const std::size_t i = std::size_t(py) * std::size_t(w) + std::size_t(px);
        out.lab[i] = huntAdjust(xyzToLab(linearRgbToXyz(rgb)));
        double e[2] = {0, 0}, q[2] = {0, 0};
        for (int y = -fr; y <= fr; ++y)
          for (int x = -fr; x <= fr; ++x) {
            const double lum = (ycc[at(px + x, py + y)].x + 16.0) / 116.0;
            const std::size_t k = std::size_t((y + fr) * fw + x + fr);
            for (int axis = 0; axis < 2; ++axis) {
              e[axis] += edge[axis][k] * lum;
              q[axis] += point[axis][k] * lum;
            }
          }
        out.edges[i] = std::hypot(e[0], e[1]);
        out.points[i] = std::hypot(q[0], q[1]);
      }
    return out;
  };
  const Prepared t = prepare(test), ref = prepare(reference);
  const double cmax = std::pow(hyab(huntAdjust(xyzToLab(linearRgbToXyz({0, 1, 0}))),
                                    huntAdjust(xyzToLab(linearRgbToXyz({0, 0, 1})))), 0.7);
  const double pccmax = 0.4 * cmax;
  std::vector<double> map(n);
  for (std::size_t i = 0; i < n; ++i) {
    double dc = std::pow(double(hyab(t.lab[i], ref.lab[i])), 0.7);
    dc = dc < pccmax ? dc * 0.95 / pccmax : 0.95 + (dc - pccmax) / (cmax - pccmax) * 0.05;
    const double df = std::pow(std::max(std::abs(t.edges[i] - ref.edges[i]), std::abs(t.points[i] - ref.points[i])) /
                               std::sqrt(2.0), 0.5);
    map[i] = std::pow(dc, 1.0 - df);
  }
  return map;
}

// ---------------------------------------------------------------------------------------------------------

TEST(ImageMetrics, IdenticalImagesAreExact) {
  const Image a = textured(48, 40);
  EXPECT_EQ(*psnr(a, a), std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(*ssim(a, a), 1.0);
  const Result<FlipResult> f = flip(a, a);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->mean, 0.0);
  ASSERT_EQ(f->map.size(), std::size_t(48 * 40));
  for (float v : f->map) ASSERT_EQ(v, 0.0f);
  const Result<ErrorMetrics> m = compare(a, a);
  ASSERT_TRUE(m.ok());
  EXPECT_TRUE(std::isinf(m->psnr));
  EXPECT_DOUBLE_EQ(m->ssim, 1.0);
  EXPECT_EQ(m->flipMean, 0.0);
}

TEST(ImageMetrics, ConstantOffsetPsnrIsExactAndErrorsGrowWithOffset) {
  const Image a = textured(48, 40);
  double lastSsim = 1.0, lastFlip = 0.0;
  for (int k : {1, 2, 4, 8, 16, 32}) {
    const Image b = offset(a, k);
    // MSE is exactly k², so PSNR = 10·log10(255²/k²).
    EXPECT_NEAR(*psnr(b, a), 20.0 * std::log10(255.0 / k), 1e-12) << "k=" << k;
    const double s = *ssim(b, a);
    const double f = flip(b, a)->mean;
    EXPECT_LT(s, lastSsim) << "k=" << k;
    EXPECT_GT(f, lastFlip) << "k=" << k;
    EXPECT_LE(f, 1.0);
    lastSsim = s;
    lastFlip = f;
  }
}

TEST(ImageMetrics, FloatPsnrAndRelMse) {
  ImageF a{4, 3, std::vector<glm::vec3>(12, glm::vec3(0.5f))};
  ImageF b = a;
  for (auto& c : b.rgb) c += glm::vec3(0.125f);  // exact in float: MSE = 1/64
  EXPECT_NEAR(*psnr(b, a), 10.0 * std::log10(64.0), 1e-9);
  EXPECT_NEAR(*psnr(b, a, 2.0), 10.0 * std::log10(4.0 * 64.0), 1e-9);
  EXPECT_TRUE(std::isinf(*psnr(a, a)));
  EXPECT_FALSE(psnr(a, a, 0.0).ok());

  EXPECT_EQ(*relMse(a, a), 0.0);
  ImageF one{2, 2, std::vector<glm::vec3>(4, glm::vec3(1.0f))};
  ImageF two{2, 2, std::vector<glm::vec3>(4, glm::vec3(2.0f))};
  EXPECT_NEAR(*relMse(two, one), 1.0 / 1.01, 1e-12);  // (2−1)² / (1² + 0.01)
  EXPECT_NEAR(*relMse(one, two), 1.0 / 4.01, 1e-12);  // relative to the reference, hence asymmetric
}

TEST(ImageMetrics, SsimOfUniformImagesIsTheLuminanceTerm) {
  // σx = σy = σxy = 0, so SSIM = (2·μx·μy + C1) / (μx² + μy² + C1) at every window.
  const Image a = solid(20, 16, {100, 100, 100, 255});
  const Image b = solid(20, 16, {140, 140, 140, 255});
  const double c1 = (0.01 * 255.0) * (0.01 * 255.0);
  EXPECT_NEAR(*ssim(a, b), (2.0 * 100 * 140 + c1) / (100.0 * 100 + 140.0 * 140 + c1), 1e-9);
  // Images smaller than the 11×11 window still work (the window is cut to the image).
  const Image tinyA = solid(3, 2, {10, 10, 10, 255});
  const Image tinyB = solid(3, 2, {20, 20, 20, 255});
  EXPECT_NEAR(*ssim(tinyA, tinyB), (2.0 * 10 * 20 + c1) / (100.0 + 400.0 + c1), 1e-9);
}

TEST(ImageMetrics, SsimSeesStructureThatPsnrMisses) {
  // Same mean and MSE either way: a noise-like change (the mirrored texture) vs a constant offset.
  const Image a = textured(48, 40);
  const Image shifted = offset(a, 10);
  EXPECT_GT(*ssim(shifted, a), 0.9);  // only the luminance term drops
  Image scrambled = a;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) scrambled.set(x, y, a.at(a.width - 1 - x, y));
  EXPECT_LT(*ssim(scrambled, a), *ssim(shifted, a));
}

TEST(ImageMetrics, ShiftedEdgeOnlyErrsNearTheEdge) {
  const int w = 64, h = 24;
  const Image a = step(w, h, 32);
  const Image b = step(w, h, 33);  // differs only in column 32
  const Result<FlipResult> f = flip(b, a);
  ASSERT_TRUE(f.ok());
  // At 67 ppd the CSF filters reach 10 px and the feature detectors 9 px (docs/metrics.md), so a change in
  // column 32 can only show up in columns 22..42.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = f->map[std::size_t(y * w + x)];
      if (x < 22 || x > 42) {
        EXPECT_EQ(v, 0.0f) << x << "," << y;
      }
      if (x >= 31 && x <= 33) {
        EXPECT_GT(v, 0.1f) << x << "," << y;
      }
    }
  EXPECT_GT(f->mean, 0.0);
  // The changed pixel itself is black vs white: its error is large.
  EXPECT_GT(f->map[std::size_t(10 * w + 32)], 0.5f);
}

TEST(ImageMetrics, FlipMatchesTheDirectTwoDimensionalForm) {
  const Image a = textured(40, 30);
  Image b = offset(a, 6);
  for (int y = 0; y < 30; ++y) b.set(y, y, {250, 20, 20, 255});  // a diagonal line: edges and colour
  b.set(0, 29, {255, 255, 255, 255});                             // a corner dot: borders and points
  for (double ppd : {67.0, 25.0}) {
    const FlipResult f = *flip(b, a, ppd);
    const std::vector<double> d = directFlip(b, a, ppd);
    double mean = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      ASSERT_NEAR(f.map[i], d[i], 2e-5) << "pixel " << i << " at " << ppd << " ppd";
      mean += d[i];
    }
    EXPECT_NEAR(f.mean, mean / double(d.size()), 1e-6);
  }
}

TEST(ImageMetrics, BlackVersusWhiteIsNearOne) {
  // Uniform images: the CSF filters (normalised, clamp-to-edge) leave them unchanged and there are no
  // features, so FLIP is the colour term alone: HyAB(white, black) = 100 (L* 100 vs 0, no chroma).
  const Image black = solid(16, 16, {0, 0, 0, 255});
  const Image white = solid(16, 16, {255, 255, 255, 255});
  const double expected = expectedUniformFlip(100.0);  // ≈ 0.9674
  EXPECT_NEAR(flip(white, black)->mean, expected, 1e-4);
  EXPECT_NEAR(expected, 0.9674, 1e-4);
  // Mid grey (sRGB 128, L* = 53.585 by the CIE formula) against black.
  const Image grey = solid(16, 16, {128, 128, 128, 255});
  EXPECT_NEAR(flip(grey, black)->mean, expectedUniformFlip(53.585), 1e-4);
}

TEST(ImageMetrics, GreenVersusBlueIsExactlyTheMaximum) {
  // The paper normalises colour differences by the distance between pure green and pure blue, so that pair
  // maps to 1 by construction.
  const Image green = solid(12, 12, {0, 255, 0, 255});
  const Image blue = solid(12, 12, {0, 0, 255, 255});
  EXPECT_NEAR(flip(green, blue)->mean, 1.0, 1e-4);
}

TEST(ImageMetrics, MetricsAreSymmetric) {
  const Image a = textured(40, 32);
  Image b = offset(a, 7);
  b.set(5, 5, {255, 0, 0, 255});
  b.set(20, 10, {0, 0, 0, 255});
  EXPECT_EQ(*psnr(a, b), *psnr(b, a));
  EXPECT_EQ(*ssim(a, b), *ssim(b, a));
  const FlipResult ab = *flip(a, b), ba = *flip(b, a);
  EXPECT_EQ(ab.mean, ba.mean);
  EXPECT_EQ(ab.map, ba.map);
}

TEST(ImageMetrics, PixelsPerDegreeChangesTheFilterReach) {
  // Seen from further away (more pixels per degree) a 1-pixel detail is smaller: the CSF blurs it more, so
  // a single dark pixel on white costs less.
  const Image white = solid(48, 48, {255, 255, 255, 255});
  Image dot = white;
  dot.set(24, 24, {0, 0, 0, 255});
  EXPECT_GT(flip(dot, white, 30.0)->mean, 0.0);
  EXPECT_GT(flip(dot, white, 120.0)->mean, 0.0);
  EXPECT_GT(flip(dot, white, 30.0)->map[24 * 48 + 24], flip(dot, white, 120.0)->map[24 * 48 + 24]);
  EXPECT_NEAR(pixelsPerDegree(0.7, 0.7, 3840.0), 67.02, 0.01);  // the paper's default observer
  EXPECT_FALSE(flip(dot, white, 0.0).ok());
}

TEST(ImageMetrics, SizeMismatchAndEmptyImagesAreErrors) {
  const Image a = solid(8, 8, {1, 2, 3, 255});
  const Image b = solid(8, 9, {1, 2, 3, 255});
  EXPECT_FALSE(psnr(a, b).ok());
  EXPECT_FALSE(ssim(a, b).ok());
  EXPECT_FALSE(flip(a, b).ok());
  const Result<ErrorMetrics> m = compare(a, b);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("8x8 vs 8x9"), std::string::npos) << m.error().message;
  EXPECT_FALSE(compare(Image{}, Image{}).ok());
  Image broken = a;
  broken.rgba.pop_back();
  EXPECT_FALSE(flip(broken, a).ok());
  EXPECT_FALSE(relMse(ImageF{2, 2, std::vector<glm::vec3>(4)}, ImageF{2, 1, std::vector<glm::vec3>(2)}).ok());
}

TEST(ImageMetrics, ColourSpaceConversionsOnKnownValues) {
  using namespace colorspace;
  EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(srgbToLinear(0.0f), 0.0f);
  EXPECT_NEAR(srgbToLinear(0.5f), 0.214041f, 1e-6f);  // ((0.5 + 0.055) / 1.055)^2.4

  const glm::vec3 white = linearRgbToXyz(glm::vec3(1.0f));
  EXPECT_NEAR(white.y, 1.0f, 1e-6f);
  EXPECT_NEAR(white.x, 0.95047f, 1e-4f);  // D65 white point, Y = 1
  EXPECT_NEAR(white.z, 1.08883f, 1e-3f);
  const glm::vec3 labWhite = xyzToLab(white);
  EXPECT_NEAR(labWhite.x, 100.0f, 1e-4f);
  EXPECT_NEAR(labWhite.y, 0.0f, 1e-4f);
  EXPECT_NEAR(labWhite.z, 0.0f, 1e-4f);
  const glm::vec3 yccWhite = xyzToYCxCz(white);
  EXPECT_NEAR(yccWhite.x, 100.0f, 1e-4f);
  EXPECT_NEAR(yccWhite.y, 0.0f, 1e-4f);
  EXPECT_NEAR(yccWhite.z, 0.0f, 1e-4f);
  EXPECT_NEAR(xyzToLab(glm::vec3(0.0f)).x, 0.0f, 1e-6f);

  // sRGB primaries at their published L*a*b* (D65) coordinates.
  const glm::vec3 red = xyzToLab(linearRgbToXyz({1, 0, 0}));
  EXPECT_NEAR(red.x, 53.2408f, 0.01f);
  EXPECT_NEAR(red.y, 80.0925f, 0.01f);
  EXPECT_NEAR(red.z, 67.2032f, 0.01f);
  const glm::vec3 green = xyzToLab(linearRgbToXyz({0, 1, 0}));
  EXPECT_NEAR(green.x, 87.7347f, 0.01f);
  EXPECT_NEAR(green.y, -86.1827f, 0.01f);
  EXPECT_NEAR(green.z, 83.1793f, 0.01f);

  // Round trips, and the Hunt adjustment / HyAB by their definitions.
  const glm::vec3 rgb{0.2f, 0.5f, 0.9f};
  const glm::vec3 back = xyzToLinearRgb(yCxCzToXyz(xyzToYCxCz(linearRgbToXyz(rgb))));
  EXPECT_NEAR(back.r, rgb.r, 1e-5f);
  EXPECT_NEAR(back.g, rgb.g, 1e-5f);
  EXPECT_NEAR(back.b, rgb.b, 1e-5f);
  const glm::vec3 hunted = huntAdjust({50.0f, 20.0f, -40.0f});
  EXPECT_FLOAT_EQ(hunted.y, 10.0f);
  EXPECT_FLOAT_EQ(hunted.z, -20.0f);
  EXPECT_FLOAT_EQ(hyab({10, 0, 0}, {40, 3, 4}), 35.0f);
}

TEST(ImageMetrics, MagmaEndpointsAndHeatmap) {
  // Entries 0 and 255 of matplotlib's magma table.
  const glm::vec3 lo = magma(0.0f), hi = magma(1.0f);
  EXPECT_NEAR(lo.r, 0.001462f, 1e-6f);
  EXPECT_NEAR(lo.g, 0.000466f, 1e-6f);
  EXPECT_NEAR(lo.b, 0.013866f, 1e-6f);
  EXPECT_NEAR(hi.r, 0.987053f, 1e-6f);
  EXPECT_NEAR(hi.g, 0.991438f, 1e-6f);
  EXPECT_NEAR(hi.b, 0.749504f, 1e-6f);
  EXPECT_EQ(magma(-1.0f), lo);  // clamped
  EXPECT_EQ(magma(2.0f), hi);
  // Entry 128 (t = 128/255) is a knot; an off-knot entry, 100 (0.537755, 0.156894, 0.506551), is within 1/255.
  EXPECT_NEAR(magma(128.0f / 255.0f).r, 0.716387f, 1e-5f);
  const glm::vec3 e100 = magma(100.0f / 255.0f);
  EXPECT_NEAR(e100.r, 0.537755f, 1.0f / 255.0f);
  EXPECT_NEAR(e100.g, 0.156894f, 1.0f / 255.0f);
  EXPECT_NEAR(e100.b, 0.506551f, 1.0f / 255.0f);
  // Magma's lightness rises monotonically: that is what makes it readable as "more error".
  float last = -1.0f;
  for (int i = 0; i <= 64; ++i) {
    const glm::vec3 c = magma(float(i) / 64.0f);
    const float luma = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
    EXPECT_GT(luma, last) << i;
    last = luma;
  }

  FlipResult r;
  r.width = 2;
  r.height = 1;
  r.map = {0.0f, 1.0f};
  const Image img = heatmap(r);
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  EXPECT_EQ(img.at(0, 0), glm::u8vec4(0, 0, 4, 255));
  EXPECT_EQ(img.at(1, 0), glm::u8vec4(252, 253, 191, 255));
}

}  // namespace
}  // namespace tandem
