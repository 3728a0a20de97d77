// Node-transform animation: keyframe extraction from a validated model and the evaluator.
#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "io/GltfInternal.h"

namespace tandem {

namespace {

glm::vec4 normalizeQuat(glm::vec4 q) {
  const float len = glm::length(q);
  return len > 1e-20f && std::isfinite(len) ? q / len : glm::vec4(0, 0, 0, 1);
}

// Shortest-path spherical interpolation of (x, y, z, w) quaternions.
glm::vec4 slerp(glm::vec4 a, glm::vec4 b, float u) {
  float d = glm::dot(a, b);
  if (d < 0.0f) {
    b = -b;
    d = -d;
  }
  if (d > 0.9995f) return normalizeQuat(glm::mix(a, b, u));  // nearly parallel: sin θ ≈ 0
  const float theta = std::acos(std::min(d, 1.0f));
  const float s = std::sin(theta);
  return normalizeQuat(a * (std::sin((1.0f - u) * theta) / s) + b * (std::sin(u * theta) / s));
}

glm::quat toQuat(glm::vec4 q) { return glm::quat(q.w, q.x, q.y, q.z); }

}  // namespace

glm::vec4 sampleChannel(const AnimChannel& ch, float t) {
  const bool cubic = ch.interpolation == AnimInterpolation::CubicSpline;
  const bool rot = ch.path == AnimPath::Rotation;
  const std::size_t n = ch.times.size();
  if (n == 0 || ch.values.size() < n * (cubic ? 3 : 1)) return rot ? glm::vec4(0, 0, 0, 1) : glm::vec4(0.0f);
  auto key = [&](std::size_t k) { return cubic ? ch.values[3 * k + 1] : ch.values[k]; };
  auto finish = [&](glm::vec4 v) { return rot ? normalizeQuat(v) : v; };
  if (!(t > ch.times.front())) return finish(key(0));  // also catches NaN t
  if (t >= ch.times.back()) return finish(key(n - 1));
  const std::size_t k = std::size_t(std::upper_bound(ch.times.begin(), ch.times.end(), t) - ch.times.begin()) - 1;
  const float t0 = ch.times[k], t1 = ch.times[k + 1];
  const float dt = t1 - t0;  // > 0: times are strictly increasing (checked at import)
  const float u = std::clamp((t - t0) / dt, 0.0f, 1.0f);
  switch (ch.interpolation) {
    case AnimInterpolation::Step: return finish(key(k));
    case AnimInterpolation::Linear: return rot ? slerp(key(k), key(k + 1), u) : glm::mix(key(k), key(k + 1), u);
    case AnimInterpolation::CubicSpline: {
      // glTF appendix C: Hermite spline with tangents scaled by the key interval.
      const glm::vec4 p0 = ch.values[3 * k + 1], m0 = dt * ch.values[3 * k + 2];
      const glm::vec4 p1 = ch.values[3 * (k + 1) + 1], m1 = dt * ch.values[3 * (k + 1)];
      const float u2 = u * u, u3 = u2 * u;
      return finish((2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1);
    }
  }
  return finish(key(k));
}

std::vector<glm::mat4> SceneAnimation::evaluate(std::size_t clip, float seconds) const {
  std::vector<glm::vec3> t(nodes.size()), s(nodes.size());
  std::vector<glm::quat> r(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    t[i] = nodes[i].translation;
    r[i] = nodes[i].rotation;
    s[i] = nodes[i].scale;
  }
  if (clip < clips.size())
    for (const AnimChannel& ch : clips[clip].channels) {
      if (ch.node >= nodes.size()) continue;
      const glm::vec4 v = sampleChannel(ch, seconds);
      switch (ch.path) {
        case AnimPath::Translation: t[ch.node] = glm::vec3(v); break;
        case AnimPath::Rotation: r[ch.node] = toQuat(v); break;
        case AnimPath::Scale: s[ch.node] = glm::vec3(v); break;
      }
    }
  std::vector<glm::mat4> world(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const AnimNode& n = nodes[i];
    const glm::mat4 local = n.hasMatrix ? n.matrix
                                        : glm::translate(glm::mat4(1.0f), t[i]) * glm::mat4_cast(r[i]) *
                                              glm::scale(glm::mat4(1.0f), s[i]);
    // Parents come first, so world[parent] is ready; a malformed parent index falls back to the root.
    world[i] = (n.parent >= 0 && std::size_t(n.parent) < i) ? world[std::size_t(n.parent)] * local : local;
  }
  return world;
}

void SceneAnimation::apply(std::size_t clip, float seconds, Scene& scene) const {
  const std::vector<glm::mat4> world = evaluate(clip, seconds);
  for (const AnimBinding& b : bindings)
    if (b.instance < scene.instances.size() && b.node < world.size())
      scene.instances[b.instance].worldFromObject = world[b.node] * b.nodeFromObject;
}

namespace gltf {

glm::mat4 nodeLocalMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::mat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(n.matrix[std::size_t(c * 4 + r)]);  // column-major
    return m;
  }
  glm::mat4 m(1.0f);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
  if (n.rotation.size() == 4)
    m *= glm::mat4_cast(glm::normalize(glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                                                 float(n.rotation[2]))));
  if (n.scale.size() == 3) m = glm::scale(m, glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
  return m;
}

namespace {

// The channel's target and sampler, checked before anything is read: nullopt for a channel to skip
// (with a warning, unless glTF says to ignore it).
std::optional<AnimChannel> channelTarget(const tinygltf::Model& m, const tinygltf::Animation& a,
                                         const tinygltf::AnimationChannel& c, const std::string& id,
                                         const std::vector<int>& animIndexOfNode, const SceneAnimation& anim,
                                         Warn& warn) {
  if (c.target_node < 0) return std::nullopt;  // glTF: a channel without a node is ignored
  if (c.target_path == "weights") {
    warn(id + ": morph-target weights are not animated (morph targets are ignored)");
    return std::nullopt;
  }
  AnimChannel out;
  if (c.target_path == "translation") out.path = AnimPath::Translation;
  else if (c.target_path == "rotation") out.path = AnimPath::Rotation;
  else if (c.target_path == "scale") out.path = AnimPath::Scale;
  else {
    warn(id + ": unknown path '" + c.target_path + "', channel skipped");
    return std::nullopt;
  }
  const int animNode = animIndexOfNode[std::size_t(c.target_node)];
  if (animNode < 0) return std::nullopt;  // node not in the loaded scene
  if (anim.nodes[std::size_t(animNode)].hasMatrix) {
    warn(id + ": targets node " + std::to_string(c.target_node) + ", which has a matrix; channel skipped");
    return std::nullopt;
  }
  out.node = std::uint32_t(animNode);
  const tinygltf::AnimationSampler& s = a.samplers[std::size_t(c.sampler)];
  out.interpolation = s.interpolation == "STEP"          ? AnimInterpolation::Step
                      : s.interpolation == "CUBICSPLINE" ? AnimInterpolation::CubicSpline
                                                         : AnimInterpolation::Linear;
  const tinygltf::Accessor& in = m.accessors[std::size_t(s.input)];
  const tinygltf::Accessor& ou = m.accessors[std::size_t(s.output)];
  if (in.type != TINYGLTF_TYPE_SCALAR || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    warn(id + ": input accessor is not SCALAR float; channel skipped");
    return std::nullopt;
  }
  const int want = out.path == AnimPath::Rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  if (ou.type != want || (ou.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !ou.normalized)) {
    warn(id + ": output accessor has the wrong type for " + c.target_path + "; channel skipped");
    return std::nullopt;
  }
  const std::size_t per = out.interpolation == AnimInterpolation::CubicSpline ? 3 : 1;
  if (ou.count != in.count * per) {
    warn(id + ": " + std::to_string(ou.count) + " output values for " + std::to_string(in.count) +
         " keys; channel skipped");
    return std::nullopt;
  }
  return out;
}

// The key times and values into `out`: false for a channel to skip (warned), an error when the budget
// refuses them.
Result<bool> readKeyframes(const tinygltf::Model& m, const tinygltf::AnimationSampler& s, const std::string& id,
                           AnimChannel& out, Warn& warn, const std::string& file, LoadBudget& budget) {
  const tinygltf::Accessor& ou = m.accessors[std::size_t(s.output)];
  // Many channels may share one sampler's accessors: each read is charged, so a small file cannot
  // make the keyframes a product of two counts.
  auto times = readFloats(m, s.input, file, &budget);
  if (!times) return times.error();
  auto values = readFloats(m, s.output, file, &budget);
  if (!values) return values.error();
  if (!budget.charge(ou.count * sizeof(glm::vec4)))
    return Error{file + ": " + budget.refusal(id + " keyframes", ou.count * sizeof(glm::vec4))};
  bool ok = true;
  for (std::size_t k = 0; k < times->size() && ok; ++k)
    ok = std::isfinite((*times)[k]) && (k == 0 || (*times)[k] > (*times)[k - 1]);
  if (!ok) {
    warn(id + ": key times are not finite and strictly increasing; channel skipped");
    return false;
  }
  const std::size_t nc = out.path == AnimPath::Rotation ? 4 : 3;
  out.values.resize(ou.count);
  for (std::size_t k = 0; k < ou.count && ok; ++k) {
    glm::vec4 v(0.0f);
    for (std::size_t j = 0; j < nc; ++j) v[int(j)] = (*values)[k * nc + j];
    ok = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
    out.values[k] = v;
  }
  if (!ok) {
    warn(id + ": a keyframe value is NaN or infinite; channel skipped");
    return false;
  }
  out.times = std::move(*times);
  return true;
}

}  // namespace

Result<void> buildAnimationClips(const tinygltf::Model& m, const std::vector<int>& animIndexOfNode, SceneAnimation& anim,
                                 Warn& warn, const std::string& file, LoadBudget& budget) {
  for (std::size_t ai = 0; ai < m.animations.size(); ++ai) {
    const tinygltf::Animation& a = m.animations[ai];
    AnimClip clip;
    clip.name = a.name.empty() ? "animation " + std::to_string(ai) : a.name;
    for (std::size_t ci = 0; ci < a.channels.size(); ++ci) {
      const tinygltf::AnimationChannel& c = a.channels[ci];
      const std::string id = "animations[" + std::to_string(ai) + "].channels[" + std::to_string(ci) + "]";
      std::optional<AnimChannel> out = channelTarget(m, a, c, id, animIndexOfNode, anim, warn);
      if (!out) continue;
      auto read = readKeyframes(m, a.samplers[std::size_t(c.sampler)], id, *out, warn, file, budget);
      if (!read) return read.error();
      if (!*read) continue;
      clip.duration = std::max(clip.duration, out->times.back());
      clip.channels.push_back(std::move(*out));
    }
    if (!clip.channels.empty()) anim.clips.push_back(std::move(clip));
  }
  return {};
}

}  // namespace gltf
}  // namespace tandem
