#include "tandem/ImageMetrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <string>

namespace tandem {

double pixelsPerDegree(double distanceM, double widthM, double resolutionX) {
  return distanceM * (resolutionX / widthM) * (std::numbers::pi / 180.0);
}

// ---------------------------------------------------------------------------------------------------------
// Colour transforms. sRGB primaries, D65 white. Single precision like the FLIP reference code, whose
// published error maps were produced in float.
namespace colorspace {
namespace {
// XYZ of linear RGB (1, 1, 1): the D65 white of the sRGB matrix below, with Y = 1.
constexpr glm::vec3 kWhite{0.950428545f, 1.0f, 1.088900371f};
constexpr float kLabDelta = 6.0f / 29.0f;

float labF(float t) {
  // CIE's exact form: cube root above (6/29)³, a linear segment below so that f is C¹ at the join.
  return t > kLabDelta * kLabDelta * kLabDelta ? std::cbrt(t) : t / (3.0f * kLabDelta * kLabDelta) + 4.0f / 29.0f;
}
}  // namespace

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

glm::vec3 linearRgbToXyz(glm::vec3 c) {
  // The sRGB→XYZ matrix as exact rationals of the primaries' chromaticities, so that the white point is
  // consistent with kWhite to float precision.
  return {(10135552.0f * c.r + 8788810.0f * c.g + 4435075.0f * c.b) / 24577794.0f,
          (2613072.0f * c.r + 8788810.0f * c.g + 887015.0f * c.b) / 12288897.0f,
          (1425312.0f * c.r + 8788810.0f * c.g + 70074185.0f * c.b) / 73733382.0f};
}

glm::vec3 xyzToLinearRgb(glm::vec3 v) {
  return {3.241003233f * v.x - 1.537398969f * v.y - 0.498615882f * v.z,
          -0.969224252f * v.x + 1.875929984f * v.y + 0.041554226f * v.z,
          0.055639420f * v.x - 0.204011206f * v.y + 1.057148977f * v.z};
}

glm::vec3 xyzToYCxCz(glm::vec3 xyz) {
  const glm::vec3 n = xyz / kWhite;
  return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

glm::vec3 yCxCzToXyz(glm::vec3 v) {
  const float y = (v.x + 16.0f) / 116.0f;
  return glm::vec3{y + v.y / 500.0f, y, y - v.z / 200.0f} * kWhite;
}

glm::vec3 xyzToLab(glm::vec3 xyz) {
  const glm::vec3 n = xyz / kWhite;
  const float fx = labF(n.x), fy = labF(n.y), fz = labF(n.z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

glm::vec3 huntAdjust(glm::vec3 lab) {
  // Hunt effect: chroma is perceived weaker at low luminance, so chroma is scaled by L/100.
  return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z};
}

float hyab(glm::vec3 p, glm::vec3 q) {
  // HyAB (Abasi et al. 2020): city-block in lightness, Euclidean in chroma; better than ΔE for large
  // differences, which is what FLIP is about.
  const float da = p.y - q.y, db = p.z - q.z;
  return std::abs(p.x - q.x) + std::sqrt(da * da + db * db);
}
}  // namespace colorspace

namespace {

// ---------------------------------------------------------------------------------------------------------
// Input checks shared by every two-image entry point.
template <class Img>
Result<void> checkPair(const Img& test, const Img& reference, std::size_t valuesPerPixel, std::size_t stored,
                       std::size_t storedRef, const char* metric) {
  if (test.width <= 0 || test.height <= 0 || reference.width <= 0 || reference.height <= 0)
    return Error{std::string(metric) + ": an image is empty"};
  if (test.width != reference.width || test.height != reference.height)
    return Error{std::string(metric) + ": image sizes differ (" + std::to_string(test.width) + "x" +
                 std::to_string(test.height) + " vs " + std::to_string(reference.width) + "x" +
                 std::to_string(reference.height) + ")"};
  const std::size_t expected = std::size_t(test.width) * std::size_t(test.height) * valuesPerPixel;
  if (stored != expected || storedRef != expected)
    return Error{std::string(metric) + ": an image's pixel buffer does not match its width and height"};
  return {};
}

Result<void> checkPair(const Image& t, const Image& r, const char* metric) {
  return checkPair(t, r, 4, t.rgba.size(), r.rgba.size(), metric);
}
Result<void> checkPair(const ImageF& t, const ImageF& r, const char* metric) {
  return checkPair(t, r, 1, t.rgb.size(), r.rgb.size(), metric);
}

std::size_t idx(int x, int y, int w) { return std::size_t(y) * std::size_t(w) + std::size_t(x); }

// ---------------------------------------------------------------------------------------------------------
// Separable convolution over a single-channel plane with clamp-to-edge borders. FLIP's reference code uses
// "replicate" borders; it keeps a uniform image uniform right up to its border, so a uniform difference
// gives a uniform FLIP map.
using Plane = std::vector<float>;
using Kernel = std::vector<float>;  // odd length, centre in the middle

Plane convolveRows(const Plane& src, int w, int h, const Kernel& k) {
  const int r = static_cast<int>(k.size() / 2);
  Plane dst(src.size());
  std::vector<float> padded(std::size_t(w + 2 * r));
  for (int y = 0; y < h; ++y) {
    const float* row = &src[idx(0, y, w)];
    for (int i = 0; i < w + 2 * r; ++i) padded[std::size_t(i)] = row[std::clamp(i - r, 0, w - 1)];
    float* out = &dst[idx(0, y, w)];
    for (int x = 0; x < w; ++x) {
      float s = 0.0f;
      for (std::size_t j = 0; j < k.size(); ++j) s += k[j] * padded[std::size_t(x) + j];
      out[x] = s;
    }
  }
  return dst;
}

Plane convolveCols(const Plane& src, int w, int h, const Kernel& k) {
  const int r = static_cast<int>(k.size() / 2);
  Plane dst(src.size(), 0.0f);
  // Row-at-a-time accumulation keeps the inner loop contiguous in memory.
  for (int y = 0; y < h; ++y) {
    float* out = &dst[idx(0, y, w)];
    for (int j = -r; j <= r; ++j) {
      const float kj = k[std::size_t(j + r)];
      const float* in = &src[idx(0, std::clamp(y + j, 0, h - 1), w)];
      for (int x = 0; x < w; ++x) out[x] += kj * in[x];
    }
  }
  return dst;
}

Plane convolve(const Plane& src, int w, int h, const Kernel& kx, const Kernel& ky) {
  return convolveCols(convolveRows(src, w, h, kx), w, h, ky);
}

// ---------------------------------------------------------------------------------------------------------
// LDR-FLIP constants (Andersson et al. 2020).
constexpr float kQc = 0.7f;     // exponent on the HyAB colour distance
constexpr float kPc = 0.4f;     // the fraction of cmax below which errors are mapped to [0, pt]
constexpr float kPt = 0.95f;    // the share of [0, 1] given to errors below pc·cmax
constexpr float kQf = 0.5f;     // exponent on the feature difference
constexpr float kFeatureWidthDegrees = 0.082f;  // edge/point detector width w; σ = w/2 in pixels

// Contrast sensitivity functions in the spatial domain: per channel a sum of two Gaussians
// a·sqrt(π/b)·exp(−π²·r²/b), r in degrees (the paper's table of CSF parameters, fitted to Movshon & Kiorpes
// and Mullen). Channel order Y (achromatic), Cx (red–green), Cz (blue–yellow).
struct CsfTerm {
  float a, b;
};
constexpr std::array<std::array<CsfTerm, 2>, 3> kCsf{{
    {{{1.0f, 0.0047f}, {0.0f, 1.0e-5f}}},
    {{{1.0f, 0.0053f}, {0.0f, 1.0e-5f}}},
    {{{34.1f, 0.04f}, {13.5f, 0.025f}}},
}};

// One separable Gaussian term of a channel's CSF filter: its normalised 1D kernel, and its share of the
// normalised 2D filter.
struct CsfPass {
  Kernel k;
  float weight = 0.0f;
};

std::array<std::vector<CsfPass>, 3> csfFilters(double ppd) {
  const double pi = std::numbers::pi;
  float bMax = 0.0f;
  for (const auto& ch : kCsf)
    for (const CsfTerm& t : ch) bMax = std::max(bMax, t.b);
  // The widest Gaussian has standard deviation sqrt(b/(2π²)) degrees; cover 3 of them.
  const int radius = static_cast<int>(std::ceil(3.0 * std::sqrt(double(bMax) / (2.0 * pi * pi)) * ppd));

  std::array<std::vector<CsfPass>, 3> filters;
  for (std::size_t c = 0; c < 3; ++c) {
    // exp(−π²(x²+y²)/b) = exp(−π²x²/b)·exp(−π²y²/b): each term is separable, and normalising the 2D sum to 1
    // amounts to weighting each term's normalised 1D kernels by amplitude·(1D sum)² / total.
    double total = 0.0;
    std::vector<std::pair<Kernel, double>> terms;
    for (const CsfTerm& t : kCsf[c]) {
      if (t.a == 0.0f) continue;
      Kernel k(std::size_t(2 * radius + 1));
      double sum = 0.0;
      for (int i = -radius; i <= radius; ++i) {
        const double x = double(i) / ppd;  // degrees
        const double v = std::exp(-pi * pi * x * x / double(t.b));
        k[std::size_t(i + radius)] = static_cast<float>(v);
        sum += v;
      }
      for (float& v : k) v = static_cast<float>(double(v) / sum);
      const double mass = double(t.a) * std::sqrt(pi / double(t.b)) * sum * sum;
      total += mass;
      terms.emplace_back(std::move(k), mass);
    }
    for (auto& [k, mass] : terms) filters[c].push_back({std::move(k), static_cast<float>(mass / total)});
  }
  return filters;
}

// Detector kernels for the feature pipeline: 1D parts of the separable first- and second-derivative-of-
// Gaussian filters. Positive and negative weights are each normalised to sum to ±1 (as in the paper), so the
// response to a unit step or unit dot is at most 1 per axis.
struct FeatureKernels {
  Kernel smooth, edge, point;
};

void normaliseSigned(Kernel& k) {
  double pos = 0.0, neg = 0.0;
  for (float v : k) (v > 0.0f ? pos : neg) += std::abs(double(v));
  for (float& v : k) {
    if (v > 0.0f) v = static_cast<float>(double(v) / pos);
    else if (v < 0.0f) v = static_cast<float>(double(v) / neg);
  }
}

FeatureKernels featureKernels(double ppd) {
  const double sigma = 0.5 * double(kFeatureWidthDegrees) * ppd;
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  const std::size_t n = std::size_t(2 * radius + 1);
  FeatureKernels f{Kernel(n), Kernel(n), Kernel(n)};
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = double(i);
    const double g = std::exp(-x * x / (2.0 * sigma * sigma));
    const std::size_t j = std::size_t(i + radius);
    f.smooth[j] = static_cast<float>(g);
    f.edge[j] = static_cast<float>(-x * g);
    f.point[j] = static_cast<float>((x * x / (sigma * sigma) - 1.0) * g);
    sum += g;
  }
  // The 2D kernels are edge(x)·smooth(y) and point(x)·smooth(y); since smooth > 0, normalising the 2D
  // kernel's positive and negative parts equals normalising each 1D factor on its own.
  for (float& v : f.smooth) v = static_cast<float>(double(v) / sum);
  normaliseSigned(f.edge);
  normaliseSigned(f.point);
  return f;
}

// Per-image work of LDR-FLIP: the Hunt-adjusted L*a*b* of the CSF-filtered image (colour pipeline) and the
// edge and point feature magnitudes of its luminance (feature pipeline).
struct FlipPrepared {
  std::vector<glm::vec3> lab;
  Plane edges, points;
};

FlipPrepared prepareFlip(const Image& img, const std::array<std::vector<CsfPass>, 3>& csf,
                         const FeatureKernels& fk) {
  const int w = img.width, h = img.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  std::array<Plane, 3> ycc{Plane(n), Plane(n), Plane(n)};
  // The sRGB decode of the 256 possible byte values, once.
  std::array<float, 256> decode{};
  for (std::size_t i = 0; i < 256; ++i) decode[i] = colorspace::srgbToLinear(static_cast<float>(i) / 255.0f);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &img.rgba[i * 4];
    const glm::vec3 v = colorspace::xyzToYCxCz(colorspace::linearRgbToXyz({decode[p[0]], decode[p[1]], decode[p[2]]}));
    ycc[0][i] = v.x;
    ycc[1][i] = v.y;
    ycc[2][i] = v.z;
  }

  FlipPrepared out;
  // Colour pipeline: CSF-filter each opponent channel, back to linear RGB clamped to the displayable range
  // (filtering can leave the gamut), then Hunt-adjusted L*a*b*.
  std::array<Plane, 3> filtered;
  for (std::size_t c = 0; c < 3; ++c) {
    filtered[c].assign(n, 0.0f);
    for (const CsfPass& pass : csf[c]) {
      const Plane f = convolve(ycc[c], w, h, pass.k, pass.k);
      for (std::size_t i = 0; i < n; ++i) filtered[c][i] += pass.weight * f[i];
    }
  }
  out.lab.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 rgb = colorspace::xyzToLinearRgb(colorspace::yCxCzToXyz({filtered[0][i], filtered[1][i], filtered[2][i]}));
    rgb = glm::clamp(rgb, glm::vec3(0.0f), glm::vec3(1.0f));
    out.lab[i] = colorspace::huntAdjust(colorspace::xyzToLab(colorspace::linearRgbToXyz(rgb)));
  }

