#pragma once
// Command-line options of tandem-render: frame size, preset and per-effect flags.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::cli {

/// Each option is empty unless given on the command line, so every value given is checked, including
/// the ones a sentinel would mistake for "not given" (--depth -1, --spp 0, --exposure 0).
struct FrameOptions {
  std::optional<std::string> size;  // WxH
  std::optional<std::string> preset;
  std::optional<std::string> shading;  // flat | gouraud | phong | toon
  std::optional<std::string> shadows;  // off | raster | ray
  std::optional<std::string> reflections;
  std::optional<std::string> refraction;
  std::optional<std::string> debugView;
  std::optional<std::string> toneMap;  // none | reinhard | aces
  std::optional<int> depth;
  std::optional<int> scale;
  std::optional<int> spp;
  std::optional<float> exposure;
  bool classicWhitted = false;
  bool schlick = false;
};

/// Registers the options on `app`.
void addFrameOptions(CLI::App& app, FrameOptions& o);
/// Applies them over `base` (the scene's defaults): preset first, then each explicit flag. Every value
/// out of range, and every flag the resulting settings would ignore (--spp without the reference preset,
/// --scale with it), is an error naming the flag and the value.
Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings base);

}  // namespace tandem::cli
