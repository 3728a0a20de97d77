#pragma once
// Image-error metrics: how far a rendered image is from a reference (docs/metrics.md).
//
//   Result<ErrorMetrics> m = compare(test, reference);
//   if (!m) { std::cerr << m.error().message << "\n"; return 1; }
//   std::cout << m->psnr << " dB, SSIM " << m->ssim << ", FLIP " << m->flipMean << "\n";
//
// Every entry point that takes two images returns an Error when their sizes differ or they are empty, since
// the images usually come from files. Convention: the first argument is the test image, the second the
// reference. PSNR, SSIM and FLIP are symmetric; relMSE divides by the reference. The order is the same
// everywhere so that callers never have to remember which metric cares.
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Image.h"
#include "tandem/Result.h"

namespace tandem {

/// Default FLIP observer: a 0.7 m wide, 3840-pixel monitor seen from 0.7 m, i.e. 67 pixels per degree
/// (Andersson et al. 2020, section 5).
inline constexpr double kFlipDefaultPixelsPerDegree = 67.0;

/// Pixels per degree of visual angle for a monitor `widthM` metres wide with `resolutionX` pixels across,
/// seen from `distanceM` metres (the paper's small-angle formula: distance · pixels/width · π/180).
double pixelsPerDegree(double distanceM, double widthM, double resolutionX);

struct ErrorMetrics {
  double psnr = 0.0;      // dB on 8-bit sRGB RGB; +infinity for identical images
  double ssim = 0.0;      // mean SSIM on 8-bit Rec. 709 luma, 1 for identical images
  double flipMean = 0.0;  // mean LDR-FLIP, 0 (identical) .. 1
};

struct FlipResult {
  double mean = 0.0;
  std::vector<float> map;  // width*height per-pixel FLIP values in [0, 1], row 0 at the top
  int width = 0;
  int height = 0;
};

/// PSNR in dB over the R, G and B channels of 8-bit images, peak 255 (alpha is ignored). Identical images
/// give +infinity (std::numeric_limits<double>::infinity()), not a cap, so that "exact" stays distinguishable.
Result<double> psnr(const Image& test, const Image& reference);
/// PSNR on linear float RGB with the given peak value (1.0 for display-range linear images).
Result<double> psnr(const ImageF& test, const ImageF& reference, double peak = 1.0);

/// Mean SSIM (Wang et al. 2004) on 8-bit luma Y = 0.2126 R + 0.7152 G + 0.0722 B computed on the sRGB
/// values, 11×11 Gaussian window σ = 1.5, C1 = (0.01·255)², C2 = (0.03·255)², averaged over the window
/// positions that lie fully inside the image (as Wang's reference code does). Images narrower or shorter
/// than 11 pixels use a window cut to the image size.
Result<double> ssim(const Image& test, const Image& reference);

/// relMSE for HDR values: mean over pixels and channels of (test − ref)² / (ref² + 0.01).
Result<double> relMse(const ImageF& test, const ImageF& reference);

/// LDR-FLIP (Andersson et al., HPG 2020) of an 8-bit sRGB test image against its reference; alpha ignored.
Result<FlipResult> flip(const Image& test, const Image& reference,
                        double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

/// The per-pixel FLIP map as an opaque 8-bit image through the magma colour map (black = no error).
Image heatmap(const FlipResult& result);

/// The magma colour map (matplotlib's, by Smith and van der Walt) at t in [0, 1] (clamped), in display
/// sRGB [0, 1]: 17 samples of the 256-entry table, linearly interpolated (within about 1/255 of the full table).
glm::vec3 magma(float t);

/// PSNR, SSIM and LDR-FLIP mean in one call.
Result<ErrorMetrics> compare(const Image& test, const Image& reference,
                             double pixelsPerDegree = kFlipDefaultPixelsPerDegree);

/// The colour transforms FLIP uses, exposed so that tests and tools can check them on known values.
/// All use the sRGB primaries with the D65 white point; XYZ is scaled so that linear white has Y = 1.
namespace colorspace {
float srgbToLinear(float c);                // IEC 61966-2-1 decoding, c in [0, 1]
glm::vec3 linearRgbToXyz(glm::vec3 rgb);
glm::vec3 xyzToLinearRgb(glm::vec3 xyz);
glm::vec3 xyzToYCxCz(glm::vec3 xyz);        // (Y, Cx, Cz): 116·Y/Yn − 16, 500·(X/Xn − Y/Yn), 200·(Y/Yn − Z/Zn)
glm::vec3 yCxCzToXyz(glm::vec3 ycxcz);
glm::vec3 xyzToLab(glm::vec3 xyz);          // CIE 1976 L*a*b*, exact 6/29 breakpoints
glm::vec3 huntAdjust(glm::vec3 lab);        // (L, 0.01·L·a, 0.01·L·b)
float hyab(glm::vec3 lab1, glm::vec3 lab2);  // |ΔL| + sqrt(Δa² + Δb²)
}  // namespace colorspace

}  // namespace tandem
