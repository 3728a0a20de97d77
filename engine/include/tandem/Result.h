#pragma once
// Error values for bad input (files, settings). Bugs assert instead; per-frame code never fails.
//
//   Result<Scene> r = loadSceneFile("a.json");
//   if (!r) { std::cerr << r.error().message << "\n"; return 1; }
//   Scene scene = std::move(*r);
#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace tandem {

/// What went wrong, phrased for the user: names the file / object / JSON path and the reason.
struct Error {
  std::string message;
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}
  Result(Error e) : v_(std::move(e)) {}
  explicit operator bool() const { return v_.index() == 0; }
  bool ok() const { return v_.index() == 0; }
  T& value() { assert(ok()); return std::get<0>(v_); }
  const T& value() const { assert(ok()); return std::get<0>(v_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const { assert(!ok()); return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error e) : err_(std::move(e)), failed_(true) {}
  explicit operator bool() const { return !failed_; }
  bool ok() const { return !failed_; }
  const Error& error() const { assert(failed_); return err_; }

 private:
  Error err_;
  bool failed_ = false;
};

}  // namespace tandem
