#include "Input.h"

#include <algorithm>
#include <cctype>

namespace marble {

const std::vector<std::string>& knownKeyNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (char c = 'A'; c <= 'Z'; ++c) n.emplace_back(1, c);
    for (char c = '0'; c <= '9'; ++c) n.emplace_back(1, c);
    for (const char* s : {"SPACE", "ENTER", "ESCAPE", "TAB", "BACKSPACE", "LEFT", "RIGHT", "UP", "DOWN", "LSHIFT",
                          "RSHIFT", "LCTRL", "RCTRL", "MINUS", "EQUAL", "LBRACKET", "RBRACKET", "COMMA", "PERIOD"})
      n.emplace_back(s);
    for (int i = 1; i <= 12; ++i) {
      std::string f = "F";  // appended, not "F" + to_string: GCC 12 warns falsely (-Wrestrict) on that
      f += std::to_string(i);
      n.push_back(f);
    }
    return n;
  }();
  return names;
}

std::optional<std::string> canonicalKeyName(std::string_view name) {
  std::string up(name);
  std::transform(up.begin(), up.end(), up.begin(),
                 [](char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); });
  const auto& names = knownKeyNames();
  if (std::find(names.begin(), names.end(), up) == names.end()) return std::nullopt;
  return up;
}

MoveIntent moveIntent(const InputState& input) {
  MoveIntent m;
  // WASD and the arrows both move, so either hand layout works; opposite keys cancel.
  if (input.isDown("W") || input.isDown("UP")) m.move.y += 1.0f;
  if (input.isDown("S") || input.isDown("DOWN")) m.move.y -= 1.0f;
  if (input.isDown("D") || input.isDown("RIGHT")) m.move.x += 1.0f;
  if (input.isDown("A") || input.isDown("LEFT")) m.move.x -= 1.0f;
  m.brake = input.isDown("SPACE");
  if (input.isDown("E")) m.orbit += 1.0f;
  if (input.isDown("Q")) m.orbit -= 1.0f;
  return m;
}

}  // namespace marble
