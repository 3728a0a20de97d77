#include "CliCommon.h"

#include <cmath>
#include <cstdio>

namespace tandem::cli {

namespace {

std::string quoted(const std::string& s) { return "'" + s + "'"; }

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

void addFrameOptions(CLI::App& app, FrameOptions& o) {
  app.add_option("--size", o.size, "Frame size WxH (default: the scene's, else 1280x720)");
  app.add_option("--preset", o.preset, "raster | hybrid-fast | hybrid-full | reference");
  app.add_option("--shading", o.shading, "Override every material's model: flat | gouraud | phong | toon");
  app.add_option("--shadows", o.shadows, "off | raster | ray");
  app.add_option("--reflections", o.reflections, "off | raster | ray");
  app.add_option("--refraction", o.refraction, "off | raster | ray");
  app.add_option("--depth", o.depth, "Maximum reflection/refraction depth, 0..64");
  app.add_option("--scale", o.scale, "Ray-pass resolution divisor: 1, 2 or 4 (not with the reference preset)");
  app.add_option("--spp", o.spp, "Reference preset only: N×N jittered samples per pixel, 1..64");
  app.add_option("--debug-view", o.debugView,
                 "final | depth | instance | primitive | normal | light-mask | reflection | transmission");
  app.add_option("--tonemap", o.toneMap, "none | reinhard | aces");
  app.add_option("--exposure", o.exposure, "Linear exposure multiplier (finite, > 0)");
  app.add_flag("--classic-whitted", o.classicWhitted, "I = local + kr·S + kt·T instead of the Fresnel-weighted sum");
  app.add_flag("--schlick", o.schlick, "Schlick's Fresnel approximation instead of the exact dielectric form");
}

Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings s) {
  if (o.preset) {
    auto p = presetSettings(*o.preset, s);
    if (!p) return Error{"--preset: unknown preset " + quoted(*o.preset) + " (raster, hybrid-fast, hybrid-full, reference)"};
    s = *p;
  }
  if (o.size) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(o.size->c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 ||
        h < 1 || w > 16384 || h > 16384)
      return Error{"--size: expected WxH with 1 <= W, H <= 16384, got " + quoted(*o.size)};
    s.width = w;
    s.height = h;
  }
  if (o.shading) {
    auto m = parseShadingModel(*o.shading);
    if (!m) return Error{"--shading: unknown model " + quoted(*o.shading) + " (flat, gouraud, phong, toon)"};
    s.shadingOverride = *m;
  }
  auto effect = [](const std::string& flag, const std::optional<std::string>& v, EffectMode& out) -> Result<void> {
    if (!v) return {};
    auto m = parseEffectMode(*v);
    if (!m) return Error{flag + ": expected off, raster or ray, got " + quoted(*v)};
    out = *m;
    return {};
  };
  if (auto r = effect("--shadows", o.shadows, s.shadows); !r) return r.error();
  if (auto r = effect("--reflections", o.reflections, s.reflections); !r) return r.error();
  if (auto r = effect("--refraction", o.refraction, s.refraction); !r) return r.error();
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
      return Error{"--debug-view: unknown view " + quoted(*o.debugView) +
                   " (final, depth, instance, primitive, normal, light-mask, reflection, transmission)"};
    s.debugView = *v;
  }
  if (o.toneMap) {
    auto t = parseToneMap(*o.toneMap);
    if (!t) return Error{"--tonemap: expected none, reinhard or aces, got " + quoted(*o.toneMap)};
    s.toneMap = *t;
  }
  if (o.exposure) {
    // Infinity passes "> 0" but turns every lit pixel white; NaN fails it. Both are typos, not requests.
    if (!std::isfinite(*o.exposure) || !(*o.exposure > 0.0f))
      return Error{"--exposure: must be a finite number > 0, got " + number(*o.exposure)};
    s.exposure = *o.exposure;
  }
  if (o.classicWhitted) s.fresnelWeighted = false;
  if (o.schlick) s.fresnel = FresnelMode::Schlick;
  // Flags the chosen mode would ignore: only the reference frame takes several samples per pixel, and it
  // traces every pixel, so it has no reduced-resolution ray pass to scale.
  if (o.spp && !s.reference)
    return Error{"--spp: only the reference preset takes samples per pixel (add --preset reference), got --spp " +
                 std::to_string(*o.spp)};
  if (o.scale && s.reference)
    return Error{"--scale: the reference preset traces every pixel at full resolution, got --scale " +
                 std::to_string(*o.scale)};
  return s.resolved();
}

}  // namespace tandem::cli