  // Feature pipeline on the unfiltered achromatic channel normalised to [0, 1] (that is, Y/Yn).
  Plane lum(n);
  for (std::size_t i = 0; i < n; ++i) lum[i] = (ycc[0][i] + 16.0f) / 116.0f;
  const Plane rowsSmooth = convolveRows(lum, w, h, fk.smooth);
  const Plane edgeX = convolveCols(convolveRows(lum, w, h, fk.edge), w, h, fk.smooth);
  const Plane edgeY = convolveCols(rowsSmooth, w, h, fk.edge);
  const Plane pointX = convolveCols(convolveRows(lum, w, h, fk.point), w, h, fk.smooth);
  const Plane pointY = convolveCols(rowsSmooth, w, h, fk.point);
  out.edges.resize(n);
  out.points.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    out.edges[i] = std::hypot(edgeX[i], edgeY[i]);
    out.points[i] = std::hypot(pointX[i], pointY[i]);
  }
  return out;
}

// The largest colour distance FLIP expects: between pure green and pure blue, after Hunt adjustment and the
// qc compression. Distances are expressed relative to it.
float flipMaxColorDistance() {
  using namespace colorspace;
  const glm::vec3 green = huntAdjust(xyzToLab(linearRgbToXyz({0.0f, 1.0f, 0.0f})));
  const glm::vec3 blue = huntAdjust(xyzToLab(linearRgbToXyz({0.0f, 0.0f, 1.0f})));
  return std::pow(hyab(green, blue), kQc);
}

