#pragma once
// The live render toggles: what each key does to the FrameSettings, and the window-level switches the
// main loop carries out (fullscreen, vsync, screenshot, quit). Keys arrive by name from GLFW or a script.
#include <optional>
#include <string>

#include "tandem/Settings.h"

namespace marble {

enum class WindowAction { None, Fullscreen, Vsync, Screenshot, Restart, Pause, Quit };

struct ViewState {
  tandem::FrameSettings settings;  // width / height set per frame from the window or --size
  std::string preset;              // the preset last applied; "custom" after a per-effect change
  int renderScalePct = 100;        // offscreen frame size relative to the window: 100, 50 or 25
  bool showHelp = true;
  bool showHud = true;
  bool vsync = true;
  bool fullscreen = false;
  float targetFps = 0.0f;          // the frame-time budget (key B); 0 = none. settings.targetMs follows it

  /// Applies a preset by name (size and debug view kept). False when the name is unknown.
  bool applyPreset(const std::string& name);
  /// Handles one key press (the down edge). Returns what the loop must do beyond the settings change.
  WindowAction onKey(const std::string& key);
  /// "model override" shown in the HUD: the override's name or "material".
  std::string shadingName() const;
  /// Sets the budget: settings.targetMs = 1000 / fps, or none for 0.
  void setTargetFps(float fps);
  /// "off" or "30 fps".
  std::string budgetName() const;
};

/// The help overlay's lines: "KEY  what it does".
const char* const* helpLines();

}  // namespace marble
