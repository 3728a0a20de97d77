#pragma once
// Files built into the binary (shaders, the default scene), by path relative to the repository root.
#include <optional>
#include <span>
#include <string_view>
#include <utility>

namespace tandem {
std::span<const std::pair<std::string_view, std::string_view>> embeddedFiles();
inline std::optional<std::string_view> findEmbedded(std::string_view path) {
  for (const auto& [name, text] : embeddedFiles())
    if (name == path) return text;
  return std::nullopt;
}
}  // namespace tandem
