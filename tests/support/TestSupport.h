#pragma once
// Helpers shared by every test binary.
#include <string>

namespace tandem::test {
/// The repository root (assets, goldens) and a scratch folder under the build tree for outputs.
std::string sourceDir();
std::string outputDir();  // created on first use: <build>/test-output
/// ../shared/assets beside the checkout, or empty when absent (tests then GTEST_SKIP with a message).
std::string sharedAssetsDir();
}  // namespace tandem::test
