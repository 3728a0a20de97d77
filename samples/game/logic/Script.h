#pragma once
// Scripted input for headless runs and tests (docs/game.md, "Script format"). One event per line:
//
//   # comment (also after an event)
//   0.50 down W        hold W from t = 0.5 s of game time
//   1.20 up W          release it
//   2.00 press 1       down then up in the same step (toggles)
//   2.50 mouse 120 -30 drag the camera by (dx, dy) pixels
//   3.00 scroll 2      wheel notches (zoom)
//
// Times are seconds of simulated game time (fixed step), non-negative; events may come in any order and
// run sorted by time (ties keep file order). Keys are named as in Input.h, in any letter case.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "Input.h"

namespace marble {

enum class ScriptAction { Down, Up, Press, Mouse, Scroll };

struct ScriptEvent {
  double time = 0.0;
  ScriptAction action = ScriptAction::Down;
  std::string key;          // Down / Up / Press
  glm::vec2 delta{0.0f};    // Mouse: pixels; Scroll: x = notches
  int line = 0;             // 1-based, for messages
};

struct ScriptParse {
  std::vector<ScriptEvent> events;  // sorted by time, stable
  std::string error;                // empty on success, else "line N: reason"
  bool ok() const { return error.empty(); }
};

ScriptParse parseScript(std::string_view text);

/// Feeds events into an InputState as simulated time advances. Edge events (a key going down) are
/// reported through `onKeyDown` so toggles fire exactly once, as they do from GLFW's key callback.
class ScriptPlayer {
 public:
  explicit ScriptPlayer(std::vector<ScriptEvent> events) : events_(std::move(events)) {}

  /// Applies every event with time <= `time` not yet applied.
  template <class OnKeyDown>
  void advance(double time, InputState& input, OnKeyDown&& onKeyDown) {
    // A tiny slack so an event at 0.5 s fires on the step that reaches 0.5 despite float steps.
    constexpr double kSlack = 1e-9;
    while (next_ < events_.size() && events_[next_].time <= time + kSlack) {
      const ScriptEvent& e = events_[next_++];
      switch (e.action) {
        case ScriptAction::Down:
          if (input.held.insert(e.key).second) onKeyDown(e.key);
          break;
        case ScriptAction::Up: input.held.erase(e.key); break;
        case ScriptAction::Press:
          if (!input.isDown(e.key)) onKeyDown(e.key);
          break;
        case ScriptAction::Mouse: input.mouseDelta += e.delta; break;
        case ScriptAction::Scroll: input.scroll += e.delta.x; break;
      }
    }
  }
  bool finished() const { return next_ >= events_.size(); }
  std::size_t applied() const { return next_; }

 private:
  std::vector<ScriptEvent> events_;
  std::size_t next_ = 0;
};

}  // namespace marble
