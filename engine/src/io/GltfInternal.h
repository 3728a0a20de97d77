#pragma once
// Internals of the glTF importer (Gltf*.cpp). Not a public header.
//
// The pipeline, in order (each step refuses before the next one can be hurt by bad input):
//   GltfFs.cpp        read the main file inside its canonical folder; tinygltf filesystem callbacks
//                     confined to that folder; JSON depth/type pre-scan; GLB header and chunk checks.
//   GltfValidate.cpp  our own validation pass over the parsed tinygltf::Model (ranges, references,
//                     graph, versions, extensions) with 64-bit overflow-safe arithmetic.
//   GltfImport.cpp    conversion into tandem::Scene from validated data only; deferred image decoding.
//   GltfAnimation.cpp keyframe extraction and the node-transform evaluator.
#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "tandem/Animation.h"
#include "tandem/Gltf.h"
#include "tandem/Result.h"
#include "io/LoadBudget.h"

namespace tandem::gltf {

/// State shared by the filesystem callbacks for one load. tinygltf only hands us a void*, so the
/// callbacks record refusals here and the loader turns the first one into the load's error
/// (tinygltf itself would only say "file not found", or merely warn for images).
struct Confinement {
  std::filesystem::path root;   // canonical folder of the main file
  std::string rootPrefix;       // root as a string ending in '/'
  std::uint64_t maxFileBytes = 0;
  const std::function<void(const std::string&)>* onFileOpened = nullptr;
  std::vector<std::string> refusals;  // "uri 'x': reason"
  // A file read for the first time joins the budget's input; reading it again (several buffers or images
  // naming one file) is charged to the budget, since tinygltf keeps a copy per buffer.
  LoadBudget* budget = nullptr;
  std::set<std::string> filesRead;
};

/// Outcome of resolving one path handed to us by tinygltf.
enum class Resolve { Ok, NotFound, Refused };
Resolve resolveInside(Confinement& c, const std::string& joined, std::filesystem::path* out);

/// Reads a regular file that has already been resolved inside the folder, honouring the size cap.
Result<std::vector<std::uint8_t>> readFileCapped(const std::filesystem::path& canonical, std::uint64_t cap,
                                                 const std::function<void(const std::string&)>* onOpened);

tinygltf::FsCallbacks makeFsCallbacks(Confinement* c);

/// Rejects JSON nested deeper than maxDepth, scanning bytes iteratively (tinygltf and nlohmann recurse).
Result<void> checkJsonDepth(const std::uint8_t* data, std::size_t size, int maxDepth);
/// What the pre-scan learnt about a file before tinygltf parses it.
struct JsonScan {
  std::uint64_t modelEstimate = 0;  // bytes tinygltf's Model will hold for it (an over-estimate)
};
/// One iterative walk over the parsed JSON, in memory bounded by the nesting depth: rejects indices given
/// as floats, negatives or values past 2^31 (tinygltf casts them modulo 2^32), a GLB buffer other than
/// buffers[0] without a uri, and estimates the model tinygltf will build (GltfLimits' budget).
/// Call after checkJsonDepth (the walk is iterative, but the parse tree's destructor recurses).
Result<JsonScan> prescanJson(const std::uint8_t* data, std::size_t size, bool glb);

/// Checks a GLB container; on success `json` points at the JSON chunk.
Result<void> checkGlb(const std::vector<std::uint8_t>& bytes, std::size_t* jsonOffset, std::size_t* jsonSize);

/// Encoded bytes of images given by URI or data URI, captured by our image-loader callback.
/// Images stored in bufferViews are *not* captured there: tinygltf hands the callback a pointer computed
/// from an unchecked view; we read those bytes later from the validated view instead.
/// Identical bytes are kept once (many images naming one file): `sourceOf` maps a glTF image to the
/// index of its bytes in `unique`, which is also what textures are decoded and cached by.
struct DeferredImages {
  std::vector<std::vector<std::uint8_t>> unique;
  std::map<int, int> sourceOf;
  std::multimap<std::uint64_t, int> byHash;
};
bool recordImage(tinygltf::Image* image, int index, std::string* err, std::string* warn, int reqW, int reqH,
                 const unsigned char* bytes, int size, void* user);

// ---- validation (GltfValidate.cpp) ----

int componentSize(int componentType);  // bytes, 0 when unknown
int componentCount(int type);          // 1..16, 0 when unknown
/// Element size including the column padding of small-component matrices (glTF 3.6.2.4).
std::uint64_t elementSize(int componentType, int type);

/// Extensions this importer understands; anything else in extensionsRequired is refused.
bool supportedExtension(const std::string& name);

/// Checks every object of the model. `file` prefixes messages. Returns the first problem.
Result<void> validateModel(const tinygltf::Model& m, const GltfLimits& limits, const std::string& file);

// ---- accessor reading from validated models (GltfValidate.cpp) ----

/// Reads `count × components` values as floats, applying `normalized` and sparse substitution.
/// Only for accessors that validateModel accepted; refuses matrix types. The result's bytes are charged
/// to `budget` (when given) before they are allocated.
Result<std::vector<float>> readFloats(const tinygltf::Model& m, int accessor, const std::string& file,
                                      LoadBudget* budget);
/// Reads an unsigned scalar accessor (indices), charged to `budget` likewise.
Result<std::vector<std::uint32_t>> readIndices(const tinygltf::Model& m, int accessor, const std::string& file,
                                               LoadBudget* budget);

// ---- import (GltfImport.cpp) and animation (GltfAnimation.cpp) ----

struct Warn {
  std::string file;
  const GltfOptions* options = nullptr;
  int count = 0;
  void operator()(const std::string& message);
};

/// Per glTF node: its parent (or -1) and local transform, the node order parents-first.
struct NodeInfo {
  int parent = -1;
  glm::mat4 local{1.0f};
};

/// Builds clips from the model's animations for nodes listed in `animIndexOfNode` (glTF node →
/// index into SceneAnimation::nodes, −1 when not in the scene). Bad channels are skipped with a warning.
Result<void> buildAnimationClips(const tinygltf::Model& m, const std::vector<int>& animIndexOfNode, SceneAnimation& anim,
                                 Warn& warn, const std::string& file, LoadBudget& budget);

/// Local TRS of a glTF node (matrix when given).
glm::mat4 nodeLocalMatrix(const tinygltf::Node& n);

}  // namespace tandem::gltf
