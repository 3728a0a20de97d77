#include "io/SceneJson.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <set>
#include <sstream>

namespace tandem::scenefile {

namespace {
// ---------------------------------------------------------------------------------------------------
// Text → JSON, with line/column on syntax errors, duplicate-key detection and a depth limit.

std::pair<std::size_t, std::size_t> lineColumn(std::string_view text, std::size_t byte) {
  byte = std::min(byte, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

// Builds the document from nlohmann's SAX events, in time linear in the text: nlohmann's own DOM parser
// inserts each key into an ordered_map (a vector) with a linear search, which made an object of n keys
// cost n² (a 4 MB file of mesh names took seconds). Keys are appended in file order instead, and
// duplicates are found with a set per open object and reported by their JSON pointer (nlohmann keeps the
// last of duplicate keys silently, which would hide a copy-paste mistake: two "kd" in one material).
class JsonBuilder {
 public:
  using number_integer_t = Json::number_integer_t;
  using number_unsigned_t = Json::number_unsigned_t;
  using number_float_t = Json::number_float_t;
  using string_t = Json::string_t;
  using binary_t = Json::binary_t;

  explicit JsonBuilder(const std::string& file) : file_(file) {}

  bool null() { return add(Json(nullptr)) != nullptr; }
  bool boolean(bool v) { return add(Json(v)) != nullptr; }
  bool number_integer(number_integer_t v) { return add(Json(v)) != nullptr; }
  bool number_unsigned(number_unsigned_t v) { return add(Json(v)) != nullptr; }
  bool number_float(number_float_t v, const string_t& literal) {
    if (!std::isfinite(v)) {
      overflow_ = literal;
      return false;
    }
    return add(Json(v)) != nullptr;
  }
  bool string(string_t& v) { return add(Json(std::move(v))) != nullptr; }
  bool binary(binary_t&) { return false; }  // JSON text has no binary values
  bool start_object(std::size_t) { return open(Json::object(), false); }
  bool start_array(std::size_t) { return open(Json::array(), true); }
  bool key(string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second) throw SceneFileError{file_ + ": " + currentPath() + ": duplicate key '" + k + "'"};
    return true;
  }
  bool end_object() {
    frames_.pop_back();
    return true;
  }
  bool end_array() {
    frames_.pop_back();
    return true;
  }
  bool parse_error(std::size_t byte, const std::string& lastToken, const nlohmann::detail::exception& e) {
    if (e.id == 406) {  // a number literal beyond double range: reported at its start, not after it
      overflow_ = lastToken;
      return false;
    }
    errorByte_ = byte;
    error_ = e.what();
    return false;
  }

  Json root;
  std::optional<std::string> overflow_;  // a number literal that overflows a double
  std::optional<std::string> error_;     // nlohmann's parse error
  std::size_t errorByte_ = 0;

 private:
  struct Frame {
    Json* value;
    bool array;
    std::size_t count = 0;  // elements so far (arrays)
    std::string key;        // the current key (objects)
    std::set<std::string> keys;
  };

  Json* add(Json v) {
    if (frames_.empty()) {
      root = std::move(v);
      return &root;
    }
    Frame& f = frames_.back();
    if (f.array) {
      ++f.count;
      f.value->push_back(std::move(v));
      return &f.value->back();
    }
    // Appended to the ordered map's vector directly: the key is known to be new (checked in key()).
    auto& members = static_cast<Json::object_t::Container&>(f.value->get_ref<Json::object_t&>());
    members.emplace_back(f.key, std::move(v));
    return &members.back().second;
  }
  bool open(Json v, bool array) {
    if (frames_.size() >= std::size_t(kMaxJsonDepth)) {
      // The path of the container being opened, for the message.
      if (!frames_.empty() && frames_.back().array) ++frames_.back().count;
      throw SceneFileError{file_ + ": " + currentPath() + ": nesting deeper than " + std::to_string(kMaxJsonDepth) + " levels"};
    }
    Json* j = add(std::move(v));
    frames_.push_back(Frame{j, array, 0, {}, {}});
    return true;
  }
  std::string currentPath() const {
    std::string p;
    for (const Frame& f : frames_) p = f.array ? child(p, f.count - 1) : child(p, f.key);
    return p.empty() ? "/" : p;
  }

  std::string file_;
  std::vector<Frame> frames_;
};

}  // namespace

std::string escapePointer(std::string_view token) {
  std::string out;
  for (char c : token) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}
std::string child(const std::string& path, std::string_view key) { return path + "/" + escapePointer(key); }
std::string child(const std::string& path, std::size_t index) { return path + "/" + std::to_string(index); }

std::string joinNames(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string out;
  // A glTF file can hold thousands of names; the first ones are enough to spot a typo.
  const std::size_t shown = std::min<std::size_t>(names.size(), 24);
  for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (shown < names.size()) out += ", ... (" + std::to_string(names.size() - shown) + " more)";
  return out;
}

std::string formatNumber(double v) {
  // The shortest text that reads back as the same double: a message quotes the file's number as written
  // (16384.25, not the 6 digits a stream gives, 16384.2).
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

Json parseText(std::string_view text, const std::string& file) {
  JsonBuilder builder(file);
  Json::sax_parse(text.begin(), text.end(), &builder, nlohmann::detail::input_format_t::json, /*strict=*/true,
                  /*ignore_comments=*/true);
  if (builder.error_) {
    auto [line, column] = lineColumn(text, builder.errorByte_ == 0 ? 0 : builder.errorByte_ - 1);
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line L, column C: reason";
    // keep the reason, and give the position in the same form as the rest of our messages.
    const std::string& what = *builder.error_;
    std::size_t colon = what.find(": ");
    std::string reason = colon == std::string::npos ? what : what.substr(colon + 2);
    throw SceneFileError{file + ": line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + reason};
  }
  if (builder.overflow_) {
    // The SAX interface gives no position for a value, so find the literal in the text.
    std::string where;
    std::size_t at = builder.overflow_->empty() ? std::string_view::npos : text.find(*builder.overflow_);
    if (at != std::string_view::npos) {
      auto [line, column] = lineColumn(text, at);
      where = "line " + std::to_string(line) + ", column " + std::to_string(column) + ": ";
    }
    throw SceneFileError{file + ": " + where + "number overflow parsing '" + *builder.overflow_ +
                         "' (not representable as a number)"};
  }
  return std::move(builder.root);
}


}  // namespace tandem::scenefile
