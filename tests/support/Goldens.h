#pragma once
// When golden images may be rewritten: only when the test binary is run with --update-goldens, which the build's
// `update-goldens` target passes (cmake --build build --target update-goldens). The environment variable the
// tests once read, left set in a shell, made every golden test overwrite its golden and skip — so a set
// TANDEM_UPDATE_GOLDENS now fails the test instead, naming the target.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

namespace tandem::test {

inline bool updatingGoldens() {
  for (const std::string& arg : ::testing::internal::GetArgvs())
    if (arg == "--update-goldens") return true;
  return false;
}

/// Empty when golden tests may run; otherwise why not (a stray TANDEM_UPDATE_GOLDENS).
inline std::string strayGoldenUpdate() {
  if (std::getenv("TANDEM_UPDATE_GOLDENS") == nullptr) return {};
  return "TANDEM_UPDATE_GOLDENS is set, but goldens are rewritten only by `cmake --build build --target "
         "update-goldens` (unset it to compare)";
}

}  // namespace tandem::test
