#include "CliCommon.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>

namespace tandem::cli {

namespace {

std::string inQuotes(const std::string& s) { return "'" + s + "'"; }

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

void addFrameOptions(CLI::App& app, FrameOptions& o) {
  // Defaults in the help come from the code (FrameSettings{}, presetSettings), so they cannot go stale.
  const FrameSettings d;
  const std::string preset = std::string(" (default: the scene's render.preset, else ") + kDefaultPreset + ")";
  app.add_option("--size", o.size, "Frame size WxH (default: the scene's render width and height, else " +
                                       std::to_string(d.width) + "x" + std::to_string(d.height) + ")");
  app.add_option("--preset", o.preset, "raster | hybrid-fast | hybrid-full | reference" + preset);
  app.add_option("--shading", o.shading,
                 "Override every material's model: flat | gouraud | phong | toon (default: each material's own)");
  app.add_option("--shadows", o.shadows,
                 "off | raster | ray | hybrid (rays only where the light-space maps cannot prove the answer; "
                 "the same image) (default: the preset's)");
  app.add_option("--shadow-proofs", o.shadowProofs,
                 "With --shadows hybrid: where the primary hits' shadow rays are proved, auto (the GL on a GPU, "
                 "else the CPU) | gl | cpu | shafts (tile shafts alone, no light-space maps); the same image (default " + std::string(toString(d.shadowProofs)) + ")");
  app.add_option("--reflections", o.reflections, "off | raster | ray (default: the preset's)");
  app.add_option("--probe-limit", o.probeLimit,
                 "Raster reflections/refraction: the most reflection probes, 1..4096; past it objects share the "
                 "nearest probe (FrameSettings::probeLimit, default " + std::to_string(d.probeLimit) + ")");
  app.add_option("--probe-size", o.probeSize,
                 "Raster reflections/refraction: each probe face's texels a side, a power of two in 16..512 "
                 "(FrameSettings::probeSize, default: the preset's)");
  app.add_option("--probes-per-frame", o.probesPerFrame,
                 "Raster reflections/refraction: the most probes a frame draws, 0..4096; the others show the "
                 "environment until later frames draw them, oldest first (FrameSettings::probesPerFrame, default 0: "
                 "all, every frame that needs them)");
  app.add_option("--refraction", o.refraction, "off | raster | ray (default: the preset's)");
  app.add_option("--depth", o.depth,
                 "Maximum reflection/refraction depth, 0..64 (default: the scene's render.maxDepth, else the preset's)");
  app.add_option("--scale", o.scale,
                 "Ray-pass resolution divisor: 1, 2 or 4, not with the reference preset (default: the preset's)");
  app.add_option("--spp", o.spp,
                 "Reference preset only: N×N jittered samples per pixel, 1..64 (default " +
                     std::to_string(d.referenceSpp) + ")");
  app.add_option("--debug-view", o.debugView,
                 "final | depth | instance | primitive | normal | light-mask | reflection | transmission | motion (default " +
                     std::string(toString(d.debugView)) + ")");
  app.add_option("--tonemap", o.toneMap, "none | reinhard | aces (default " + std::string(toString(d.toneMap)) + ")");
  app.add_option("--exposure", o.exposure, "Linear exposure multiplier, finite and > 0 (default " + number(d.exposure) + ")");
  app.add_option("--target-fps", o.targetFps,
                 "Frame-time budget: each frame drawn with the settings above or the cheaper choice (coarser ray grid, "
                 "capped depth, raster fallbacks) expected to be least wrong within 1000/N ms (FrameSettings::targetMs, "
                 "docs/budget.md); 0.1..1000, not with the reference preset (default: none)");
  app.add_option("--aa", o.aa,
                 "Anti-aliasing: off | ssaa [N] (N jittered samples per pixel, each a whole frame, default 4) | "
                 "adaptive [N] (4 samples, then more only where they disagree, up to N, default 16); N 1..256; "
                 "not with the reference preset (--spp) or --target-fps (default: off)")
      ->expected(1, 2);
  app.add_option("--aa-threshold", o.aaThreshold,
                 "Adaptive anti-aliasing: display-luminance range (0..1) over which a pixel's samples disagree (default " +
                     number(d.aaThreshold) + ")");
  app.add_option("--denoise", o.denoise,
                 "on | off: the spatiotemporal filter (docs/denoise.md): each frame draws new light and gloss samples "
                 "at a new sub-pixel offset, reprojects the last frames' along the motion vectors and smooths what is "
                 "still noisy, edge-aware; not with --aa or the reference preset (default: off)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--accumulate", o.accumulate,
                 "Progressive accumulation: while nothing changes, each frame adds new samples, up to N frames; "
                 "tandem-render then renders at least N frames and writes the converged image; 0..65536 (default: off)");
  app.add_option("--light-samples", o.lightSamples,
                 "Area lights: samples per light per shaded point and frame, each with its own shadow ray when shadows "
                 "are by rays (accumulated frames add new ones); 1..32 (default " + std::to_string(d.lightSamples) + ")");
  app.add_option("--light-samples-past-filter", o.lightSamplesPastFilter,
                 "With --denoise on: area-light samples, at least --light-samples, at every ray hit past the "
                 "primary hit (a mirror's or glass's, whose light the filter does not smooth; a glossy lobe's) and "
                 "in the reflection probes; 1..32 (default " +
                     std::to_string(d.lightSamplesPastFilter) + ")");
  app.add_option("--gloss-samples", o.glossSamples,
                 "Glossy materials (roughness > 0): reflection and refraction rays per primary hit and frame, sampled "
                 "from the lobe (deeper bounces take one; accumulated frames draw new ones); 1..32 (default " +
                     std::to_string(d.glossSamples) + ")");
  app.add_option("--gi", o.gi,
                 "Diffuse interreflection: none | path (the reference preset only: a path tracer with next-event "
                 "estimation and Russian roulette, the ambient term left out; docs/path-tracing.md) (default: none)");
  app.add_option("--radiosity", o.radiosity,
                 "off | on: diffuse interreflection from a progressive-refinement radiosity solution in place of the "
                 "ambient term, solved before the frame; raster and rays both show it (docs/radiosity.md); not with "
                 "--gi path (default: the scene's render.radiosity, else off)");
  app.add_option("--radiosity-error", o.radiosityError,
                 "Radiosity: stop shooting when the unshot light is this fraction of the light that entered, 0..1 "
                 "(default " + number(d.radiosityError) + ")");
  app.add_option("--radiosity-shots", o.radiosityShots,
                 "Radiosity: stop after N shots whatever is left, 1..100000000 (default: no cap)");
  app.add_option("--radiosity-patches", o.radiosityPatches,
                 "Radiosity: about how many patches the scene's surfaces are cut into, 16..1048576 (default " +
                     std::to_string(d.radiosityPatches) + ")");
  app.add_option("--radiosity-refine", o.radiosityRefine,
                 "Radiosity: on | off: once solved, grids twice as fine on the triangles where the solution steps "
                 "steeply (gradients, shadow edges in the indirect light), solved again (default off)");
  app.add_flag("--classic-whitted", o.classicWhitted,
               "I = local + kr·S + kt·T (default: the Fresnel-weighted sum, docs/shading.md)");
  app.add_flag("--schlick", o.schlick, "Schlick's Fresnel approximation (default: the exact dielectric form)");
  std::string footer = "Presets (--preset sets these; each flag above then overrides its own):\n";
  for (const std::string& name : presetNames()) {
    char line[160];
    std::snprintf(line, sizeof line, "  %-12s %s%s\n", name.c_str(), describeSettings(*presetSettings(name)).c_str(),
                  name == kDefaultPreset ? "   <- the default" : "");
    footer += line;
  }
  app.footer(footer);
}

Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings s) {
  if (o.preset) {
    auto p = presetSettings(*o.preset, s);
    if (!p) return Error{"--preset: unknown preset " + inQuotes(*o.preset) + " (raster, hybrid-fast, hybrid-full, reference)"};
    s = *p;
  }
  if (o.size) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(o.size->c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 ||
        h < 1 || w > 16384 || h > 16384)
      return Error{"--size: expected WxH with 1 <= W, H <= 16384, got " + inQuotes(*o.size)};
    s.width = w;
    s.height = h;
  }
  if (o.shading) {
    auto m = parseShadingModel(*o.shading);
    if (!m) return Error{"--shading: unknown model " + inQuotes(*o.shading) + " (flat, gouraud, phong, toon)"};
    s.shadingOverride = *m;
  }
  auto effect = [](const std::string& flag, const std::optional<std::string>& v, EffectMode& out) -> Result<void> {
    if (!v) return {};
    auto m = parseEffectMode(*v);
    if (!m) return Error{flag + ": expected off, raster or ray, got " + inQuotes(*v)};
    out = *m;
    return {};
  };
  if (o.shadows && !applyShadowMode(*o.shadows, s))
    return Error{"--shadows: expected off, raster, ray or hybrid, got " + inQuotes(*o.shadows)};
  if (o.shadowProofs) {
    auto p = parseShadowProofs(*o.shadowProofs);
    if (!p) return Error{"--shadow-proofs: expected auto, gl, cpu or shafts, got " + inQuotes(*o.shadowProofs)};
    s.shadowProofs = *p;
  }
  if (auto r = effect("--reflections", o.reflections, s.reflections); !r) return r.error();
  if (auto r = effect("--refraction", o.refraction, s.refraction); !r) return r.error();
  if (o.probeLimit) {
    if (*o.probeLimit < 1 || *o.probeLimit > 4096)
      return Error{"--probe-limit: must be 1..4096, got " + std::to_string(*o.probeLimit)};
    s.probeLimit = *o.probeLimit;
  }
  if (o.probesPerFrame) {
    if (*o.probesPerFrame < 0 || *o.probesPerFrame > 4096)
      return Error{"--probes-per-frame: must be 0..4096, got " + std::to_string(*o.probesPerFrame)};
    s.probesPerFrame = *o.probesPerFrame;
  }
  if (o.probeSize) {
    const int n = *o.probeSize;
    if (n < 16 || n > 512 || (n & (n - 1)) != 0)
      return Error{"--probe-size: must be a power of two in 16..512, got " + std::to_string(n)};
    s.probeSize = n;
  }
  if (o.depth) {
    if (*o.depth < 0 || *o.depth > 64) return Error{"--depth: must be 0..64, got " + std::to_string(*o.depth)};
    s.maxDepth = *o.depth;
  }
  if (o.scale) {
    if (*o.scale != 1 && *o.scale != 2 && *o.scale != 4)
      return Error{"--scale: must be 1, 2 or 4, got " + std::to_string(*o.scale)};
    s.rayScale = *o.scale;
  }
  if (o.spp) {
    if (*o.spp < 1 || *o.spp > 64) return Error{"--spp: must be 1..64, got " + std::to_string(*o.spp)};
    s.referenceSpp = *o.spp;
  }
  if (o.debugView) {
    auto v = parseDebugView(*o.debugView);
    if (!v)
      return Error{"--debug-view: unknown view " + inQuotes(*o.debugView) +
                   " (final, depth, instance, primitive, normal, light-mask, reflection, transmission)"};
    s.debugView = *v;
  }
  if (o.toneMap) {
    auto t = parseToneMap(*o.toneMap);
    if (!t) return Error{"--tonemap: expected none, reinhard or aces, got " + inQuotes(*o.toneMap)};
    s.toneMap = *t;
  }
  if (o.exposure) {
    // Infinity passes "> 0" but turns every lit pixel white; NaN fails it. Both are typos, not requests.
    if (!std::isfinite(*o.exposure) || !(*o.exposure > 0.0f))
      return Error{"--exposure: must be a finite number > 0, got " + number(*o.exposure)};
    s.exposure = *o.exposure;
  }
  if (o.targetFps) {
    if (!std::isfinite(*o.targetFps) || !(*o.targetFps >= 0.1f) || *o.targetFps > 1000.0f)
      return Error{"--target-fps: must be 0.1..1000 frames per second, got " + number(*o.targetFps)};
    s.targetMs = 1000.0f / *o.targetFps;
  }
  if (o.aa) {
    const std::vector<std::string>& v = *o.aa;
    auto mode = parseAntiAlias(v.front());
    if (!mode) return Error{"--aa: expected off, ssaa [N] or adaptive [N], got " + inQuotes(v.front())};
    s.aa = *mode;
    s.aaSamples = *mode == AntiAlias::Adaptive ? 16 : 4;
    if (v.size() == 2) {
      int n = 0;
      auto [end, ec] = std::from_chars(v[1].data(), v[1].data() + v[1].size(), n);
      if (*mode == AntiAlias::Off || ec != std::errc() || end != v[1].data() + v[1].size() || n < 1 || n > 256)
        return Error{"--aa: " + v.front() + " takes a sample count 1..256" +
                     (*mode == AntiAlias::Off ? std::string(" only after ssaa or adaptive") : std::string()) + ", got " +
                     inQuotes(v[1])};
      s.aaSamples = n;
    }
  }
  if (o.aaThreshold) {
    if (!std::isfinite(*o.aaThreshold) || *o.aaThreshold < 0.0f || *o.aaThreshold > 1.0f)
      return Error{"--aa-threshold: must be 0..1, got " + number(*o.aaThreshold)};
    if (s.aa != AntiAlias::Adaptive)
      return Error{"--aa-threshold: only adaptive anti-aliasing has a threshold (add --aa adaptive), got --aa-threshold " +
                   number(*o.aaThreshold)};
    s.aaThreshold = *o.aaThreshold;
  }
  if (o.accumulate) {
    if (*o.accumulate < 0 || *o.accumulate > 65536)
      return Error{"--accumulate: must be 0..65536 frames, got " + std::to_string(*o.accumulate)};
    s.accumulate = *o.accumulate;
  }
  if (o.lightSamples) {
    if (*o.lightSamples < 1 || *o.lightSamples > 32)
      return Error{"--light-samples: must be 1..32 samples per light per frame (accumulate frames for more), got " +
                   std::to_string(*o.lightSamples)};
    s.lightSamples = *o.lightSamples;
  }
  if (o.lightSamplesPastFilter) {
    if (*o.lightSamplesPastFilter < 1 || *o.lightSamplesPastFilter > 32)
      return Error{"--light-samples-past-filter: must be 1..32 samples per light per frame, got " +
                   std::to_string(*o.lightSamplesPastFilter)};
    s.lightSamplesPastFilter = *o.lightSamplesPastFilter;
  }
  if (o.glossSamples) {
    if (*o.glossSamples < 1 || *o.glossSamples > 32)
      return Error{"--gloss-samples: must be 1..32 rays per glossy hit per frame (accumulate frames for more), got " +
                   std::to_string(*o.glossSamples)};
    s.glossSamples = *o.glossSamples;
  }
  if (o.gi) {
    auto g = parseGlobalIllumination(*o.gi);
    if (!g) return Error{"--gi: expected none or path, got " + inQuotes(*o.gi)};
    if (*g != GlobalIllumination::None && !s.reference)
      return Error{"--gi: only the reference preset traces paths (add --preset reference), got --gi " + *o.gi};
    s.gi = *g;
  }
  if (o.radiosity) {
    if (*o.radiosity != "off" && *o.radiosity != "on")
      return Error{"--radiosity: expected off or on, got " + inQuotes(*o.radiosity)};
    s.radiosity = *o.radiosity == "on";
  }
  if (s.radiosity && s.gi == GlobalIllumination::Path) {
    if (o.radiosity)
      return Error{"--radiosity: the path tracer (--gi path) carries diffuse interreflection itself; use one of them"};
    s.radiosity = false;  // the scene's render.radiosity gives way to --gi path
  }
  if (o.radiosityError) {
    if (!std::isfinite(*o.radiosityError) || *o.radiosityError < 0.0f || *o.radiosityError > 1.0f)
      return Error{"--radiosity-error: must be 0..1, got " + number(*o.radiosityError)};
    s.radiosityError = *o.radiosityError;
  }
  if (o.radiosityShots) {
    if (*o.radiosityShots < 1 || *o.radiosityShots > 100000000)
      return Error{"--radiosity-shots: must be 1..100000000, got " + std::to_string(*o.radiosityShots)};
    s.radiosityShots = *o.radiosityShots;
  }
  if (o.radiosityPatches) {
    if (*o.radiosityPatches < 16 || *o.radiosityPatches > (1 << 20))
      return Error{"--radiosity-patches: must be 16..1048576, got " + std::to_string(*o.radiosityPatches)};
    s.radiosityPatches = *o.radiosityPatches;
  }
  if (o.radiosityRefine) {
    if (*o.radiosityRefine != "off" && *o.radiosityRefine != "on")
      return Error{"--radiosity-refine: expected off or on, got " + inQuotes(*o.radiosityRefine)};
    s.radiosityRefine = *o.radiosityRefine == "on";
  }
  if ((o.radiosityError || o.radiosityShots || o.radiosityPatches || o.radiosityRefine) && !s.radiosity)
    return Error{"--radiosity-error, --radiosity-shots, --radiosity-patches and --radiosity-refine set up the "
                 "radiosity solve: add --radiosity on (or the scene's render.radiosity)"};
  if (s.aa != AntiAlias::Off && s.reference)
    return Error{"--aa: the reference preset takes its samples per pixel from --spp, got --aa " + o.aa->front()};
  if (o.denoise) {
    s.denoise = *o.denoise == "on";
    if (s.denoise && s.reference)
      return Error{"--denoise: the reference frame is converged, not filtered (drop --denoise or the reference preset)"};
    if (s.denoise && s.aa != AntiAlias::Off)
      return Error{"--denoise: a frame of several samples (--aa) is not filtered; the filter's frames draw one sample "
                   "each at a new sub-pixel offset (drop --aa or --denoise), got --aa " + o.aa->front()};
  }
  if (s.accumulate > 1 && o.targetFps)
    return Error{"--accumulate: a frame-time budget has no accumulation step yet (drop --target-fps or --accumulate), "
                 "got --accumulate " + std::to_string(s.accumulate)};
  if (s.aa != AntiAlias::Off && o.targetFps)
    return Error{"--aa: a frame-time budget has no anti-aliasing step yet (drop --target-fps or --aa), got --aa " +
                 o.aa->front()};
  if (o.classicWhitted) s.fresnelWeighted = false;
  if (o.schlick) s.fresnel = FresnelMode::Schlick;
  // Only raster reflections and refraction draw probes.
  if ((o.probeLimit || o.probeSize || o.probesPerFrame) &&
      (s.reference || (s.reflections != EffectMode::Raster && s.refraction != EffectMode::Raster)))
    return Error{std::string(o.probeLimit ? "--probe-limit" : o.probeSize ? "--probe-size" : "--probes-per-frame") +
                 ": only raster reflections or refraction use probes (the raster preset, or --reflections raster "
                 "or --refraction raster), got reflections " + std::string(toString(s.reflections)) +
                 ", refraction " + std::string(toString(s.refraction)) + (s.reference ? " (the reference)" : "")};
  // Flags the chosen mode would ignore: only the reference frame takes several samples per pixel, and it
  // traces every pixel, so it has no reduced-resolution ray pass to scale.
  if (o.spp && !s.reference)
    return Error{"--spp: only the reference preset takes samples per pixel (add --preset reference), got --spp " +
                 std::to_string(*o.spp)};
  if (o.scale && s.reference)
    return Error{"--scale: the reference preset traces every pixel at full resolution, got --scale " +
                 std::to_string(*o.scale)};
  if (o.targetFps && s.reference)
    return Error{"--target-fps: the reference frame is never cut down to a budget, got --target-fps " +
                 number(*o.targetFps)};
  return s.resolved();
}

