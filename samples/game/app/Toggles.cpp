#include "Toggles.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace marble {

namespace {

tandem::EffectMode nextMode(tandem::EffectMode m) {
  using tandem::EffectMode;
  return m == EffectMode::Off ? EffectMode::Raster : m == EffectMode::Raster ? EffectMode::Ray : EffectMode::Off;
}

constexpr const char* kHelp[] = {
    "W A S D / arrows   roll the marble (relative to the camera)",
    "SPACE              brake",
    "mouse drag, Q / E  orbit the camera;  wheel  zoom",
    "R                  restart",
    "TAB                pause: the world stands still and the frame converges (anti-aliased)",
    "1 / 2 / 3          shadows (off, raster, ray, hybrid) / reflections / refraction (off, raster, ray)",
    "4                  shading: material, flat, gouraud, phong, toon",
    "5 / 6              recursion depth - / +",
    "7                  ray-pass scale 1/1, 1/2, 1/4",
    "8                  preset: raster, hybrid-fast, hybrid-full, reference",
    "9                  debug view (final, depth, ids, normals, ray channels)",
    "0                  render scale 100 %, 50 %, 25 % of the window",
    "B                  frame budget: off, 60, 30, 20, 15, 10 fps (the renderer picks what fits)",
    "G                  radiosity: the hall's diffuse interreflection, solved in the background (HUD: progress)",
    "N                  denoise: the spatiotemporal filter (soft shadows from one sample a frame, TAA edges)",
    "V                  vsync on / off",
    "F / F11            fullscreen",
    "P / F12            screenshot (frame, and the window with the HUD)",
    "F1 / H             this help;  F2  HUD",
    "ESC                quit",
    nullptr,
};

}  // namespace

const char* const* helpLines() { return kHelp; }

bool ViewState::applyPreset(const std::string& name) {
  auto p = tandem::presetSettings(name, settings);
  if (!p) return false;
  settings = *p;
  preset = name;
  return true;
}

void ViewState::setTargetFps(float fps) {
  targetFps = fps > 0.0f ? fps : 0.0f;
  settings.targetMs = targetFps > 0.0f ? 1000.0f / targetFps : 0.0f;
}

std::string ViewState::budgetName() const {
  if (targetFps <= 0.0f) return "off";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g fps", static_cast<double>(targetFps));
  return buf;
}

std::string ViewState::shadingName() const {
  return settings.shadingOverride ? std::string(tandem::toString(*settings.shadingOverride)) : "material";
}

WindowAction ViewState::onKey(const std::string& key) {
  using tandem::ShadingModel;
  if (key == "1") {
    // off -> raster -> ray -> hybrid -> off
    if (settings.shadows == tandem::EffectMode::Ray && !settings.hybridShadows) settings.hybridShadows = true;
    else {
      settings.shadows = nextMode(settings.shadows);
      settings.hybridShadows = false;
    }
    preset = "custom";
  } else if (key == "2") {
    settings.reflections = nextMode(settings.reflections);
    preset = "custom";
  } else if (key == "3") {
    settings.refraction = nextMode(settings.refraction);
    preset = "custom";
  } else if (key == "4") {
    // material's own model -> flat -> gouraud -> phong -> toon -> material
    if (!settings.shadingOverride) settings.shadingOverride = ShadingModel::Flat;
    else if (*settings.shadingOverride == ShadingModel::Toon) settings.shadingOverride.reset();
    else settings.shadingOverride = static_cast<ShadingModel>(static_cast<int>(*settings.shadingOverride) + 1);
  } else if (key == "5" || key == "MINUS") {
    settings.maxDepth = std::max(0, settings.maxDepth - 1);
    preset = "custom";
  } else if (key == "6" || key == "EQUAL") {
    settings.maxDepth = std::min(16, settings.maxDepth + 1);
    preset = "custom";
  } else if (key == "7") {
    settings.rayScale = settings.rayScale == 1 ? 2 : settings.rayScale == 2 ? 4 : 1;
    preset = "custom";
  } else if (key == "8") {
    const std::vector<std::string> names = tandem::presetNames();
    auto it = std::find(names.begin(), names.end(), preset);
    applyPreset(it == names.end() || it + 1 == names.end() ? names.front() : *(it + 1));
  } else if (key == "9") {
    const int n = static_cast<int>(tandem::DebugView::Motion) + 1;
    settings.debugView = static_cast<tandem::DebugView>((static_cast<int>(settings.debugView) + 1) % n);
  } else if (key == "B") {
    // off -> 60 -> 30 -> 20 -> 15 -> 10 -> off; a target set by --target-fps goes to the next lower one
    constexpr float kSteps[] = {60.0f, 30.0f, 20.0f, 15.0f, 10.0f};
    float next = 0.0f;
    for (float f : kSteps)
      if (targetFps <= 0.0f || f < targetFps) {
        next = f;
        break;
      }
    setTargetFps(next);
  } else if (key == "G") {
    settings.radiosity = !settings.radiosity;
  } else if (key == "N") {
    settings.denoise = !settings.denoise;
  } else if (key == "0") {
    renderScalePct = renderScalePct == 100 ? 50 : renderScalePct == 50 ? 25 : 100;
  } else if (key == "F1" || key == "H") {
    showHelp = !showHelp;
  } else if (key == "F2") {
    showHud = !showHud;
  } else if (key == "V") {
    vsync = !vsync;
    return WindowAction::Vsync;
  } else if (key == "F" || key == "F11") {
    fullscreen = !fullscreen;
    return WindowAction::Fullscreen;
  } else if (key == "P" || key == "F12") {
    return WindowAction::Screenshot;
  } else if (key == "R") {
    return WindowAction::Restart;
  } else if (key == "TAB") {
    return WindowAction::Pause;
  } else if (key == "ESCAPE") {
    return WindowAction::Quit;
  }
  return WindowAction::None;
}

}  // namespace marble
