// tandem-diff: how far image A is from image B (the reference): PSNR, SSIM and LDR-FLIP (docs/metrics.md).
//
//   tandem-diff test.png reference.png [--heatmap flip.png] [--json] [--ppd 67]
//
// Exit status 0 on success; 1 with a one-line message on stderr when a file cannot be read or written or the
// sizes differ; CLI11's own status for bad arguments.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "tandem/Image.h"
#include "tandem/ImageMetrics.h"

namespace {

// JSON has no infinity: identical images report "psnr": null (documented in docs/metrics.md).
std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

int fail(const std::string& message) {
  std::cerr << "tandem-diff: " << message << "\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Compare two images: PSNR, SSIM and LDR-FLIP (A is the test image, B the reference)"};
  std::string pathA, pathB, heatmapPath;
  bool json = false;
  double ppd = tandem::kFlipDefaultPixelsPerDegree;
  app.add_option("A", pathA, "test image (PNG)")->required();
  app.add_option("B", pathB, "reference image (PNG)")->required();
  app.add_option("--heatmap", heatmapPath, "write the per-pixel FLIP map as a magma heat map (.png, .jpg or .jpeg)");
  app.add_flag("--json", json, "print the numbers as one JSON object");
  app.add_option("--ppd", ppd, "FLIP observer, pixels per degree (default 67: 0.7 m wide 4K monitor at 0.7 m)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  if (!heatmapPath.empty())
    if (auto format = tandem::imageFormatForPath(heatmapPath); !format) return fail("--heatmap: " + format.error().message);

  tandem::Result<tandem::Image> a = tandem::readPng(pathA);
  if (!a) return fail(a.error().message);
  tandem::Result<tandem::Image> b = tandem::readPng(pathB);
  if (!b) return fail(b.error().message);
  if (a->width != b->width || a->height != b->height)
    return fail("image sizes differ: " + pathA + " is " + std::to_string(a->width) + "x" +
                std::to_string(a->height) + ", " + pathB + " is " + std::to_string(b->width) + "x" +
                std::to_string(b->height));

  const tandem::Result<double> p = tandem::psnr(*a, *b);
  if (!p) return fail(p.error().message);
  const tandem::Result<double> s = tandem::ssim(*a, *b);
  if (!s) return fail(s.error().message);
  const tandem::Result<tandem::FlipResult> f = tandem::flip(*a, *b, ppd);
  if (!f) return fail(f.error().message);

  if (!heatmapPath.empty()) {
    if (auto w = tandem::writeImage(heatmapPath, tandem::heatmap(*f)); !w) return fail(w.error().message);
  }

  if (json) {
    std::cout << "{\"a\": " << jsonString(pathA) << ", \"b\": " << jsonString(pathB) << ", \"width\": " << a->width
              << ", \"height\": " << a->height << ", \"psnr\": " << jsonNumber(*p) << ", \"ssim\": " << jsonNumber(*s)
              << ", \"flip_mean\": " << jsonNumber(f->mean) << ", \"ppd\": " << jsonNumber(ppd);
    if (!heatmapPath.empty()) std::cout << ", \"heatmap\": " << jsonString(heatmapPath);
    std::cout << "}\n";
  } else {
    char line[128];
    if (std::isinf(*p))
      std::cout << "PSNR  inf (identical)\n";
    else {
      std::snprintf(line, sizeof line, "PSNR  %.4f dB\n", *p);
      std::cout << line;
    }
    std::snprintf(line, sizeof line, "SSIM  %.6f\nFLIP  %.6f (mean, %g ppd)\n", *s, f->mean, ppd);
    std::cout << line;
    if (!heatmapPath.empty()) std::cout << "heat map written to " << heatmapPath << "\n";
  }
  return 0;
}
