#include "support/TestSupport.h"

#include <filesystem>

namespace tandem::test {

std::string sourceDir() { return TANDEM_SOURCE_DIR; }

std::string outputDir() {
  std::filesystem::path p = std::filesystem::path(TANDEM_BINARY_DIR) / "test-output";
  std::filesystem::create_directories(p);
  return p.string();
}

std::string sharedAssetsDir() {
  std::filesystem::path p = std::filesystem::path(TANDEM_SOURCE_DIR).parent_path() / "shared" / "assets";
  std::error_code ec;
  return std::filesystem::is_directory(p, ec) ? std::filesystem::canonical(p).string() : std::string();
}

}  // namespace tandem::test
