#pragma once
// Command-line options of tandem-render: frame size, preset and per-effect flags.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "tandem/Result.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::cli {

/// Each option is empty unless given on the command line, so every value given is checked, including
/// the ones a sentinel would mistake for "not given" (--depth -1, --spp 0, --exposure 0).
struct FrameOptions {
  std::optional<std::string> size;  // WxH
  std::optional<std::string> preset;
  std::optional<std::string> shading;  // flat | gouraud | phong | toon
  std::optional<std::string> shadows;  // off | raster | ray | hybrid
  std::optional<std::string> shadowProofs;  // auto | gl | cpu | shafts
  std::optional<std::string> reflections;
  std::optional<std::string> refraction;
  std::optional<std::string> debugView;
  std::optional<std::string> toneMap;  // none | reinhard | aces
  std::optional<int> depth;
  std::optional<int> probeLimit;
  std::optional<int> probeSize;
  std::optional<int> probesPerFrame;
  std::optional<int> scale;
  std::optional<int> spp;
  std::optional<float> exposure;
  std::optional<float> targetFps;  // FrameSettings::targetMs = 1000 / fps
  std::optional<std::vector<std::string>> aa;  // off | ssaa [N] | adaptive [N]
  std::optional<float> aaThreshold;
  std::optional<int> accumulate;
  std::optional<int> lightSamples;
  std::optional<int> lightSamplesPastFilter;
  std::optional<int> glossSamples;
  std::optional<std::string> gi;  // none | path
  std::optional<std::string> radiosity;  // off | on
  std::optional<float> radiosityError;
  std::optional<int> radiosityShots;
  std::optional<int> radiosityPatches;
  std::optional<std::string> radiosityRefine;  // on | off
  std::optional<std::string> denoise;  // on | off
  bool classicWhitted = false;
  bool schlick = false;
};

/// The preset tandem-render starts from when neither --preset nor the scene's render.preset names one.
/// Of the named presets it is the closest to the engine's FrameSettings{} (every effect by rays, full
/// resolution ray pass), which tandem-render rendered before it had a named default.
inline constexpr const char* kDefaultPreset = "hybrid-full";

/// Registers the options on `app`, each help line with its default, and a footer listing the presets.
void addFrameOptions(CLI::App& app, FrameOptions& o);
/// Applies them over `base`: --preset first, then each explicit flag. Every value out of range, and every
/// flag the resulting settings would ignore (--spp without the reference preset, --scale with it), is an
/// error naming the flag and the value.
Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings base);

/// The settings of one run and where they came from, for the summary tandem-render prints.
struct ResolvedFrame {
  FrameSettings settings;
  std::string preset;        // the named preset the settings start from
  std::string presetSource;  // "--preset", "the scene's render.preset" or "the default"
  std::vector<std::string> changedBy;  // what then changed a value the preset sets, e.g. "--depth"
};
/// The whole chain: the scene's render block (size, preset, maxDepth), kDefaultPreset where it names no
/// preset, then the command line (resolveFrameOptions). --preset replaces the scene's preset and maxDepth.
Result<ResolvedFrame> resolveFrame(const FrameOptions& o, const SceneRenderDefaults& scene);

/// --trace-pixel X,Y: the pixel of a width × height frame (row 0 at the top) whose ray tree tandem-render
/// prints after the frame. Malformed text and pixels outside the frame are one-line errors naming the flag.
Result<glm::ivec2> parseTracePixel(const std::string& text, int width, int height);

/// "shadows ray, reflections ray, refraction raster, depth 2, scale 1/2" (reference frames: the samples
/// per pixel instead of the scale, which they do not have).
std::string describeSettings(const FrameSettings& s);

}  // namespace tandem::cli