// ---------------------------------------------------------------------------------------------------------
// SSIM helpers: separable "valid" convolution (outputs only where the window lies inside the image).
std::vector<double> validRows(const std::vector<double>& src, int w, int h, const std::vector<double>& k) {
  const int kn = static_cast<int>(k.size());
  const int ow = w - kn + 1;
  std::vector<double> dst(std::size_t(ow) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < ow; ++x) {
      double s = 0.0;
      for (int j = 0; j < kn; ++j) s += k[std::size_t(j)] * src[idx(x + j, y, w)];
      dst[idx(x, y, ow)] = s;
    }
  return dst;
}

std::vector<double> validCols(const std::vector<double>& src, int w, int h, const std::vector<double>& k) {
  const int kn = static_cast<int>(k.size());
  const int oh = h - kn + 1;
  std::vector<double> dst(std::size_t(w) * std::size_t(oh), 0.0);
  for (int y = 0; y < oh; ++y)
    for (int j = 0; j < kn; ++j) {
      const double kj = k[std::size_t(j)];
      for (int x = 0; x < w; ++x) dst[idx(x, y, w)] += kj * src[idx(x, y + j, w)];
    }
  return dst;
}

std::vector<double> ssimWindow(int radius) {
  constexpr double kSigma = 1.5;
  std::vector<double> k(std::size_t(2 * radius + 1));
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    k[std::size_t(i + radius)] = std::exp(-double(i * i) / (2.0 * kSigma * kSigma));
    sum += k[std::size_t(i + radius)];
  }
  for (double& v : k) v /= sum;
  return k;
}

