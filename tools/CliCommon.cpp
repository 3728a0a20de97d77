#include "CliCommon.h"

#include <cstdio>

namespace tandem::cli {

void addFrameOptions(CLI::App& app, FrameOptions& o) {
  app.add_option("--size", o.size, "Frame size WxH (default: the scene's, else 1280x720)");
  app.add_option("--preset", o.preset, "raster | hybrid-fast | hybrid-full | reference");
  app.add_option("--shading", o.shading, "Override every material's model: flat | gouraud | phong | toon");
  app.add_option("--shadows", o.shadows, "off | raster | ray");
  app.add_option("--reflections", o.reflections, "off | raster | ray");
  app.add_option("--refraction", o.refraction, "off | raster | ray");
  app.add_option("--depth", o.depth, "Maximum reflection/refraction depth, 0..64");
  app.add_option("--scale", o.scale, "Ray-pass resolution divisor: 1, 2 or 4");
  app.add_option("--spp", o.spp, "Reference mode: N×N jittered samples per pixel");
  app.add_option("--debug-view", o.debugView,
                 "final | depth | instance | primitive | normal | light-mask | reflection | transmission");
  app.add_option("--tonemap", o.toneMap, "none | reinhard | aces");
  app.add_option("--exposure", o.exposure, "Linear exposure multiplier (> 0)");
  app.add_flag("--classic-whitted", o.classicWhitted, "I = local + kr·S + kt·T instead of the Fresnel-weighted sum");
  app.add_flag("--schlick", o.schlick, "Schlick's Fresnel approximation instead of the exact dielectric form");
}

Result<FrameSettings> resolveFrameOptions(const FrameOptions& o, FrameSettings s) {
  if (!o.preset.empty()) {
    auto p = presetSettings(o.preset, s);
    if (!p) return Error{"--preset: unknown preset '" + o.preset + "' (raster, hybrid-fast, hybrid-full, reference)"};
    s = *p;
  }
  if (!o.size.empty()) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(o.size.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 ||
        h < 1 || w > 16384 || h > 16384)
      return Error{"--size: expected WxH with 1 <= W, H <= 16384, got '" + o.size + "'"};
    s.width = w;
    s.height = h;
  }
  if (!o.shading.empty()) {
    auto m = parseShadingModel(o.shading);
    if (!m) return Error{"--shading: unknown model '" + o.shading + "' (flat, gouraud, phong, toon)"};
    s.shadingOverride = *m;
  }
  auto effect = [](const std::string& flag, const std::string& v, EffectMode& out) -> Result<void> {
    if (v.empty()) return {};
    auto m = parseEffectMode(v);
    if (!m) return Error{flag + ": expected off, raster or ray, got '" + v + "'"};
    out = *m;
    return {};
  };
  if (auto r = effect("--shadows", o.shadows, s.shadows); !r) return r.error();
  if (auto r = effect("--reflections", o.reflections, s.reflections); !r) return r.error();
  if (auto r = effect("--refraction", o.refraction, s.refraction); !r) return r.error();
  if (o.depth >= 0) {
    if (o.depth > 64) return Error{"--depth: must be 0..64"};
    s.maxDepth = o.depth;
  }
  if (o.scale != 0) {
    if (o.scale != 1 && o.scale != 2 && o.scale != 4) return Error{"--scale: must be 1, 2 or 4"};
    s.rayScale = o.scale;
  }
  if (o.spp != 0) {
    if (o.spp < 1 || o.spp > 64) return Error{"--spp: must be 1..64"};
    s.referenceSpp = o.spp;
  }
  if (!o.debugView.empty()) {
    auto v = parseDebugView(o.debugView);
    if (!v) return Error{"--debug-view: unknown view '" + o.debugView + "'"};
    s.debugView = *v;
  }
  if (!o.toneMap.empty()) {
    if (o.toneMap == "none") s.toneMap = ToneMap::None;
    else if (o.toneMap == "reinhard") s.toneMap = ToneMap::Reinhard;
    else if (o.toneMap == "aces") s.toneMap = ToneMap::Aces;
    else return Error{"--tonemap: expected none, reinhard or aces"};
  }
  if (o.exposure != 0.0f) {
    if (!(o.exposure > 0.0f)) return Error{"--exposure: must be > 0"};
    s.exposure = o.exposure;
  }
  if (o.classicWhitted) s.fresnelWeighted = false;
  if (o.schlick) s.fresnel = FresnelMode::Schlick;
  return s.resolved();
}

}  // namespace tandem::cli
