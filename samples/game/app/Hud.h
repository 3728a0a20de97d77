#pragma once
// The Dear ImGui overlay of a windowed game: score and timer, frame time per stage, ray counts, the
// current settings and the help overlay. Headless runs draw no HUD (their capture is the frame alone).
#include "Game.h"
#include "Toggles.h"
#include "tandem/FrameStats.h"

struct GLFWwindow;

namespace marble {

struct HudInfo {
  const Game* game = nullptr;
  const ViewState* view = nullptr;
  tandem::FrameStats stats;
  double frameMs = 0.0;      // wall time of the whole loop iteration (render, HUD, swap)
  double presentMs = 0.0;    // Renderer::present, timed by the game
  int framebufferW = 0, framebufferH = 0;
  const char* context = "";
  const char* message = "";  // last screenshot path etc.
  bool paused = false;       // TAB: the world stands still
};

class Hud {
 public:
  /// Sets up ImGui with the GLFW and OpenGL3 backends on the current context; installs ImGui's GLFW
  /// callbacks, which chain to the game's own (install those first).
  explicit Hud(GLFWwindow* window);
  ~Hud();
  Hud(const Hud&) = delete;
  Hud& operator=(const Hud&) = delete;

  /// Builds and draws the overlay into the current (default) framebuffer.
  void draw(const HudInfo& info);
  /// True while ImGui wants the mouse / keyboard (over a HUD window), so the game ignores them.
  bool wantsMouse() const;
  bool wantsKeyboard() const;
};

}  // namespace marble