// The magma colour map (matplotlib; Smith & van der Walt, CC0): entries 0, 16, 32, ..., 240 and 255 of its
// 256-entry table. Linear interpolation between them stays within about 1/255 of the full table, which is
// below what an 8-bit heat map can show anyway.
constexpr std::array<glm::vec3, 17> kMagma{{
    {0.001462f, 0.000466f, 0.013866f}, {0.039608f, 0.031090f, 0.133515f}, {0.113094f, 0.065492f, 0.276784f},
    {0.211718f, 0.061992f, 0.418647f}, {0.316654f, 0.071690f, 0.485380f}, {0.414709f, 0.110431f, 0.504662f},
    {0.512831f, 0.148179f, 0.507648f}, {0.613617f, 0.181811f, 0.498536f}, {0.716387f, 0.214982f, 0.475290f},
    {0.816914f, 0.255895f, 0.436461f}, {0.904281f, 0.319610f, 0.388137f}, {0.960949f, 0.418323f, 0.359630f},
    {0.986700f, 0.535582f, 0.382210f}, {0.996096f, 0.653659f, 0.446213f}, {0.996898f, 0.769591f, 0.534892f},
    {0.992440f, 0.884330f, 0.640099f}, {0.987053f, 0.991438f, 0.749504f},
}};

}  // namespace

