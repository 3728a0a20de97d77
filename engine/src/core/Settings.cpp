#include "tandem/Settings.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace tandem {

FrameSettings FrameSettings::resolved() const {
  FrameSettings s = *this;
  s.width = std::clamp(s.width, 1, kMaxFrameSide);
  s.height = std::clamp(s.height, 1, kMaxFrameSide);
  s.maxDepth = std::clamp(s.maxDepth, 0, 64);
  s.minContribution = std::isfinite(s.minContribution) ? std::clamp(s.minContribution, 0.0f, 1.0f) : 0.01f;
  s.rayScale = s.rayScale >= 4 ? 4 : s.rayScale >= 2 ? 2 : 1;
  s.exposure = std::isfinite(s.exposure) && s.exposure > 0.0f ? s.exposure : 1.0f;
  s.referenceSpp = std::clamp(s.referenceSpp, 1, 64);
  s.probesPerFrame = std::max(s.probesPerFrame, 0);
  s.probeLimit = std::clamp(s.probeLimit, 1, 4096);
  s.probeSize = static_cast<int>(std::bit_floor(static_cast<unsigned>(std::clamp(s.probeSize, 16, 512))));
  s.targetMs = std::isfinite(s.targetMs) ? std::clamp(s.targetMs, 0.0f, 10000.0f) : 0.0f;
  s.aaSamples = std::clamp(s.aaSamples, 1, 256);
  s.aaThreshold = std::isfinite(s.aaThreshold) ? std::clamp(s.aaThreshold, 0.0f, 1.0f) : 0.05f;
  s.accumulate = std::clamp(s.accumulate, 0, 65536);
  s.lightSamples = std::clamp(s.lightSamples, 1, 32);
  s.lightSamplesPastFilter = std::clamp(s.lightSamplesPastFilter, 1, 32);
  s.glossSamples = std::clamp(s.glossSamples, 1, 32);
  if (s.reference || s.targetMs > 0.0f) s.aa = AntiAlias::Off;
  if (s.targetMs > 0.0f) s.accumulate = 0;
  if (!s.reference) s.gi = GlobalIllumination::None;
  if (s.reference || s.aa != AntiAlias::Off) s.denoise = false;
  if (s.gi == GlobalIllumination::Path) s.radiosity = false;
  s.radiosityError = std::isfinite(s.radiosityError) ? std::clamp(s.radiosityError, 0.0f, 1.0f) : 0.01f;
  s.radiosityShots = std::clamp(s.radiosityShots, 0, 100000000);
  s.radiosityPatches = std::clamp(s.radiosityPatches, 16, 1 << 20);
  return s;
}

std::optional<FrameSettings> presetSettings(std::string_view name, FrameSettings s) {
  if (name == "raster") {
    // Every effect by raster, the cheap way: shadow maps looked up on the half-resolution grid (as hybrid-fast
    // traces its rays there) and gathered edge-aware, a quarter of the lookups that are most of a raster
    // frame's shading; probes of 64² faces, a quarter of 128²'s pixels for blurrier mirrors (the hybrid
    // presets trace those).
    s.shadows = s.reflections = s.refraction = EffectMode::Raster;
    s.maxDepth = 1;
    s.rayScale = 2;
    s.probeSize = 64;
    s.reference = false;
  } else if (name == "hybrid-fast") {
    // Ray-traced hard shadows and reflections (up to two bounces: a mirror seen in a mirror) at half
    // resolution; refraction by raster.
    s.shadows = EffectMode::Ray;
    s.hybridShadows = false;
    s.reflections = EffectMode::Ray;
    s.refraction = EffectMode::Raster;
    s.maxDepth = 2;
    s.minContribution = 0.05f;
    s.rayScale = 2;
    s.probeSize = 128;
    s.reference = false;
  } else if (name == "hybrid-full") {
    s.shadows = s.reflections = s.refraction = EffectMode::Ray;
    s.hybridShadows = false;
    s.maxDepth = 8;
    s.minContribution = 0.005f;
    s.rayScale = 1;
    s.probeSize = 128;
    s.reference = false;
  } else if (name == "reference") {
    s.shadows = s.reflections = s.refraction = EffectMode::Ray;
    s.hybridShadows = false;
    s.maxDepth = 16;
    s.minContribution = 0.0f;
    s.rayScale = 1;
    s.probeSize = 128;
    s.reference = true;
  } else {
    return std::nullopt;
  }
  return s;
}

