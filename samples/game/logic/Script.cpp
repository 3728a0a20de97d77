#include "Script.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace marble {

namespace {

// Parses a whole token as a finite number; std::stod alone would accept "1.5abc".
bool parseNumber(const std::string& token, double& out) {
  if (token.empty()) return false;
  std::size_t used = 0;
  try {
    out = std::stod(token, &used);
  } catch (...) {
    return false;
  }
  return used == token.size() && std::isfinite(out);
}

}  // namespace

ScriptParse parseScript(std::string_view text) {
  ScriptParse result;
  std::istringstream in{std::string(text)};
  std::string raw;
  int lineNo = 0;
  auto fail = [&](const std::string& why) {
    result.events.clear();
    result.error = "line " + std::to_string(lineNo) + ": " + why;
    return result;
  };
  while (std::getline(in, raw)) {
    ++lineNo;
    if (auto hash = raw.find('#'); hash != std::string::npos) raw.erase(hash);
    std::istringstream line(raw);
    std::vector<std::string> tok;
    for (std::string t; line >> t;) tok.push_back(t);
    if (tok.empty()) continue;

    ScriptEvent e;
    e.line = lineNo;
    if (!parseNumber(tok[0], e.time) || e.time < 0.0)
      return fail("expected a time in seconds (>= 0), got '" + tok[0] + "'");
    if (tok.size() < 2) return fail("missing action after the time (down, up, press, mouse, scroll)");
    const std::string& action = tok[1];
    if (action == "down" || action == "up" || action == "press") {
      if (tok.size() != 3) return fail("'" + action + "' takes exactly one key name");
      auto key = canonicalKeyName(tok[2]);
      if (!key) return fail("unknown key '" + tok[2] + "'");
      e.action = action == "down" ? ScriptAction::Down : action == "up" ? ScriptAction::Up : ScriptAction::Press;
      e.key = *key;
    } else if (action == "mouse") {
      double dx = 0, dy = 0;
      if (tok.size() != 4 || !parseNumber(tok[2], dx) || !parseNumber(tok[3], dy))
        return fail("'mouse' takes two numbers: dx dy in pixels");
      e.action = ScriptAction::Mouse;
      e.delta = {static_cast<float>(dx), static_cast<float>(dy)};
    } else if (action == "scroll") {
      double n = 0;
      if (tok.size() != 3 || !parseNumber(tok[2], n)) return fail("'scroll' takes one number of notches");
      e.action = ScriptAction::Scroll;
      e.delta = {static_cast<float>(n), 0.0f};
    } else {
      return fail("unknown action '" + action + "' (down, up, press, mouse, scroll)");
    }
    result.events.push_back(std::move(e));
  }
  std::stable_sort(result.events.begin(), result.events.end(),
                   [](const ScriptEvent& a, const ScriptEvent& b) { return a.time < b.time; });
  return result;
}

}  // namespace marble