// ---------------------------------------------------------------------------------------------------------

Result<double> psnr(const Image& test, const Image& reference) {
  if (auto ok = checkPair(test, reference, "PSNR"); !ok) return ok.error();
  // Integer sum of squared differences: exact, so a constant offset k gives exactly 20·log10(255/k).
  std::uint64_t sse = 0;
  const std::size_t n = std::size_t(test.width) * std::size_t(test.height);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t c = 0; c < 3; ++c) {
      const int d = int(test.rgba[i * 4 + c]) - int(reference.rgba[i * 4 + c]);
      sse += std::uint64_t(d * d);
    }
  if (sse == 0) return std::numeric_limits<double>::infinity();
  const double mse = double(sse) / double(n * 3);
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

Result<double> psnr(const ImageF& test, const ImageF& reference, double peak) {
  if (auto ok = checkPair(test, reference, "PSNR"); !ok) return ok.error();
  if (!(peak > 0.0)) return Error{"PSNR: the peak value must be positive"};
  double sse = 0.0;
  for (std::size_t i = 0; i < test.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double d = double(test.rgb[i][c]) - double(reference.rgb[i][c]);
      sse += d * d;
    }
  if (sse == 0.0) return std::numeric_limits<double>::infinity();
  const double mse = sse / double(test.rgb.size() * 3);
  return 10.0 * std::log10(peak * peak / mse);
}

Result<double> relMse(const ImageF& test, const ImageF& reference) {
  if (auto ok = checkPair(test, reference, "relMSE"); !ok) return ok.error();
  double sum = 0.0;
  for (std::size_t i = 0; i < test.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = double(test.rgb[i][c]), y = double(reference.rgb[i][c]);
      // The 0.01 keeps near-black reference pixels from dominating.
      sum += (x - y) * (x - y) / (y * y + 0.01);
    }
  return sum / double(test.rgb.size() * 3);
}

Result<double> ssim(const Image& test, const Image& reference) {
  if (auto ok = checkPair(test, reference, "SSIM"); !ok) return ok.error();
  const int w = test.width, h = test.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  constexpr double kC1 = (0.01 * 255.0) * (0.01 * 255.0);
  constexpr double kC2 = (0.03 * 255.0) * (0.03 * 255.0);

  std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* a = &test.rgba[i * 4];
    const std::uint8_t* b = &reference.rgba[i * 4];
    x[i] = 0.2126 * a[0] + 0.7152 * a[1] + 0.0722 * a[2];
    y[i] = 0.2126 * b[0] + 0.7152 * b[1] + 0.0722 * b[2];
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  const std::vector<double> kx = ssimWindow(std::min(5, (w - 1) / 2));
  const std::vector<double> ky = ssimWindow(std::min(5, (h - 1) / 2));
  auto window = [&](const std::vector<double>& p) { return validCols(validRows(p, w, h, kx), w - int(kx.size()) + 1, h, ky); };
  const std::vector<double> mx = window(x), my = window(y), sxx = window(xx), syy = window(yy), sxy = window(xy);

  double sum = 0.0;
  for (std::size_t i = 0; i < mx.size(); ++i) {
    const double vx = sxx[i] - mx[i] * mx[i];
    const double vy = syy[i] - my[i] * my[i];
    const double cov = sxy[i] - mx[i] * my[i];
    sum += ((2.0 * mx[i] * my[i] + kC1) * (2.0 * cov + kC2)) /
           ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (vx + vy + kC2));
  }
  return sum / double(mx.size());
}

