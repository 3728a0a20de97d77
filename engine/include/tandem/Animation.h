#pragma once
// Node-transform animation (glTF animations of translation / rotation / scale), kept beside a Scene.
// The scene itself stays a flat list of instances; this holds the node hierarchy those instances came
// from, the keyframes, and which instance follows which node, so the hierarchy is evaluated per frame.
//
//   GltfAsset a = *loadGltfAsset("AnimatedCube.gltf");
//   a.animation.apply(0, seconds, a.scene);   // moves the instances of clip 0's nodes
//
// Skins and morph targets are not represented (the importer warns and keeps the static mesh).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "tandem/Scene.h"

namespace tandem {

enum class AnimPath : std::uint8_t { Translation = 0, Rotation = 1, Scale = 2 };
enum class AnimInterpolation : std::uint8_t { Step = 0, Linear = 1, CubicSpline = 2 };

/// One animated property of one node. `times` are finite and strictly increasing (the importer
/// skips channels that are not). `values` holds xyz (w unused) or a quaternion as (x, y, z, w);
/// CUBICSPLINE stores three per key: in-tangent, value, out-tangent (glTF order).
struct AnimChannel {
  std::uint32_t node = 0;  // index into SceneAnimation::nodes
  AnimPath path = AnimPath::Translation;
  AnimInterpolation interpolation = AnimInterpolation::Linear;
  std::vector<float> times;
  std::vector<glm::vec4> values;
};

struct AnimClip {
  std::string name;
  float duration = 0.0f;  // last key time over all channels (seconds)
  std::vector<AnimChannel> channels;
};

/// A node of the hierarchy at rest. Nodes are stored parents first (parent < own index).
struct AnimNode {
  int parent = -1;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // (w, x, y, z) as glm stores it
  glm::vec3 scale{1.0f};
  bool hasMatrix = false;  // glTF `matrix` nodes cannot be animated; `matrix` is used as is
  glm::mat4 matrix{1.0f};
};

/// An instance that follows a node: worldFromObject = worldFromNode · nodeFromObject
/// (nodeFromObject is the EXT_mesh_gpu_instancing transform, identity otherwise).
struct AnimBinding {
  std::uint32_t instance = 0;
  std::uint32_t node = 0;
  glm::mat4 nodeFromObject{1.0f};
};

struct SceneAnimation {
  std::vector<AnimNode> nodes;
  std::vector<AnimClip> clips;
  std::vector<AnimBinding> bindings;

  bool empty() const { return clips.empty(); }
  /// World transforms of every node at `seconds` into clip `clip` (time clamped to the keys; nodes
  /// without channels keep their rest transform). An out-of-range clip gives the rest pose.
  std::vector<glm::mat4> evaluate(std::size_t clip, float seconds) const;
  /// Writes worldFromObject of every bound instance. Bindings naming instances the scene lacks are skipped.
  void apply(std::size_t clip, float seconds, Scene& scene) const;
};

/// Samples one channel at time t (clamped to its first and last key). For rotations the result is a
/// unit quaternion (x, y, z, w); LINEAR rotations use shortest-path slerp.
glm::vec4 sampleChannel(const AnimChannel& channel, float t);

}  // namespace tandem
