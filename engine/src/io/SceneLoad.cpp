#include <algorithm>
#include <cctype>
#include <filesystem>

#include "tandem/Gltf.h"
#include "tandem/SceneFile.h"

namespace tandem {

Result<Scene> loadAnyScene(const std::string& path) {
  if (path.empty()) return loadDefaultScene();
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".gltf" || ext == ".glb") return loadGltf(path);
  if (ext == ".json") return loadSceneFile(path);
  return Error{path + ": unknown scene type '" + ext + "' (expected .json, .gltf or .glb)"};
}

}  // namespace tandem