Result<ResolvedFrame> resolveFrame(const FrameOptions& o, const SceneRenderDefaults& scene) {
  ResolvedFrame out;
  FrameSettings base;
  base.width = scene.width;
  base.height = scene.height;
  if (scene.radiosity >= 0) base.radiosity = scene.radiosity == 1;
  if (o.preset) {
    out.preset = *o.preset;  // resolveFrameOptions applies (or refuses) it
    out.presetSource = "--preset";
  } else {
    out.preset = scene.preset.empty() ? std::string(kDefaultPreset) : scene.preset;
    out.presetSource = scene.preset.empty() ? "the default" : "the scene's render.preset";
    auto p = presetSettings(out.preset, base);
    if (!p) return Error{"scene render.preset: unknown preset " + inQuotes(out.preset)};
    base = *p;
    if (scene.maxDepth >= 0 && scene.maxDepth != base.maxDepth) {
      base.maxDepth = scene.maxDepth;
      out.changedBy.push_back("the scene's render.maxDepth");
    }
  }
  auto settings = resolveFrameOptions(o, base);
  if (!settings) return settings.error();
  out.settings = *settings;
  const std::pair<const char*, bool> flags[] = {
      {"--shadows", o.shadows.has_value()}, {"--reflections", o.reflections.has_value()},
      {"--refraction", o.refraction.has_value()}, {"--depth", o.depth.has_value()},
      {"--scale", o.scale.has_value()}};
  for (const auto& [flag, given] : flags)
    if (given) out.changedBy.push_back(flag);
  return out;
}

