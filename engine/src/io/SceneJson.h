#pragma once
// The scene file's strict JSON reader (docs/scene-format.md): text to a JSON document in time linear in its
// size, with line and column on syntax errors, duplicate keys and a depth limit; then typed access where
// every read names the JSON pointer of what it reads and fails with SceneFileError. The scene builder
// (SceneFile.cpp) reads through it. Internal to the scene loaders.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace tandem::scenefile {

// ordered_json keeps the file's order, so "known: ..." lists and mesh/material indices follow the file.
using Json = nlohmann::ordered_json;

inline constexpr int kMaxJsonDepth = 64;

struct SceneFileError {
  std::string message;
};

// JSON pointers (RFC 6901), used as the location in every message.
std::string escapePointer(std::string_view token);
std::string child(const std::string& path, std::string_view key);
std::string child(const std::string& path, std::size_t index);
/// "a, b, c" (the first names of a long list), "none" when empty.
std::string joinNames(const std::vector<std::string>& names);
std::string formatNumber(double v);

/// Text → JSON: throws SceneFileError naming the line and column of a syntax error, the pointer of a
/// duplicate key, or nesting deeper than kMaxJsonDepth.
Json parseText(std::string_view text, const std::string& file);

// ---------------------------------------------------------------------------------------------------
// Typed access with ranges. Every reader takes the value and its JSON pointer.

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false;  // lo itself excluded
  bool hiOpen = false;
  bool contains(double v) const {
    return (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
  }
  std::string describe() const {
    const bool hasLo = std::isfinite(lo), hasHi = std::isfinite(hi);
    if (hasLo && hasHi)
      return std::string("in ") + (loOpen ? "(" : "[") + formatNumber(lo) + ", " + formatNumber(hi) + (hiOpen ? ")" : "]");
    if (hasLo) return std::string(loOpen ? "> " : ">= ") + formatNumber(lo);
    if (hasHi) return std::string(hiOpen ? "< " : "<= ") + formatNumber(hi);
    return "finite";
  }
};
constexpr Range kAny{};
constexpr Range kNonNegative{0.0};
constexpr Range kPositive{0.0, std::numeric_limits<double>::infinity(), true};
constexpr Range kUnit{0.0, 1.0};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
    throw SceneFileError{file_ + ": " + (path.empty() ? std::string("/") : path) + ": " + reason};
  }
  const std::string& file() const { return file_; }

  const Json& object(const Json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, std::string("expected an object, got ") + typeName(j));
    return j;
  }
  const Json& array(const Json& j, const std::string& path) const {
    if (!j.is_array()) fail(path, std::string("expected an array, got ") + typeName(j));
    return j;
  }
  /// Rejects keys outside `allowed`, naming the key and the allowed ones.
  void checkKeys(const Json& obj, const std::string& path, std::initializer_list<std::string_view> allowed,
                 std::string_view context = {}) const {
    checkKeys(obj, path, std::span<const std::string_view>(allowed.begin(), allowed.size()), context);
  }
  void checkKeys(const Json& obj, const std::string& path, std::span<const std::string_view> allowed,
                 std::string_view context = {}) const {
    for (const auto& [key, value] : obj.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(child(path, key), "unknown key '" + key + "'" + (context.empty() ? "" : " for " + std::string(context)) +
                                 " (allowed: " + list + ")");
    }
  }
  static const Json* find(const Json& obj, std::string_view key) {
    auto it = obj.find(std::string(key));
    return it == obj.end() ? nullptr : &*it;
  }
  const Json& require(const Json& obj, const std::string& path, std::string_view key,
                      std::string_view what = {}) const {
    const Json* v = find(obj, key);
    if (!v) fail(path, "missing required key '" + std::string(key) + "'" + (what.empty() ? "" : " (" + std::string(what) + ")"));
    return *v;
  }

  float number(const Json& j, const std::string& path, Range range = kAny) const {
    if (!j.is_number()) fail(path, std::string("expected a number, got ") + typeName(j));
    const double d = j.get<double>();
    // Doubles beyond float range (1e39) would become infinite in the scene: reject them here.
    const auto f = static_cast<float>(d);
    if (!std::isfinite(d) || !std::isfinite(f)) fail(path, formatNumber(d) + " is too large (not a finite float)");
    if (!range.contains(d)) fail(path, "must be " + range.describe() + ", got " + formatNumber(d));
    return f;
  }
  int integer(const Json& j, const std::string& path, int lo, int hi) const {
    if (!j.is_number()) fail(path, std::string("expected an integer, got ") + typeName(j));
    const double d = j.get<double>();
    if (!j.is_number_integer() && d != std::floor(d)) fail(path, "expected an integer, got " + formatNumber(d));
    if (!(d >= lo && d <= hi))
      fail(path, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + formatNumber(d));
    return static_cast<int>(d);
  }
  bool boolean(const Json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, std::string("expected true or false, got ") + typeName(j));
    return j.get<bool>();
  }
  std::string string(const Json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, std::string("expected a string, got ") + typeName(j));
    return j.get<std::string>();
  }
  std::string nonEmptyString(const Json& j, const std::string& path) const {
    std::string s = string(j, path);
    if (s.empty()) fail(path, "must not be empty");
    return s;
  }
  /// [x, y, z]; with `scalarOk`, a single number s means [s, s, s].
  glm::vec3 vec3(const Json& j, const std::string& path, Range range = kAny, bool scalarOk = false) const {
    if (scalarOk && j.is_number()) return glm::vec3(number(j, path, range));
    if (!j.is_array() || j.size() != 3)
      fail(path, std::string("expected [x, y, z]") + (scalarOk ? " or a number" : "") + ", got " + describe(j));
    return {number(j[0], child(path, 0), range), number(j[1], child(path, 1), range), number(j[2], child(path, 2), range)};
  }
  /// A linear RGB colour: [r, g, b] or a grey level.
  glm::vec3 color(const Json& j, const std::string& path) const { return vec3(j, path, kNonNegative, true); }

  static const char* typeName(const Json& j) {
    switch (j.type()) {
      case Json::value_t::null: return "null";
      case Json::value_t::object: return "an object";
      case Json::value_t::array: return "an array";
      case Json::value_t::string: return "a string";
      case Json::value_t::boolean: return "a boolean";
      case Json::value_t::binary: return "binary data";
      case Json::value_t::discarded: return "nothing";
      default: return "a number";
    }
  }
  static std::string describe(const Json& j) {
    if (j.is_array()) return "an array of " + std::to_string(j.size());
    return typeName(j);
  }

 private:
  std::string file_;
};

}  // namespace tandem::scenefile
