#pragma once
// Command-line options shared by tandem-render and tandem-bench: frame size, preset and per-effect flags.
#include <string>

#include <CLI/CLI.hpp>

#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::cli {

struct FrameOptions {
  std::string size;       // WxH
  std::string preset;
  std::string shading;    // flat | gouraud | phong | toon
  std::string shadows;    // off | raster | ray
  std::string reflections;
  std::string refraction;
  std::string debugView;
  std::string toneMap;    // none | reinhard | aces
  int depth = -1;
  int scale = 0;
  int spp = 0;
  float exposure = 0.0f;
  bool classicWhitted = false;
  bool schlick = false;
};

/// Registers the options on `app`.
void addFrameOptions(CLI::App& app, FrameOptions& o);
/// Applies them over `base` (the scene's defaults): preset first, then each explicit flag.
Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings base);

}  // namespace tandem::cli