std::vector<std::string> presetNames() { return {"raster", "hybrid-fast", "hybrid-full", "reference"}; }

std::optional<EffectMode> parseEffectMode(std::string_view s) {
  if (s == "off") return EffectMode::Off;
  if (s == "raster") return EffectMode::Raster;
  if (s == "ray") return EffectMode::Ray;
  return std::nullopt;
}

bool applyShadowMode(std::string_view s, FrameSettings& settings) {
  if (s == "hybrid") {
    settings.shadows = EffectMode::Ray;
    settings.hybridShadows = true;
    return true;
  }
  auto m = parseEffectMode(s);
  if (!m) return false;
  settings.shadows = *m;
  settings.hybridShadows = false;
  return true;
}

std::string_view shadowModeName(const FrameSettings& s) {
  return s.shadows == EffectMode::Ray && s.hybridShadows ? "hybrid" : toString(s.shadows);
}

std::optional<ShadingModel> parseShadingModel(std::string_view s) {
  if (s == "flat") return ShadingModel::Flat;
  if (s == "gouraud") return ShadingModel::Gouraud;
  if (s == "phong") return ShadingModel::Phong;
  if (s == "toon" || s == "cartoon") return ShadingModel::Toon;
  return std::nullopt;
}

std::optional<ToneMap> parseToneMap(std::string_view s) {
  if (s == "none") return ToneMap::None;
  if (s == "reinhard") return ToneMap::Reinhard;
  if (s == "aces") return ToneMap::Aces;
  return std::nullopt;
}

std::optional<AntiAlias> parseAntiAlias(std::string_view s) {
  if (s == "off") return AntiAlias::Off;
  if (s == "ssaa") return AntiAlias::Ssaa;
  if (s == "adaptive") return AntiAlias::Adaptive;
  return std::nullopt;
}

std::optional<GlobalIllumination> parseGlobalIllumination(std::string_view s) {
  if (s == "none") return GlobalIllumination::None;
  if (s == "path") return GlobalIllumination::Path;
  return std::nullopt;
}

std::string_view toString(GlobalIllumination g) {
  switch (g) {
    case GlobalIllumination::None: return "none";
    case GlobalIllumination::Path: return "path";
  }
  return "?";
}

std::string_view toString(AntiAlias a) {
  switch (a) {
    case AntiAlias::Off: return "off";
    case AntiAlias::Ssaa: return "ssaa";
    case AntiAlias::Adaptive: return "adaptive";
  }
  return "?";
}

std::string_view toString(ToneMap m) {
  switch (m) {
    case ToneMap::None: return "none";
    case ToneMap::Reinhard: return "reinhard";
    case ToneMap::Aces: return "aces";
  }
  return "?";
}

namespace {
constexpr std::string_view kDebugNames[] = {"final",      "depth",      "instance",     "primitive", "normal",
                                            "light-mask", "reflection", "transmission", "motion"};
}

std::optional<DebugView> parseDebugView(std::string_view s) {
  for (std::size_t i = 0; i < std::size(kDebugNames); ++i)
    if (s == kDebugNames[i]) return static_cast<DebugView>(i);
  return std::nullopt;
}

std::string_view toString(DebugView v) { return kDebugNames[static_cast<int>(v)]; }

std::string_view toString(ShadowProofs p) {
  switch (p) {
    case ShadowProofs::Auto: return "auto";
    case ShadowProofs::Gl: return "gl";
    case ShadowProofs::Cpu: return "cpu";
    case ShadowProofs::Shafts: return "shafts";
  }
  return "?";
}

std::optional<ShadowProofs> parseShadowProofs(std::string_view s) {
  for (ShadowProofs p : {ShadowProofs::Auto, ShadowProofs::Gl, ShadowProofs::Cpu, ShadowProofs::Shafts})
    if (s == toString(p)) return p;
  return std::nullopt;
}

std::string_view toString(EffectMode m) {
  switch (m) {
    case EffectMode::Off: return "off";
    case EffectMode::Raster: return "raster";
    case EffectMode::Ray: return "ray";
  }
  return "?";
}

std::string_view toString(ShadingModel m) {
  switch (m) {
    case ShadingModel::Flat: return "flat";
    case ShadingModel::Gouraud: return "gouraud";
    case ShadingModel::Phong: return "phong";
    case ShadingModel::Toon: return "toon";
  }
  return "?";
}

bool isRadianceView(DebugView v) {
  return v == DebugView::Final || v == DebugView::Reflection || v == DebugView::Transmission;
}

}  // namespace tandem
