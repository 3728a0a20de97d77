// loadGltf: the hardened pipeline (GltfInternal.h) and the conversion of a validated model into a Scene.
// docs/gltf.md documents the material mapping, light units, defaults, limits and refusals.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <array>
#include <map>
#include <memory>
#include <new>
#include <optional>
#include <numbers>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "io/GltfImporter.h"
#include "tandem/Image.h"
#include "tandem/Log.h"

namespace tandem {

using namespace gltf;
namespace fs = std::filesystem;

void gltf::Warn::operator()(const std::string& message) {
  ++count;
  const std::string full = file + ": " + message;
  // A hostile file can ask for a warning per object; the log shows the first ones (the callback sees all).
  constexpr int kLogged = 100;
  if (count <= kLogged) logWarning(full);
  else if (count == kLogged + 1) logWarning(file + ": further warnings are not logged");
  if (options && options->onWarning) options->onWarning(full);
}

namespace gltf {

// ---- nodes ----

Result<std::vector<glm::mat4>> Importer::gpuInstances(const tinygltf::Node& n, std::size_t nodeIndex) {
  const tinygltf::Value* e = ext(n.extensions, "EXT_mesh_gpu_instancing");
  if (!e) return std::vector<glm::mat4>{glm::mat4(1.0f)};
  const std::string id = "nodes[" + std::to_string(nodeIndex) + "].EXT_mesh_gpu_instancing";
  if (!e->Has("attributes") || !e->Get("attributes").IsObject()) return err(id + ": no attributes");
  const tinygltf::Value& attrs = e->Get("attributes");
  std::size_t count = 0;
  std::vector<float> data[3];
  const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
  const int types[3] = {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4, TINYGLTF_TYPE_VEC3};
  for (int k = 0; k < 3; ++k) {
    if (!attrs.Has(names[k])) continue;
    const int a = intOf(attrs, names[k], -1);
    if (a < 0 || a >= int(m_.accessors.size()))
      return err(id + ": " + names[k] + " names accessor " + std::to_string(a) + ", which does not exist");
    const tinygltf::Accessor& acc = m_.accessors[std::size_t(a)];
    if (acc.type != types[k]) return err(id + ": " + names[k] + " accessor has the wrong type");
    if (count != 0 && acc.count != count) return err(id + ": attribute counts differ");
    count = acc.count;
    auto r = readFloats(m_, a, file_, &budget_);
    if (!r) return r.error();
    for (float v : *r)
      if (!std::isfinite(v)) return err(id + ": " + names[k] + " contains NaN or infinity");
    data[k] = std::move(*r);
  }
  if (count == 0) return err(id + ": no TRANSLATION, ROTATION or SCALE attribute");
  if (auto c = charge(id + " transforms", u64(count) * sizeof(glm::mat4)); !c) return c.error();
  std::vector<glm::mat4> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    glm::mat4 t(1.0f);
    if (!data[0].empty()) t = glm::translate(t, glm::vec3(data[0][3 * i], data[0][3 * i + 1], data[0][3 * i + 2]));
    if (!data[1].empty()) {
      glm::quat q(data[1][4 * i + 3], data[1][4 * i], data[1][4 * i + 1], data[1][4 * i + 2]);
      const float len = glm::length(q);
      t *= glm::mat4_cast(len > 1e-20f ? q / len : glm::quat(1, 0, 0, 0));
    }
    if (!data[2].empty()) t = glm::scale(t, glm::vec3(data[2][3 * i], data[2][3 * i + 1], data[2][3 * i + 2]));
    out[i] = t;
  }
  return out;
}

void Importer::addCamera(const tinygltf::Node& n, const glm::mat4& world) {
  const tinygltf::Camera& c = m_.cameras[std::size_t(n.camera)];
  const std::string id = "cameras[" + std::to_string(n.camera) + "]";
  Camera cam;
  if (c.type == "perspective") {
    const auto& p = c.perspective;
    if (!(p.yfov > 0.0 && p.yfov < 3.14159) || !(p.znear > 0.0) || !std::isfinite(p.znear) ||
        !(p.zfar == 0.0 || (std::isfinite(p.zfar) && p.zfar > p.znear)) || !(p.aspectRatio >= 0.0)) {
      warn_(id + ": invalid perspective parameters (need 0 < yfov < π, znear > 0, zfar > znear); camera skipped");
      return;
    }
    cam.yFovDeg = float(glm::degrees(p.yfov));
    cam.nearZ = float(p.znear);
    cam.farZ = p.zfar == 0.0 ? std::numeric_limits<float>::infinity() : float(p.zfar);
  } else {
    const auto& o = c.orthographic;
    if (!(std::abs(o.ymag) > 0.0) || !std::isfinite(o.ymag) || !(std::abs(o.xmag) > 0.0) || !(o.znear >= 0.0) ||
        !std::isfinite(o.zfar) || !(o.zfar > o.znear)) {
      warn_(id + ": invalid orthographic parameters (need xmag, ymag ≠ 0, zfar > znear >= 0); camera skipped");
      return;
    }
    cam.orthographic = true;
    cam.orthoHeight = float(2.0 * std::abs(o.ymag));
    cam.nearZ = std::max(float(o.znear), 1e-4f);  // the engine's projections need near > 0
    cam.farZ = float(o.zfar);
  }
  // glTF cameras look down their local −Z with +Y up.
  const glm::vec3 pos(world[3]);
  const glm::vec3 fwd = glm::mat3(world) * glm::vec3(0, 0, -1);
  const glm::vec3 up = glm::mat3(world) * glm::vec3(0, 1, 0);
  if (!finite3(pos) || !(glm::length(fwd) > 1e-12f) || !(glm::length(up) > 1e-12f) ||
      !(glm::length(glm::cross(fwd, up)) > 1e-12f)) {
    warn_(id + ": its node's transform is degenerate; camera skipped");
    return;
  }
  cam.posW = pos;
  cam.targetW = pos + glm::normalize(fwd);
  cam.upW = glm::normalize(up);
  out_.scene.camera = cam;
  haveCamera_ = true;
}

void Importer::addLight(const tinygltf::Node& n, std::size_t nodeIndex, const glm::mat4& world) {
  const tinygltf::Value* e = ext(n.extensions, "KHR_lights_punctual");
  if (!e) return;
  const std::string id = "nodes[" + std::to_string(nodeIndex) + "].KHR_lights_punctual";
  const int li = intOf(*e, "light", -1);
  if (li < 0 || li >= int(m_.lights.size())) {
    warn_(id + ": light " + std::to_string(li) + " does not exist; light skipped");
    return;
  }
  const tinygltf::Light& g = m_.lights[std::size_t(li)];
  const std::string lid = "KHR_lights_punctual.lights[" + std::to_string(li) + "]";
  Light l;
  l.name = g.name;
  if (g.type == "point") l.type = LightType::Point;
  else if (g.type == "spot") l.type = LightType::Spot;
  else if (g.type == "directional") l.type = LightType::Directional;
  else {
    warn_(lid + ": unknown type '" + g.type + "'; light skipped");
    return;
  }
  if (!g.color.empty()) {
    if (g.color.size() != 3) {
      warn_(lid + ": color needs 3 numbers; light skipped");
      return;
    }
    l.color = glm::vec3(float(g.color[0]), float(g.color[1]), float(g.color[2]));
  }
  if (!finite3(l.color) || l.color.x < 0 || l.color.y < 0 || l.color.z < 0 || !std::isfinite(g.intensity) ||
      g.intensity < 0 || !std::isfinite(g.range) || g.range < 0) {
    warn_(lid + ": negative or non-finite colour, intensity or range; light skipped");
    return;
  }
  // Units (docs/gltf.md): point/spot intensity in candela with inverse-square falloff, directional in lux.
  // glTF's diffuse BRDF is albedo/π, the engine's Phong term kd·E·(N·L) has no 1/π: dividing the
  // intensity by π makes a Lambertian surface as bright as in glTF viewers at exposure 1.
  l.intensity = float(g.intensity / std::numbers::pi);
  l.range = float(g.range);
  l.attenuation = l.type == LightType::Directional ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
  if (l.type == LightType::Spot) {
    const double inner = g.spot.innerConeAngle, outer = g.spot.outerConeAngle;
    if (!(inner >= 0.0) || !(outer > inner) || !(outer <= 1.5707964)) {
      warn_(lid + ": spot cone needs 0 <= inner < outer <= π/2; light skipped");
      return;
    }
    l.innerConeDeg = float(glm::degrees(inner));
    l.outerConeDeg = float(glm::degrees(outer));
  }
  l.posW = glm::vec3(world[3]);
  const glm::vec3 dir = glm::mat3(world) * glm::vec3(0, 0, -1);  // lights shine down their local −Z
  if (!finite3(l.posW) || !(glm::length(dir) > 1e-12f)) {
    warn_(lid + ": its node's transform is degenerate; light skipped");
    return;
  }
  l.dirW = glm::normalize(dir);
  if (out_.scene.directLights().size() >= std::size_t(kMaxLights)) {
    warn_(lid + ": more than " + std::to_string(kMaxLights) + " lights; light skipped");
    return;
  }
  out_.scene.lights.push_back(std::move(l));
}

// Instances are a product (nodes × primitives × GPU instances). Counted over the tree first, charged and
// reserved at once, so the vector never doubles past what the budget allowed.
Result<void> Importer::reserveInstances(const std::vector<int>& roots, bool animating) {
  u64 planned = 0;
  std::vector<int> walk(roots.begin(), roots.end());
  while (!walk.empty()) {
    const tinygltf::Node& n = m_.nodes[std::size_t(walk.back())];
    walk.pop_back();
    if (n.mesh >= 0) {
      u64 copies = 1;
      if (const tinygltf::Value* e = ext(n.extensions, "EXT_mesh_gpu_instancing"); e && e->Has("attributes"))
        for (const char* a : {"TRANSLATION", "ROTATION", "SCALE"}) {
          const int ai = intOf(e->Get("attributes"), a, -1);
          if (ai >= 0 && ai < int(m_.accessors.size())) copies = std::max<u64>(copies, m_.accessors[std::size_t(ai)].count);
        }
      planned += copies * m_.meshes[std::size_t(n.mesh)].primitives.size();
    }
    walk.insert(walk.end(), n.children.begin(), n.children.end());
  }
  const u64 each = sizeof(Instance) + (animating ? sizeof(AnimBinding) : 0);
  if (planned > (~u64(0)) / each) return err("the scene's instances overflow a 64-bit count");
  if (auto c = charge(std::to_string(planned) + " instances (nodes × primitives × GPU instances)", planned * each); !c)
    return c.error();
  out_.scene.instances.reserve(std::size_t(planned));
  if (animating) out_.animation.bindings.reserve(std::size_t(planned));
  return {};
}

// The instances of node `ni`'s mesh: one per primitive and GPU instance, skipping singular static
// transforms (they draw nothing and would give NaN normals).
Result<void> Importer::addMeshInstances(const tinygltf::Node& n, std::size_t ni, const glm::mat4& world, bool dynamic,
                                        int animIndex) {
  auto xf = gpuInstances(n, ni);
  if (!xf) return xf.error();
  const tinygltf::Mesh& mesh = m_.meshes[std::size_t(n.mesh)];
  for (const glm::mat4& x : *xf) {
    const glm::mat4 w = world * x;
    const float det = glm::determinant(glm::mat3(w));
    if (!finiteMat(w) || (!dynamic && !(std::abs(det) > 1e-30f))) {
      // A singular static transform (zero scale) draws nothing and would give NaN normals.
      warnOnce("singular" + std::to_string(ni), "nodes[" + std::to_string(ni) + "]: singular or non-finite transform; its mesh is skipped");
      continue;
    }
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      auto mi = meshFor(n.mesh, int(p), det < 0.0f);
      if (!mi) return mi.error();
      if (*mi < 0) continue;
      triangles_ += out_.scene.meshes[std::size_t(*mi)].triangleCount();
      if (triangles_ > opt_.limits.maxTriangles)
        return err("more than the cap maxTriangles = " + std::to_string(opt_.limits.maxTriangles) + " triangles");
      const int gm = mesh.primitives[p].material;
      if (gm < 0 && defaultMaterial_ < 0) {
        // glTF's default material: white, fully rough dielectric, single-sided.
        Material d;
        d.name = "default";
        d.doubleSided = false;
        d.kd = d.ka = glm::vec3(1.0f);
        d.ks = glm::vec3(0.04f);
        d.ns = 1.0f;
        defaultMaterial_ = int(out_.scene.materials.size());
        out_.scene.materials.push_back(std::move(d));
      }
      Instance inst;
      inst.name = n.name.empty() ? "node " + std::to_string(ni) : n.name;
      // The instance itself was charged by reserveInstances; a name too long for the string's own storage is extra.
      if (inst.name.size() > 15)
        if (auto c = charge("nodes[" + std::to_string(ni) + "] instance names", inst.name.size()); !c) return c.error();
      inst.mesh = std::uint32_t(*mi);
      inst.material = std::uint32_t(gm < 0 ? defaultMaterial_ : materialOf_[std::size_t(gm)]);
      // A skinned mesh is drawn unposed (skins are ignored): which way its faces turn is not the author's,
      // so it shows both sides rather than none (the asset generator's skinned planes face away unposed).
      if (n.skin >= 0) inst.material = unposedMaterial(inst.material);
      inst.worldFromObject = w;
      inst.dynamic = dynamic;
      if (dynamic && animIndex >= 0)
        out_.animation.bindings.push_back({std::uint32_t(out_.scene.instances.size()), std::uint32_t(animIndex), x});
      out_.scene.instances.push_back(std::move(inst));
    }
  }
  return {};
}