Result<FlipResult> flip(const Image& test, const Image& reference, double pixelsPerDegree) {
  if (auto ok = checkPair(test, reference, "FLIP"); !ok) return ok.error();
  if (!(pixelsPerDegree > 0.0) || !std::isfinite(pixelsPerDegree))
    return Error{"FLIP: pixels per degree must be a positive number"};

  const auto csf = csfFilters(pixelsPerDegree);
  const FeatureKernels fk = featureKernels(pixelsPerDegree);
  const FlipPrepared t = prepareFlip(test, csf, fk);
  const FlipPrepared r = prepareFlip(reference, csf, fk);

  const float cmax = flipMaxColorDistance();
  const float pccmax = kPc * cmax;
  const float invSqrt2 = 1.0f / std::sqrt(2.0f);

  FlipResult out;
  out.width = test.width;
  out.height = test.height;
  out.map.assign(t.lab.size(), 0.0f);
  double sum = 0.0;
  for (std::size_t i = 0; i < out.map.size(); ++i) {
    // Colour: compress the HyAB distance, then map [0, pc·cmax) linearly onto [0, pt) and the rest onto
    // [pt, 1], so that the small differences that matter most get most of the range.
    float dc = std::pow(colorspace::hyab(t.lab[i], r.lab[i]), kQc);
    dc = dc < pccmax ? dc * (kPt / pccmax) : kPt + (dc - pccmax) / (cmax - pccmax) * (1.0f - kPt);
    // Features: the larger of the edge and point magnitude differences; each magnitude is at most sqrt(2)
    // (unit response per axis), hence the 1/sqrt(2) to keep it in [0, 1].
    const float de = std::abs(t.edges[i] - r.edges[i]);
    const float dp = std::abs(t.points[i] - r.points[i]);
    const float df = std::pow(invSqrt2 * std::max(de, dp), kQf);
    // Combination: a feature difference raises the colour error towards 1 (exponent below 1).
    const float e = std::pow(dc, 1.0f - df);
    out.map[i] = e;
    sum += double(e);
  }
  out.mean = sum / double(out.map.size());
  return out;
}

glm::vec3 magma(float t) {
  const float p = std::clamp(t, 0.0f, 1.0f) * 255.0f;  // position in the 256-entry table
  // Knot i sits at table index 16·i, except the last, which is entry 255.
  const int seg = std::min(static_cast<int>(p / 16.0f), 15);
  const float lo = 16.0f * static_cast<float>(seg);
  const float hi = seg == 15 ? 255.0f : lo + 16.0f;
  const float f = std::clamp((p - lo) / (hi - lo), 0.0f, 1.0f);
  return glm::mix(kMagma[std::size_t(seg)], kMagma[std::size_t(seg + 1)], f);
}

Image heatmap(const FlipResult& result) {
  Image img;
  img.width = result.width;
  img.height = result.height;
  img.rgba.resize(result.map.size() * 4);
  for (std::size_t i = 0; i < result.map.size(); ++i) {
    const glm::vec3 c = magma(result.map[i]);
    for (std::size_t k = 0; k < 3; ++k)
      img.rgba[i * 4 + k] = static_cast<std::uint8_t>(std::lround(std::clamp(c[int(k)], 0.0f, 1.0f) * 255.0f));
    img.rgba[i * 4 + 3] = 255;
  }
  return img;
}

Result<ErrorMetrics> compare(const Image& test, const Image& reference, double pixelsPerDegree) {
  Result<double> p = psnr(test, reference);
  if (!p) return p.error();
  Result<double> s = ssim(test, reference);
  if (!s) return s.error();
  Result<FlipResult> f = flip(test, reference, pixelsPerDegree);
  if (!f) return f.error();
  return ErrorMetrics{*p, *s, f->mean};
}

}  // namespace tandem
