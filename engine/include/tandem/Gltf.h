#pragma once
// glTF 2.0 import (.gltf + .bin + images, .glb) through tinygltf, treating every file as untrusted:
// files are read only inside the asset's own folder, validated before any data is used.
// docs/gltf.md documents the material mapping, light units, defaults and limits.
//
//   GltfOptions opt;
//   Result<Scene> s = loadGltf("model/Model.gltf", opt);
#include <functional>
#include <string>
#include <vector>

#include "tandem/Animation.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem {

struct GltfLimits {
  std::uint64_t maxFileBytes = 512ull << 20;    // any one file read (main, buffer, image)
  int maxJsonDepth = 64;                        // nesting depth of the JSON
  std::uint64_t maxImagePixels = 4096ull * 4096; // per image, checked before decoding
  std::uint64_t maxTriangles = 20'000'000;
  std::uint64_t maxNodes = 1'000'000;
  std::uint64_t maxTotalPixels = 64ull << 20;   // all decoded images together
  std::uint64_t maxObjects = 4'000'000;         // accessors, views, meshes, materials… each
  // The resource contract (docs/gltf.md, "Resources"): the parsed model (estimated before tinygltf builds
  // it) and everything decoded from it — accessor reads, texels, meshes, instances, repeated file reads —
  // each stay within budgetBaseBytes + budgetBytesPerInputByte × (bytes of the main file and of every
  // distinct file it reads). A file asking for more is refused with a message naming what and the budget.
  std::uint64_t budgetBaseBytes = 64ull << 20;
  std::uint64_t budgetBytesPerInputByte = 32;
};

/// What one load read and produced (for tests and tools; see GltfLimits' budget).
struct GltfLoadStats {
  std::uint64_t inputBytes = 0;     // main file + each distinct file read, once
  std::uint64_t modelEstimate = 0;  // bytes the parsed model was estimated at before parsing
  std::uint64_t decodedBytes = 0;   // bytes charged to the budget while converting
  std::uint64_t budgetBytes = 0;    // the budget for this input
};

struct GltfOptions {
  int sceneIndex = -1;  // -1: the file's default scene (or scene 0)
  GltfLimits limits;
  /// Called with the canonical path of every file the loader opens (tests check confinement).
  std::function<void(const std::string&)> onFileOpened;
  bool addDefaultLights = true;  // when the file has none (see docs/gltf.md)
  bool addDefaultCamera = true;
  /// Called with every warning (skipped primitive, missing image, ignored skin…); they also go to the log.
  std::function<void(const std::string&)> onWarning;
};

/// A loaded file: the scene and its node-transform animation (empty when the file has none).
/// Instances that follow animated nodes are marked `dynamic`.
struct GltfAsset {
  Scene scene;
  SceneAnimation animation;
  GltfLoadStats stats;
};

/// Loads a glTF file into a Scene. Warnings (skipped primitives, missing images) go to the log.
Result<Scene> loadGltf(const std::string& path, const GltfOptions& options = {});
/// The same, keeping the animation.
Result<GltfAsset> loadGltfAsset(const std::string& path, const GltfOptions& options = {});

}  // namespace tandem