Result<void> Importer::traverse(const std::vector<int>& roots) {
  struct Item {
    int node;
    int parentAnim;
    bool dynamic;
    glm::mat4 parentWorld;
  };
  const bool animating = !m_.animations.empty();
  animIndexOfNode_.assign(m_.nodes.size(), -1);
  if (auto r = reserveInstances(roots, animating); !r) return r;
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, false, glm::mat4(1.0f)});
  // Iterative depth-first walk (validateModel proved the graph a forest), so a 100 000-deep chain needs
  // no call stack.
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    const std::size_t ni = std::size_t(item.node);
    const tinygltf::Node& n = m_.nodes[ni];
    const glm::mat4 local = nodeLocalMatrix(n);
    const glm::mat4 world = item.parentWorld * local;
    const bool dynamic = item.dynamic || animated_[ni];
    int animIndex = -1;
    if (animating) {
      AnimNode an;
      an.parent = item.parentAnim;
      if (n.matrix.size() == 16) {
        an.hasMatrix = true;
        an.matrix = local;
      } else {
        if (n.translation.size() == 3) an.translation = glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
        if (n.rotation.size() == 4)
          an.rotation = glm::normalize(glm::quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])));
        if (n.scale.size() == 3) an.scale = glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
      }
      animIndex = int(out_.animation.nodes.size());
      animIndexOfNode_[ni] = animIndex;
      out_.animation.nodes.push_back(an);
    }
    if (n.skin >= 0) warnOnce("skin", "skins are ignored; skinned meshes are drawn unposed with their node transform");
    if (n.camera >= 0 && !haveCamera_) addCamera(n, world);
    addLight(n, ni, world);
    if (n.mesh >= 0)
      if (auto r = addMeshInstances(n, ni, world, dynamic, animIndex); !r) return r;
    for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, animIndex, dynamic, world});
  }
  return {};
}