Result<glm::ivec2> parseTracePixel(const std::string& text, int width, int height) {
  // Two runs of digits around one comma: no sign, no spaces, no overflow (from_chars reports it).
  auto number = [](std::string_view digits, int& v) {
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string_view::npos) return false;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    return ec == std::errc() && end == digits.data() + digits.size();
  };
  const std::size_t comma = text.find(',');
  int x = 0, y = 0;
  if (comma == std::string::npos || !number(std::string_view(text).substr(0, comma), x) ||
      !number(std::string_view(text).substr(comma + 1), y))
    return Error{"--trace-pixel: expected X,Y (the pixel's column and row, row 0 at the top), got " + inQuotes(text)};
  if (x >= width || y >= height)
    return Error{"--trace-pixel: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                 std::to_string(width) + "x" + std::to_string(height) + " frame (X 0.." + std::to_string(width - 1) +
                 ", Y 0.." + std::to_string(height - 1) + ")"};
  return glm::ivec2(x, y);
}

std::string describeSettings(const FrameSettings& s) {
  std::string d = "shadows " + std::string(shadowModeName(s)) + ", reflections " +
                  std::string(toString(s.reflections)) + ", refraction " + std::string(toString(s.refraction)) +
                  ", depth " + std::to_string(s.maxDepth);
  if (s.reference)
    return d + ", primary visibility by rays, " + std::to_string(s.referenceSpp) + "×" +
           std::to_string(s.referenceSpp) + " samples per pixel" +
           (s.gi == GlobalIllumination::Path ? std::string(", path-traced interreflection") : std::string()) +
           (s.accumulate > 1 ? ", accumulating up to " + std::to_string(s.accumulate) + " frames" : std::string());
  d += ", scale 1/" + std::to_string(s.rayScale);
  if (s.aa == AntiAlias::Ssaa) d += ", ssaa " + std::to_string(s.aaSamples);
  if (s.aa == AntiAlias::Adaptive) d += ", adaptive aa up to " + std::to_string(s.aaSamples) + " (threshold " + number(s.aaThreshold) + ")";
  if (s.accumulate > 1) d += ", accumulating up to " + std::to_string(s.accumulate) + " frames";
  if (s.denoise) d += ", denoised";
  return d;
}

}  // namespace tandem::cli
