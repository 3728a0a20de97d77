#pragma once
// Keys by name, so the same game loop takes input from GLFW (a window) or from a script (headless).
// Names are upper case: A..Z, 0..9, SPACE, ENTER, ESCAPE, TAB, BACKSPACE, LEFT, RIGHT, UP, DOWN,
// LSHIFT, RSHIFT, LCTRL, RCTRL, F1..F12, MINUS, EQUAL, LBRACKET, RBRACKET, COMMA, PERIOD.
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

namespace marble {

/// Every key name a script or the key bindings may use.
const std::vector<std::string>& knownKeyNames();
/// The canonical (upper-case) name, or nullopt when the key is unknown. Accepts any letter case.
std::optional<std::string> canonicalKeyName(std::string_view name);

/// What the player holds down this step, plus the mouse drag / wheel accumulated since the last step.
struct InputState {
  std::set<std::string, std::less<>> held;
  glm::vec2 mouseDelta{0.0f};  // pixels dragged (orbit), x right, y down
  float scroll = 0.0f;         // wheel notches, positive = away from the user (zoom in)

  bool isDown(std::string_view key) const { return held.find(key) != held.end(); }
  /// Forgets the per-step deltas once a step has consumed them; held keys stay.
  void consumeDeltas() {
    mouseDelta = glm::vec2(0.0f);
    scroll = 0.0f;
  }
};

/// The movement the game reads from held keys: x = right, y = forward, each in [-1, 1].
struct MoveIntent {
  glm::vec2 move{0.0f};
  bool brake = false;
  float orbit = 0.0f;  // keyboard camera orbit, -1 (Q) .. 1 (E)
};
MoveIntent moveIntent(const InputState& input);

}  // namespace marble