void Importer::addDefaults() {
  Scene& s = out_.scene;
  if (!haveCamera_ && opt_.addDefaultCamera) {
    // Frame the world bounds of every instance from the glTF "front" (+Z), slightly above.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Instance& inst : s.instances)
      for (const glm::vec3& p : s.meshes[inst.mesh].positions) {
        const glm::vec3 w(inst.worldFromObject * glm::vec4(p, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
    Camera cam;
    if (!s.instances.empty() && finite3(lo) && finite3(hi) && lo.x <= hi.x) {
      const glm::vec3 c = (lo + hi) * 0.5f;
      const float r = std::max(glm::length(hi - lo) * 0.5f, 1e-3f);
      const float d = r / std::sin(glm::radians(cam.yFovDeg) * 0.5f) * 1.1f;
      cam.posW = c + glm::normalize(glm::vec3(0.0f, 0.25f, 1.0f)) * d;
      cam.targetW = c;
      cam.nearZ = std::max(r * 1e-3f, 1e-5f);
    }
    s.camera = cam;
  }
  // glTF has no environment, and every glTF viewer lights a file with one: the default sky (docs/environment.md),
  // which escaped rays see and whose light is the ambient term (a metal has something to reflect, faces turned
  // from the lights are not black). The background colour is what a scene without the sky would show.
  s.background = glm::vec3(0.05f);
  s.environment.kind = Environment::Kind::Sky;
  if (s.lights.empty() && opt_.addDefaultLights) {
    // A headlight along the view direction: every visible surface facing the camera is lit.
    Light head;
    head.name = "default headlight";
    head.type = LightType::Directional;
    head.intensity = 1.0f;
    head.attenuation = glm::vec3(1, 0, 0);
    const glm::vec3 dir = s.camera.targetW - s.camera.posW;
    head.dirW = glm::length(dir) > 1e-12f ? glm::normalize(dir) : glm::vec3(0, 0, -1);
    head.castShadows = false;
    s.lights.push_back(std::move(head));
  }
}

std::uint32_t Importer::unposedMaterial(std::uint32_t material) {
  if (out_.scene.materials[material].doubleSided) return material;
  auto [it, fresh] = unposedCopy_.try_emplace(material, 0u);
  if (fresh) {
    Material copy = out_.scene.materials[material];
    copy.doubleSided = true;
    copy.name += " (unposed skin: both sides)";
    it->second = std::uint32_t(out_.scene.materials.size());
    out_.scene.materials.push_back(std::move(copy));
  }
  return it->second;
}

Result<GltfAsset> Importer::run() {
  if (m_.scenes.empty() && opt_.sceneIndex >= 0) return err("scene " + std::to_string(opt_.sceneIndex) + " does not exist (the file has no scenes)");
  if (opt_.sceneIndex >= int(m_.scenes.size())) return err("scene " + std::to_string(opt_.sceneIndex) + " does not exist (the file has " + std::to_string(m_.scenes.size()) + ")");
  std::vector<int> roots;
  if (!m_.scenes.empty()) {
    const int si = opt_.sceneIndex >= 0 ? opt_.sceneIndex : std::max(m_.defaultScene, 0);
    roots = m_.scenes[std::size_t(si)].nodes;
    out_.scene.name = m_.scenes[std::size_t(si)].name;
  } else {
    // No scene: glTF leaves rendering to the application; we show every root node.
    std::vector<bool> child(m_.nodes.size(), false);
    for (const auto& n : m_.nodes)
      for (int c : n.children) child[std::size_t(c)] = true;
    for (std::size_t i = 0; i < m_.nodes.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  if (out_.scene.name.empty()) out_.scene.name = fs::path(file_).stem().string();
  animated_.assign(m_.nodes.size(), false);
  for (const auto& a : m_.animations)
    for (const auto& c : a.channels)
      if (c.target_node >= 0 && (c.target_path == "translation" || c.target_path == "rotation" || c.target_path == "scale"))
        animated_[std::size_t(c.target_node)] = true;
  if (auto r = buildMaterials(); !r) return r.error();
  if (auto r = traverse(roots); !r) return r.error();
  applyFactorMaps();
  if (!m_.animations.empty())
    if (auto r = buildAnimationClips(m_, animIndexOfNode_, out_.animation, warn_, file_, budget_); !r) return r.error();
  if (out_.animation.clips.empty()) out_.animation = SceneAnimation{};
  if (out_.scene.instances.empty()) warn_("the scene has nothing to draw");
  addDefaults();
  if (auto r = validateScene(out_.scene); !r) return err("imported scene failed validation: " + r.error().message);
  return std::move(out_);
}

}  // namespace gltf

namespace {

Result<GltfAsset> loadImpl(const std::string& path, const GltfOptions& opt) {
  // Messages name the file as the caller gave it, as the scene file's do.
  const std::string& file = path;
  std::error_code ec;
  const fs::path canon = fs::canonical(fs::path(path), ec);
  if (ec) return Error{file + ": cannot open: " + ec.message()};
  // The main file gets the same treatment as every file it names.
  auto bytes = readFileCapped(canon, opt.limits.maxFileBytes, &opt.onFileOpened);
  if (!bytes) return Error{file + ": " + bytes.error().message};
  if (bytes->empty()) return Error{file + ": empty file"};
  if (bytes->size() > std::size_t(UINT32_MAX)) return Error{file + ": larger than tinygltf can take (4 GiB)"};

  Confinement conf;
  conf.root = canon.parent_path();
  conf.rootPrefix = conf.root.string();
  if (conf.rootPrefix.empty() || conf.rootPrefix.back() != '/') conf.rootPrefix += '/';
  conf.maxFileBytes = opt.limits.maxFileBytes;
  conf.onFileOpened = &opt.onFileOpened;
  // tinygltf joins baseDir and uri with '/', so the root without its trailing slash (except "/").
  const std::string baseDir = conf.root.string();

  const bool glb = bytes->size() >= 4 && std::memcmp(bytes->data(), "glTF", 4) == 0;
  std::size_t jsonOffset = 0, jsonSize = bytes->size();
  if (glb)
    if (auto r = checkGlb(*bytes, &jsonOffset, &jsonSize); !r) return Error{file + ": " + r.error().message};
  if (auto r = checkJsonDepth(bytes->data() + jsonOffset, jsonSize, opt.limits.maxJsonDepth); !r)
    return Error{file + ": " + r.error().message};
  LoadBudget budget(opt.limits.budgetBaseBytes, opt.limits.budgetBytesPerInputByte);
  budget.addInput(bytes->size());
  auto scan = prescanJson(bytes->data() + jsonOffset, jsonSize, glb);
  if (!scan) return Error{file + ": " + scan.error().message};
  // The model tinygltf will build is charged before it is built: a file of many tiny objects ("{}" is a
  // 2 KB tinygltf::Material) is refused here instead of after the parser has allocated them.
  if (!budget.charge(scan->modelEstimate))
    return Error{file + ": " + budget.refusal("the parsed model (estimated before parsing)", scan->modelEstimate)};
  conf.budget = &budget;

  tinygltf::Model model;
  DeferredImages images;
  std::string err, warn;
  bool ok = false;
  try {
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(makeFsCallbacks(&conf));
    loader.SetImageLoader(&recordImage, &images);
    if (glb)
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes->data(), static_cast<unsigned>(bytes->size()), baseDir);
    else
      ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes->data()),
                                      static_cast<unsigned>(bytes->size()), baseDir);
  } catch (const std::bad_alloc&) {
    return Error{file + ": out of memory while parsing (tinygltf threw std::bad_alloc)"};
  } catch (const std::exception& e) {
    return Error{file + ": parse failed (tinygltf threw: " + e.what() + ")"};
  } catch (...) {
    return Error{file + ": parse failed (tinygltf threw an unknown exception)"};
  }
  // A refused file (escape, non-regular, oversized) rejects the load whatever tinygltf made of it.
  if (!conf.refusals.empty()) return Error{file + ": " + conf.refusals.front()};
  auto trim = [](std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& ch : s)
      if (ch == '\n') ch = ';';
    return s;
  };
  if (!ok) return Error{file + ": " + (err.empty() ? std::string("tinygltf failed without a message") : trim(err))};

  Warn w{file, &opt, 0};
  if (!warn.empty()) w(trim(warn));
  if (auto r = validateModel(model, opt.limits, file); !r) return r.error();
  Importer imp(model, opt, file, w, images, budget);
  auto asset = imp.run();
  if (!asset) return asset.error();
  asset->stats.inputBytes = budget.inputBytes();
  asset->stats.modelEstimate = scan->modelEstimate;
  asset->stats.decodedBytes = budget.used() - scan->modelEstimate;
  asset->stats.budgetBytes = budget.limit();
  return asset;
}

}  // namespace

Result<GltfAsset> loadGltfAsset(const std::string& path, const GltfOptions& options) {
  // Everything the loader allocates is sized by validated data, but a hostile file can still ask for a
  // lot within the caps: running out of memory fails this load, not the process.
  try {
    return loadImpl(path, options);
  } catch (const std::bad_alloc&) {
    return Error{path + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

Result<Scene> loadGltf(const std::string& path, const GltfOptions& options) {
  auto r = loadGltfAsset(path, options);
  if (!r) return r.error();
  return std::move(r->scene);
}

}  // namespace tandem
