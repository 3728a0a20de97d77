#pragma once
// The JSON scene format (docs/scene-format.md): meshes (glTF files or built-in primitives), materials,
// lights, camera and render settings. Errors name the file, the JSON path and the reason.
//
//   Result<Scene> s = loadSceneFile("assets/scenes/whitted.json");
#include <memory>
#include <string>
#include <string_view>

#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem {

/// Loads a scene file. glTF files it names are resolved relative to the scene file's folder.
Result<Scene> loadSceneFile(const std::string& path);
/// Parses scene JSON text; `name` is used in error messages and `baseDir` resolves relative files.
Result<Scene> parseSceneJson(std::string_view text, const std::string& name, const std::string& baseDir);
/// The embedded default scene (assets/scenes/whitted.json, built into the binary).
Result<Scene> loadDefaultScene();
std::string_view defaultSceneText();

}  // namespace tandem

namespace tandem {
/// Reads an equirectangular Radiance .hdr image for Environment::map (readHdr's bounds; docs/environment.md).
Result<std::shared_ptr<const EnvironmentMap>> loadEnvironmentMap(const std::string& path);
/// Loads any scene the tools accept: a JSON scene file (.json), a glTF file (.gltf / .glb), or the
/// embedded default scene when `path` is empty.
Result<Scene> loadAnyScene(const std::string& path);
}  // namespace tandem
