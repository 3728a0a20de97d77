// The JSON scene format (docs/scene-format.md).
//
// Scene files are written by hand, so the reader is strict: every key is checked against the keys its
// object allows (a typo is an error, not a silently ignored setting), every number against its range,
// and every error names the file, the JSON pointer of the offending value and the reason. Internally a
// failure throws SceneFileError, which the public functions turn into Result errors: nothing escapes.
#include "tandem/SceneFile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/Embedded.h"
#include "core/Solids.h"
#include "io/LoadBudget.h"
#include "io/SceneJson.h"
#include "tandem/Gltf.h"
#include "tandem/Image.h"
#include "tandem/Log.h"
#include "tandem/Primitives.h"
#include "tandem/Settings.h"

namespace tandem {

namespace {

namespace fs = std::filesystem;

// Limits against absurd input: a hand-written scene never comes near them, a corrupted or hostile one
// must fail with a message instead of exhausting memory.
constexpr std::uintmax_t kMaxFileBytes = 64ull << 20;
constexpr int kMaxTessellation = 4096;                     // sphere segments/rings, plane divisions
constexpr std::uint64_t kMaxPrimitiveTriangles = 4u << 20;  // one built-in mesh
constexpr std::uint64_t kMaxSceneTriangles = 20'000'000;     // all meshes together (the glTF limit)
constexpr std::size_t kMaxToonSteps = 64;
constexpr int kMaxImageSide = 16384;
constexpr int kMaxDepthLimit = 64;
// The resource contract (docs/scene-format.md, "Resources"), the glTF loader's defaults.
constexpr std::uint64_t kBudgetBaseBytes = GltfLimits{}.budgetBaseBytes;
constexpr std::uint64_t kBudgetBytesPerInputByte = GltfLimits{}.budgetBytesPerInputByte;

using namespace scenefile;

// ---------------------------------------------------------------------------------------------------
// Mesh helpers for glTF-sourced meshes.

/// Appends `src`, transformed by `m`, to `dst`. Attributes survive only when every part has them
/// (the caller clears the flags); a mirroring transform swaps the winding back to counter-clockwise.
struct MergeAttributes {
  bool normals = true, uvs = true, tangents = true, colors = true;
};

void appendTransformed(Mesh& dst, const Mesh& src, const glm::mat4& m, const MergeAttributes& keep) {
  const auto base = static_cast<std::uint32_t>(dst.positions.size());
  const glm::mat3 linear(m);
  const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
  const bool mirrored = glm::determinant(linear) < 0.0f;
  for (const glm::vec3& p : src.positions) dst.positions.push_back(glm::vec3(m * glm::vec4(p, 1.0f)));
  if (keep.normals)
    for (const glm::vec3& n : src.normals) {
      glm::vec3 t = normalMatrix * n;
      float len = glm::length(t);
      dst.normals.push_back(len > 0.0f ? t / len : glm::vec3(0, 1, 0));
    }
  if (keep.uvs) dst.uvs.insert(dst.uvs.end(), src.uvs.begin(), src.uvs.end());
  if (keep.tangents)
    for (const glm::vec4& t : src.tangents) {
      glm::vec3 v = linear * glm::vec3(t);
      float len = glm::length(v);
      dst.tangents.push_back(glm::vec4(len > 0.0f ? v / len : glm::vec3(1, 0, 0), mirrored ? -t.w : t.w));
    }
  if (keep.colors) dst.colors.insert(dst.colors.end(), src.colors.begin(), src.colors.end());
  for (std::size_t i = 0; i + 2 < src.indices.size(); i += 3) {
    std::uint32_t a = src.indices[i] + base, b = src.indices[i + 1] + base, c = src.indices[i + 2] + base;
    if (mirrored) std::swap(b, c);
    dst.indices.insert(dst.indices.end(), {a, b, c});
  }
}

// ---------------------------------------------------------------------------------------------------
// The builder: JSON → Scene.

// A glTF file loaded for this scene, and where its data went the first time it was placed: every placement
// of one file shares its meshes, textures and material copies, so placing a file N times costs N instances,
// not N copies of the file.
struct Placed {
  Scene scene;
  bool placed = false;
  std::uint32_t meshBase = 0;
  int textureBase = 0;
  std::vector<std::int64_t> materialCopy;  // glTF material → this scene's copy, −1 until one is needed
};

class Builder {
 public:
  Builder(Reader reader, std::optional<std::string> baseDir, std::size_t textBytes)
      : r_(std::move(reader)), baseDir_(std::move(baseDir)) {
    budget_.addInput(textBytes);
  }

  Scene build(const Json& root, const std::string& defaultName) {
    r_.object(root, "");
    r_.checkKeys(root, "", {"name", "meshes", "materials", "lights", "instances", "camera", "background", "environment",
                            "render"});
    scene_.name = defaultName;
    if (const Json* j = Reader::find(root, "name")) scene_.name = r_.nonEmptyString(*j, "/name");
    if (const Json* j = Reader::find(root, "meshes")) meshes(*j, "/meshes");
    if (const Json* j = Reader::find(root, "materials")) materials(*j, "/materials");
    if (const Json* j = Reader::find(root, "lights")) lights(*j, "/lights");
    if (const Json* j = Reader::find(root, "instances")) instances(*j, "/instances");
    checkLightCount();
    checkTriangleBudget();
    if (const Json* j = Reader::find(root, "camera")) camera(*j, "/camera");
    if (const Json* j = Reader::find(root, "background")) scene_.background = r_.color(*j, "/background");
    if (const Json* j = Reader::find(root, "environment")) environment(*j, "/environment");
    if (const Json* j = Reader::find(root, "render")) render(*j, "/render");
    return std::move(scene_);
  }

 private:
  // ---- meshes ----
  void meshes(const Json& j, const std::string& path) {
    r_.object(j, path);
    for (const auto& [name, value] : j.items()) {
      const std::string p = child(path, name);
      if (name.empty()) r_.fail(p, "mesh names must not be empty");
      r_.object(value, p);
      const Json* prim = Reader::find(value, "primitive");
      const Json* gltf = Reader::find(value, "gltf");
      const Json* csg = Reader::find(value, "csg");
      if ((prim ? 1 : 0) + (gltf ? 1 : 0) + (csg ? 1 : 0) > 1)
        r_.fail(p, "a mesh has one of 'primitive', 'gltf' or 'csg', not several");
      if (!prim && !gltf && !csg) r_.fail(p, "missing required key 'primitive', 'gltf' or 'csg'");
      Mesh mesh = prim ? primitive(value, p) : csg ? exactMesh(value, p) : gltfMesh(value, p);
      mesh.name = name;
      meshIndex_[name] = static_cast<std::uint32_t>(scene_.meshes.size());
      meshNames_.push_back(name);
      scene_.meshes.push_back(std::move(mesh));
    }
  }

  Mesh primitive(const Json& j, const std::string& path) {
    const std::string type = r_.string(j.at("primitive"), child(path, "primitive"));
    // The exact-only shapes: a solid with its bounding box as the raster's proxy (docs/csg.md).
    if (type == "cylinder" || type == "cone" || type == "torus") return exactMesh(j, path);
    if (type == "sphere") {
      r_.checkKeys(j, path, {"primitive", "radius", "segments", "rings", "exact"}, "a sphere");
      float radius = 1.0f;
      int segments = 64, rings = 32;
      if (const Json* v = Reader::find(j, "radius")) radius = r_.number(*v, child(path, "radius"), kPositive);
      if (const Json* v = Reader::find(j, "segments")) segments = r_.integer(*v, child(path, "segments"), 3, kMaxTessellation);
      if (const Json* v = Reader::find(j, "rings")) rings = r_.integer(*v, child(path, "rings"), 2, kMaxTessellation);
      // The two pole rows have one triangle per segment, the others two.
      const std::uint64_t triangles = std::uint64_t(segments) * std::uint64_t(2 * rings - 2);
      checkPrimitiveTriangles(triangles, path);
      chargeMesh(path, std::uint64_t(segments + 1) * std::uint64_t(rings + 1), triangles);
      if (!isExact(j, path)) return makeSphere(radius, segments, rings);
      // The proxy circumscribes the sphere (its faces lie outside it), so it covers every pixel the sphere
      // does; the rays see the sphere itself.
      const double pi = 3.14159265358979323846;
      const double outward = 1.0 / (std::cos(pi / segments) * std::cos(pi / (2.0 * rings)));
      Mesh mesh = makeSphere(static_cast<float>(radius * outward * (1.0 + 1e-6)), segments, rings);
      mesh.exact = leafSolid({solid::Shape::Sphere, glm::dvec3(radius)});
      return mesh;
    }
    if (type == "box") {
      r_.checkKeys(j, path, {"primitive", "size", "exact"}, "a box");
      glm::vec3 size(1.0f);
      if (const Json* v = Reader::find(j, "size")) size = r_.vec3(*v, child(path, "size"), kPositive, true);
      Mesh mesh = makeBox(size);
      if (isExact(j, path)) mesh.exact = leafSolid({solid::Shape::Box, 0.5 * glm::dvec3(size)});
      return mesh;
    }
    if (type == "plane") {
      r_.checkKeys(j, path, {"primitive", "size", "divisions"}, "a plane");
      glm::vec2 size(10.0f);
      int divisions = 1;
      if (const Json* v = Reader::find(j, "size")) {
        const std::string p = child(path, "size");
        if (v->is_number()) {
          size = glm::vec2(r_.number(*v, p, kPositive));
        } else {
          if (!v->is_array() || v->size() != 2) r_.fail(p, "expected [x, z] or a number, got " + Reader::describe(*v));
          size = {r_.number((*v)[0], child(p, 0), kPositive), r_.number((*v)[1], child(p, 1), kPositive)};
        }
      }
      if (const Json* v = Reader::find(j, "divisions")) divisions = r_.integer(*v, child(path, "divisions"), 1, kMaxTessellation);
      checkPrimitiveTriangles(2ull * std::uint64_t(divisions) * std::uint64_t(divisions), path);
      chargeMesh(path, std::uint64_t(divisions + 1) * std::uint64_t(divisions + 1), 2ull * std::uint64_t(divisions) * std::uint64_t(divisions));
      return makePlane(size, divisions);
    }
    r_.fail(child(path, "primitive"),
            "unknown primitive '" + type + "' (known: sphere, box, plane; exact only: cylinder, cone, torus)");
  }

  // ---- exact solids and CSG (docs/csg.md) ----
  bool isExact(const Json& j, const std::string& path) const {
    const Json* v = Reader::find(j, "exact");
    return v && r_.boolean(*v, child(path, "exact"));
  }

  static solid::Solid leafSolid(const solid::Primitive& p) {
    solid::Solid s;
    solid::Node n;
    n.primitive = p;
    s.nodes.push_back(n);
    return s;
  }

  /// A mesh that is an exact solid: a CSG tree ("csg") or one exact-only primitive, with a tessellation that
  /// encloses it as the raster's proxy (makeSolidProxy).
  Mesh exactMesh(const Json& j, const std::string& path) {
    solid::Solid s;
    s.root = solidNode(j, path, s, 1);
    // The tree and its proxy are charged to the load's budget like any mesh (a few bytes of JSON per node; the
    // proxy at most a tessellated shape per leaf, which the node limit bounds).
    charge(path, "the solid", s.nodes.size() * sizeof(solid::Node));
    if (const std::string bad = solid::validate(s); !bad.empty()) r_.fail(path, "the solid is not valid: " + bad);
    const solid::Bounds b = solid::bounds(s);
    const glm::dvec3 size = b.hi - b.lo;
    for (int a = 0; a < 3; ++a)
      if (!(size[a] > 0.0) || !(size[a] < 1e15))
        r_.fail(path, "the solid is unbounded (a 'plane' must be cut by the other operands of an intersection or difference)");
    chargeMesh(path, kProxyVertices * s.nodes.size(), kProxyTriangles * s.nodes.size());
    return makeSolidProxy(s);
  }
  // A leaf's proxy at makeSolidProxy's default 48 segments: at most (48 + 1) × 25 vertices and 48 × 48 triangles.
  static constexpr std::uint64_t kProxyVertices = 49 * 25, kProxyTriangles = 48 * 48;

  /// One node of a solid: {"csg": op, "of": [...]} or {"primitive": ...}, either with translate / rotate /
  /// scale (applied scale first, then rotate, then translate, as an instance's transform). Returns its index.
  std::uint32_t solidNode(const Json& j, const std::string& path, solid::Solid& s, int depth) {
    r_.object(j, path);
    if (depth > solid::kMaxCsgDepth) r_.fail(path, "CSG nested deeper than " + std::to_string(solid::kMaxCsgDepth));
    if (s.nodes.size() >= solid::kMaxCsgNodes)
      r_.fail(path, "more than " + std::to_string(solid::kMaxCsgNodes) + " CSG nodes in one solid");
    const auto index = static_cast<std::uint32_t>(s.nodes.size());
    s.nodes.emplace_back();
    solid::Node node;
    if (const Json* op = Reader::find(j, "csg")) {
      r_.checkKeys(j, path, {"csg", "of", "translate", "rotate", "scale"}, "a CSG node");
      const std::string name = r_.string(*op, child(path, "csg"));
      node.op = name == "union"          ? solid::Op::Union
                : name == "merge"        ? solid::Op::Merge
                : name == "intersection" ? solid::Op::Intersection
                : name == "difference"   ? solid::Op::Difference
                                         : solid::Op::Leaf;
      if (node.op == solid::Op::Leaf)
        r_.fail(child(path, "csg"), "unknown operation '" + name + "' (known: union, merge, intersection, difference)");
      const std::string ofPath = child(path, "of");
      const Json& of = r_.require(j, path, "of", "the operands");
      if (!of.is_array() || of.empty()) r_.fail(ofPath, "expected a non-empty array of operands, got " + Reader::describe(of));
      for (std::size_t k = 0; k < of.size(); ++k) node.children.push_back(solidNode(of[k], child(ofPath, k), s, depth + 1));
    } else if (const Json* prim = Reader::find(j, "primitive")) {
      const std::string type = r_.string(*prim, child(path, "primitive"));
      auto length = [&](const char* key, double fallback) {
        const Json* v = Reader::find(j, key);
        return v ? static_cast<double>(r_.number(*v, child(path, key), kPositive)) : fallback;
      };
      // Top-level exact-only primitives may carry "exact" (always true for them).
      const std::vector<std::string> placement{"primitive", "translate", "rotate", "scale", "exact"};
      auto keys = [&](std::vector<std::string> more) {
        more.insert(more.end(), placement.begin(), placement.end());
        const std::vector<std::string_view> allowed(more.begin(), more.end());
        r_.checkKeys(j, path, std::span<const std::string_view>(allowed), "an exact " + type);
      };
      if (type == "sphere") {
        keys({"radius"});
        node.primitive = {solid::Shape::Sphere, glm::dvec3(length("radius", 1.0))};
      } else if (type == "box") {
        keys({"size"});
        glm::vec3 size(1.0f);
        if (const Json* v = Reader::find(j, "size")) size = r_.vec3(*v, child(path, "size"), kPositive, true);
        node.primitive = {solid::Shape::Box, 0.5 * glm::dvec3(size)};
      } else if (type == "cylinder") {
        keys({"radius", "height"});
        node.primitive = {solid::Shape::Cylinder, {length("radius", 1.0), 0.5 * length("height", 1.0), 0.0}};
      } else if (type == "cone") {
        keys({"radius", "topRadius", "height"});
        double top = 0.0;
        if (const Json* v = Reader::find(j, "topRadius")) top = r_.number(*v, child(path, "topRadius"), Range{0.0, 1e30});
        node.primitive = {solid::Shape::Cone, {length("radius", 1.0), top, 0.5 * length("height", 1.0)}};
      } else if (type == "torus") {
        keys({"radius", "tube"});
        const double ring = length("radius", 1.0), tube = length("tube", 0.25);
        if (!(tube < ring)) r_.fail(child(path, "tube"), "must be less than the radius (a ring torus)");
        node.primitive = {solid::Shape::Torus, {ring, tube, 0.0}};
      } else if (type == "plane") {
        keys({});
        node.primitive = {solid::Shape::Plane, glm::dvec3(0.0)};
      } else {
        r_.fail(child(path, "primitive"), "unknown solid '" + type + "' (known: sphere, box, cylinder, cone, torus, plane)");
      }
    } else {
      r_.fail(path, "expected 'csg' (an operation) or 'primitive' (a solid)");
    }
    glm::mat4 m(1.0f);
    if (const Json* v = Reader::find(j, "translate")) m = glm::translate(m, r_.vec3(*v, child(path, "translate")));
    if (const Json* v = Reader::find(j, "rotate")) m = m * rotation(*v, child(path, "rotate"));
    if (const Json* v = Reader::find(j, "scale"))
      m = glm::scale(m, r_.vec3(*v, child(path, "scale"), Range{0.0, 1e6, true}, true));
    node.parentFromNode = glm::dmat4(m);
    s.nodes[index] = std::move(node);
    return index;
  }

  // Everything the file makes is charged to the load's budget before it is made (LoadBudget.h): a few
  // bytes of JSON can ask for millions of triangles, and a file placed many times for its copies.
  void charge(const std::string& path, const std::string& what, std::uint64_t bytes) {
    if (!budget_.charge(bytes)) r_.fail(path, budget_.refusal(what, bytes));
  }
  /// What a built-in mesh keeps per vertex (tandem/Primitives.h): a position, a normal and a uv.
  static constexpr std::uint64_t kPrimitiveVertexBytes = 2 * sizeof(glm::vec3) + sizeof(glm::vec2);
  /// Charges what the mesh will keep: its vertices' attributes and three indices a triangle.
  void chargeMesh(const std::string& path, std::uint64_t vertices, std::uint64_t triangles,
                  std::uint64_t vertexBytes = kPrimitiveVertexBytes) {
    charge(path, "the mesh", vertices * vertexBytes + triangles * 3 * sizeof(std::uint32_t));
  }

  void checkPrimitiveTriangles(std::uint64_t n, const std::string& path) const {
    if (n > kMaxPrimitiveTriangles)
      r_.fail(path, "tessellation gives " + std::to_string(n) + " triangles, more than the limit of " +
                        std::to_string(kMaxPrimitiveTriangles));
  }

  Mesh gltfMesh(const Json& j, const std::string& path) {
    r_.checkKeys(j, path, {"gltf", "mesh"}, "a glTF mesh");
    const Scene& g = loadGltfCached(j.at("gltf"), child(path, "gltf")).scene;
    std::vector<std::pair<const Mesh*, glm::mat4>> parts;
    if (const Json* sel = Reader::find(j, "mesh")) {
      // One named (or numbered) mesh of the file, in its own object space.
      const std::string p = child(path, "mesh");
      if (sel->is_string()) {
        const std::string want = sel->get<std::string>();
        for (const Mesh& m : g.meshes)
          if (m.name == want) parts.push_back({&m, glm::mat4(1.0f)});
        if (parts.empty()) {
          std::vector<std::string> known;
          for (const Mesh& m : g.meshes)
            if (std::find(known.begin(), known.end(), m.name) == known.end()) known.push_back(m.name);
          r_.fail(p, "no mesh named '" + want + "' in the glTF file (known: " + joinNames(known) + ")");
        }
      } else {
        if (g.meshes.empty()) r_.fail(p, "the glTF file has no meshes");
        const int i = r_.integer(*sel, p, 0, static_cast<int>(std::min<std::size_t>(g.meshes.size() - 1, 1u << 30)));
        parts.push_back({&g.meshes[static_cast<std::size_t>(i)], glm::mat4(1.0f)});
      }
    } else {
      // The whole file as it is placed by its nodes, flattened into one mesh.
      for (const Instance& inst : g.instances) parts.push_back({&g.meshes[inst.mesh], inst.worldFromObject});
      if (parts.empty()) r_.fail(child(path, "gltf"), "the glTF file places no meshes");
    }
    MergeAttributes keep;
    std::uint64_t vertices = 0, triangles = 0;
    for (const auto& [m, xf] : parts) {
      keep.normals = keep.normals && m->normals.size() == m->positions.size();
      keep.uvs = keep.uvs && m->uvs.size() == m->positions.size();
      keep.tangents = keep.tangents && m->tangents.size() == m->positions.size();
      keep.colors = keep.colors && m->colors.size() == m->positions.size();
      vertices += m->positions.size();
      triangles += m->triangleCount();
    }
    if (vertices >= std::numeric_limits<std::uint32_t>::max() || triangles > kMaxSceneTriangles)
      r_.fail(path, "the merged glTF mesh is too large (" + std::to_string(triangles) + " triangles)");
    chargeMesh(path, vertices, triangles,
               sizeof(glm::vec3) + (keep.normals ? sizeof(glm::vec3) : 0) + (keep.uvs ? sizeof(glm::vec2) : 0) +
                   (keep.tangents ? sizeof(glm::vec4) : 0) + (keep.colors ? sizeof(glm::vec4) : 0));
    Mesh out;
    for (const auto& [m, xf] : parts) appendTransformed(out, *m, xf, keep);
    return out;
  }

  std::string resolve(const Json& j, const std::string& path) const {
    const std::string rel = r_.nonEmptyString(j, path);
    fs::path p(rel);
    if (p.is_absolute()) return p.lexically_normal().string();
    if (!baseDir_)
      r_.fail(path, "cannot resolve the relative path '" + rel +
                        "': the embedded default scene has no folder (the repository's assets/scenes was not found)");
    return (fs::path(*baseDir_) / p).lexically_normal().string();
  }

  Placed& loadGltfCached(const Json& j, const std::string& path) {
    const std::string file = resolve(j, path);
    auto it = gltfCache_.find(file);
    if (it != gltfCache_.end()) return it->second;
    GltfOptions options;
    // The scene file decides lights and camera; the glTF loader's stand-ins would only get in the way.
    options.addDefaultLights = false;
    options.addDefaultCamera = false;
    Result<GltfAsset> g = loadGltfAsset(file, options);
    if (!g) r_.fail(path, "cannot load glTF '" + file + "': " + g.error().message);
    // The glTF file and what it read join this load's input; its own load kept to its own budget.
    budget_.addInput(g->stats.inputBytes);
    Placed placed;
    placed.scene = std::move(g->scene);
    return gltfCache_.emplace(file, std::move(placed)).first->second;
  }

  // ---- materials ----
  void materials(const Json& j, const std::string& path) {
    r_.object(j, path);
    for (const auto& [name, value] : j.items()) {
      const std::string p = child(path, name);
      if (name.empty()) r_.fail(p, "material names must not be empty");
      Material m = material(value, p);
      m.name = name;
      materialIndex_[name] = static_cast<std::uint32_t>(scene_.materials.size());
      materialNames_.push_back(name);
      scene_.materials.push_back(std::move(m));
    }
  }

  Material material(const Json& j, const std::string& path) const {
    r_.object(j, path);
    r_.checkKeys(j, path, {"ka", "kd", "ks", "ns", "kr", "kt", "ior", "roughness", "emission", "shading", "toonRamp", "checker",
                           "texture", "opacity", "alphaMode", "alphaCutoff", "doubleSided", "unlit"});
    Material m;
    auto opt = [&](std::string_view key) { return Reader::find(j, key); };
    if (const Json* v = opt("ka")) m.ka = r_.color(*v, child(path, "ka"));
    if (const Json* v = opt("kd")) m.kd = r_.color(*v, child(path, "kd"));
    if (const Json* v = opt("ks")) m.ks = r_.color(*v, child(path, "ks"));
    if (const Json* v = opt("ns")) m.ns = r_.number(*v, child(path, "ns"), Range{0.0, 10000.0});
    if (const Json* v = opt("kr")) m.kr = r_.number(*v, child(path, "kr"), kUnit);
    if (const Json* v = opt("kt")) m.kt = r_.number(*v, child(path, "kt"), kUnit);
    if (const Json* v = opt("ior")) m.ior = r_.number(*v, child(path, "ior"), Range{0.0, 10.0, true});
    if (const Json* v = opt("roughness")) m.roughness = r_.number(*v, child(path, "roughness"), kUnit);
    if (const Json* v = opt("emission")) m.emission = r_.color(*v, child(path, "emission"));
    if (const Json* v = opt("shading")) {
      const std::string p = child(path, "shading");
      const std::string s = r_.string(*v, p);
      std::optional<ShadingModel> model = parseShadingModel(s);
      if (!model) r_.fail(p, "unknown shading model '" + s + "' (known: flat, gouraud, phong, toon)");
      m.shading = *model;
    }
    if (const Json* v = opt("toonRamp")) m.toonRamp = toonRamp(*v, child(path, "toonRamp"));
    if (const Json* v = opt("checker")) {
      const std::string p = child(path, "checker");
      r_.object(*v, p);
      r_.checkKeys(*v, p, {"color2", "frequency"});
      m.kd2 = r_.color(r_.require(*v, p, "color2", "the second colour of the squares"), child(p, "color2"));
      m.checkerFrequency = 1.0f;
      if (const Json* f = Reader::find(*v, "frequency")) m.checkerFrequency = r_.number(*f, child(p, "frequency"), Range{0.0, 1e6, true});
    }
    if (const Json* v = opt("texture")) {
      const std::string p = child(path, "texture");
      if (m.checkerFrequency > 0.0f) r_.fail(p, "a material has a checker or a texture, not both");
      m.procedural = procedural(*v, p, m);
    }
    if (const Json* v = opt("opacity")) m.opacity = r_.number(*v, child(path, "opacity"), kUnit);
    if (const Json* v = opt("alphaMode")) {
      const std::string p = child(path, "alphaMode");
      const std::string s = r_.string(*v, p);
      if (s == "opaque") m.alphaMode = AlphaMode::Opaque;
      else if (s == "mask") m.alphaMode = AlphaMode::Mask;
      else if (s == "blend") m.alphaMode = AlphaMode::Blend;
      else r_.fail(p, "unknown alpha mode '" + s + "' (known: opaque, mask, blend)");
    }
    if (const Json* v = opt("alphaCutoff")) m.alphaCutoff = r_.number(*v, child(path, "alphaCutoff"), kUnit);
    if (const Json* v = opt("doubleSided")) m.doubleSided = r_.boolean(*v, child(path, "doubleSided"));
    if (const Json* v = opt("unlit")) m.unlit = r_.boolean(*v, child(path, "unlit"));
    return m;
  }

  // "texture": a procedural pattern (docs/procedural.md); its second colour is the material's kd2.
  ProceduralTexture procedural(const Json& j, const std::string& path, Material& m) const {
    r_.object(j, path);
    r_.checkKeys(j, path, {"type", "space", "scale", "turbulence", "octaves", "color2", "bump"});
    ProceduralTexture t;
    const std::string tp = child(path, "type");
    const std::string type = r_.string(r_.require(j, path, "type", "the pattern"), tp);
    static constexpr std::pair<std::string_view, Pattern> kTypes[] = {
        {"noise", Pattern::Noise}, {"fbm", Pattern::Fbm}, {"turbulence", Pattern::Turbulence},
        {"marble", Pattern::Marble}, {"wood", Pattern::Wood}, {"granite", Pattern::Granite}};
    for (const auto& [name, pattern] : kTypes)
      if (type == name) t.type = pattern;
    if (t.type == Pattern::None)
      r_.fail(tp, "unknown pattern '" + type + "' (known: noise, fbm, turbulence, marble, wood, granite)");
    if (const Json* v = Reader::find(j, "space")) {
      const std::string sp = child(path, "space");
      const std::string space = r_.string(*v, sp);
      if (space == "world") t.worldSpace = true;
      else if (space != "object") r_.fail(sp, "unknown space '" + space + "' (known: object, world)");
    }
    if (const Json* v = Reader::find(j, "scale")) t.scale = r_.number(*v, child(path, "scale"), Range{0.0, 1e6, true});
    if (const Json* v = Reader::find(j, "turbulence")) t.turbulence = r_.number(*v, child(path, "turbulence"), Range{0.0, 1e3});
    if (const Json* v = Reader::find(j, "octaves"))
      t.octaves = static_cast<int>(r_.integer(*v, child(path, "octaves"), 1, 8));
    if (const Json* v = Reader::find(j, "bump")) t.bump = r_.number(*v, child(path, "bump"), Range{0.0, 1e3});
    // Without color2 the pattern only bumps (kd on both ends).
    m.kd2 = m.kd;
    if (const Json* v = Reader::find(j, "color2")) m.kd2 = r_.color(*v, child(path, "color2"));
    return t;
  }

  std::vector<ToonStep> toonRamp(const Json& j, const std::string& path) const {
    r_.array(j, path);
    if (j.empty()) r_.fail(path, "needs at least one [threshold, level] step");
    if (j.size() > kMaxToonSteps) r_.fail(path, "more than " + std::to_string(kMaxToonSteps) + " steps");
    std::vector<ToonStep> ramp;
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string p = child(path, i);
      const Json& s = j[i];
      if (!s.is_array() || s.size() != 2) r_.fail(p, "expected [threshold, level], got " + Reader::describe(s));
      ramp.push_back({r_.number(s[0], child(p, 0), Range{-1.0, 1.0}), r_.number(s[1], child(p, 1), kNonNegative)});
    }
    return ramp;
  }

  // ---- lights ----
  void lights(const Json& j, const std::string& path) {
    r_.array(j, path);
    std::set<std::string> names;
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string p = child(path, i);
      Light l = light(j[i], p);
      if (const Json* n = Reader::find(j[i], "name")) {
        l.name = r_.nonEmptyString(*n, child(p, "name"));
        if (!names.insert(l.name).second) r_.fail(child(p, "name"), "duplicate light name '" + l.name + "'");
      } else {
        l.name = "light" + std::to_string(i);
      }
      addLight(std::move(l), p);
    }
  }

  Light light(const Json& j, const std::string& path) const {
    r_.object(j, path);
    const std::string typePath = child(path, "type");
    const std::string type =
        r_.string(r_.require(j, path, "type", "ambient, point, spot, directional, rect, disk or sphere"), typePath);
    Light l;
    if (type == "ambient") {
      l.type = LightType::Ambient;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity"}, "an ambient light");
    } else if (type == "point") {
      l.type = LightType::Point;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "position", "range", "attenuation", "castShadows"},
                   "a point light");
    } else if (type == "spot") {
      l.type = LightType::Spot;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "position", "direction", "range", "attenuation",
                             "innerCone", "outerCone", "castShadows"},
                   "a spot light");
    } else if (type == "directional") {
      l.type = LightType::Directional;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "direction", "castShadows"}, "a directional light");
    } else if (type == "rect") {
      l.type = LightType::Rect;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "position", "direction", "size", "up", "range",
                             "attenuation", "castShadows"},
                   "a rect light");
    } else if (type == "disk") {
      l.type = LightType::Disk;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "position", "direction", "radius", "range",
                             "attenuation", "castShadows"},
                   "a disk light");
    } else if (type == "sphere") {
      l.type = LightType::Sphere;
      r_.checkKeys(j, path, {"type", "name", "color", "intensity", "position", "radius", "range", "attenuation",
                             "castShadows"},
                   "a sphere light");
    } else {
      r_.fail(typePath, "unknown light type '" + type + "' (known: ambient, point, spot, directional, rect, disk, sphere)");
    }
    if (const Json* v = Reader::find(j, "color")) l.color = r_.color(*v, child(path, "color"));
    if (const Json* v = Reader::find(j, "intensity")) l.intensity = r_.number(*v, child(path, "intensity"), kNonNegative);
    const bool positioned = l.type == LightType::Point || l.type == LightType::Spot || isAreaLight(l.type);
    const bool directed = l.type == LightType::Spot || l.type == LightType::Directional || l.type == LightType::Rect ||
                          l.type == LightType::Disk;
    if (positioned) l.posW = r_.vec3(r_.require(j, path, "position"), child(path, "position"));
    if (directed) {
      const std::string p = child(path, "direction");
      glm::vec3 d = r_.vec3(r_.require(j, path, "direction", "the way the light travels"), p);
      const float len = glm::length(d);
      if (!(len > 1e-12f) || !std::isfinite(len)) r_.fail(p, "direction must be a non-zero vector");
      l.dirW = d / len;
    }
    if (positioned) {
      if (const Json* v = Reader::find(j, "range")) l.range = r_.number(*v, child(path, "range"), kNonNegative);
      if (const Json* v = Reader::find(j, "attenuation")) {
        const std::string p = child(path, "attenuation");
        l.attenuation = r_.vec3(*v, p, kNonNegative);
        // 1 / (c + l·d + q·d²) must stay finite away from the light.
        if (l.attenuation.x + l.attenuation.y + l.attenuation.z <= 0.0f)
          r_.fail(p, "at least one of constant, linear, quadratic must be > 0");
      }
    }
    if (l.type == LightType::Spot) {
      if (const Json* v = Reader::find(j, "innerCone")) l.innerConeDeg = r_.number(*v, child(path, "innerCone"), Range{0.0, 90.0});
      if (const Json* v = Reader::find(j, "outerCone"))
        l.outerConeDeg = r_.number(*v, child(path, "outerCone"), Range{0.0, 90.0, false, true});
      if (l.innerConeDeg > l.outerConeDeg)
        r_.fail(child(path, "innerCone"), "innerCone (" + formatNumber(l.innerConeDeg) + ") must not exceed outerCone (" +
                                              formatNumber(l.outerConeDeg) + ")");
    }
    if (l.type == LightType::Rect) {
      const std::string p = child(path, "size");
      const Json& v = r_.require(j, path, "size", "[width, height]");
      r_.array(v, p);
      if (v.size() != 2) r_.fail(p, "expected [width, height]");
      l.size = glm::vec2(r_.number(v[0], child(p, 0), kNonNegative), r_.number(v[1], child(p, 1), kNonNegative));
      if (const Json* u = Reader::find(j, "up")) {
        const std::string up = child(path, "up");
        glm::vec3 d = r_.vec3(*u, up);
        const float len = glm::length(d);
        if (!(len > 1e-12f) || !std::isfinite(len)) r_.fail(up, "up must be a non-zero vector");
        l.upW = d / len;
      }
    }
    if (l.type == LightType::Disk || l.type == LightType::Sphere)
      l.radius = r_.number(r_.require(j, path, "radius"), child(path, "radius"), kNonNegative);
    if (const Json* v = Reader::find(j, "castShadows")) l.castShadows = r_.boolean(*v, child(path, "castShadows"));
    return l;
  }

  void addLight(Light l, const std::string& source) {
    lightSources_.push_back(source);
    scene_.lights.push_back(std::move(l));
  }

  void checkLightCount() const {
    int direct = 0;
    for (std::size_t i = 0; i < scene_.lights.size(); ++i) {
      if (scene_.lights[i].type == LightType::Ambient) continue;
      if (++direct > kMaxLights) {
        int total = 0;
        for (const Light& l : scene_.lights) total += l.type != LightType::Ambient;
        r_.fail(lightSources_[i], "too many lights: " + std::to_string(total) + " non-ambient lights, the limit is " +
                                      std::to_string(kMaxLights) + " (ambient lights do not count)");
      }
    }
  }

  void checkTriangleBudget() const {
    std::uint64_t n = 0;
    for (const Mesh& m : scene_.meshes) n += m.triangleCount();
    if (n > kMaxSceneTriangles)
      r_.fail("/meshes", "the meshes hold " + std::to_string(n) + " triangles, more than the limit of " +
                             std::to_string(kMaxSceneTriangles));
  }

  // ---- instances and glTF placements ----
  void instances(const Json& j, const std::string& path) {
    r_.array(j, path);
    std::set<std::string> names;
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string p = child(path, i);
      r_.object(j[i], p);
      std::string name;
      if (const Json* n = Reader::find(j[i], "name")) {
        name = r_.nonEmptyString(*n, child(p, "name"));
        if (!names.insert(name).second) r_.fail(child(p, "name"), "duplicate instance name '" + name + "'");
      }
      if (Reader::find(j[i], "gltf")) placement(j[i], p, name);
      else meshInstance(j[i], p, name);
    }
  }

  void meshInstance(const Json& j, const std::string& path, std::string name) {
    r_.checkKeys(j, path, {"name", "mesh", "material", "transform", "dynamic", "motion"}, "a mesh instance");
    Instance inst;
    const std::string meshName = r_.string(r_.require(j, path, "mesh", "or 'gltf' for a glTF placement"), child(path, "mesh"));
    auto m = meshIndex_.find(meshName);
    if (m == meshIndex_.end()) r_.fail(child(path, "mesh"), "unknown mesh '" + meshName + "' (known: " + joinNames(meshNames_) + ")");
    inst.mesh = m->second;
    inst.material = materialByName(r_.require(j, path, "material"), child(path, "material"));
    if (const Json* v = Reader::find(j, "transform")) inst.worldFromObject = transform(*v, child(path, "transform"));
    if (const Json* v = Reader::find(j, "dynamic")) inst.dynamic = r_.boolean(*v, child(path, "dynamic"));
    if (const Json* v = Reader::find(j, "motion")) motion(*v, child(path, "motion"), inst);
    inst.name = name.empty() ? meshName : std::move(name);
    charge(path, "the instance", sizeof(Instance) + inst.name.size());
    scene_.instances.push_back(std::move(inst));
  }

  // Motion blur: world units per second and degrees per second about the instance's origin (docs/motion-blur.md).
  void motion(const Json& j, const std::string& path, Instance& inst) {
    r_.object(j, path);
    r_.checkKeys(j, path, {"velocity", "angularVelocity"});
    if (const Json* v = Reader::find(j, "velocity")) inst.velocity = r_.vec3(*v, child(path, "velocity"));
    if (const Json* v = Reader::find(j, "angularVelocity"))
      inst.angularVelocity = glm::radians(r_.vec3(*v, child(path, "angularVelocity")));
  }

  std::uint32_t materialByName(const Json& j, const std::string& path) const {
    const std::string s = r_.string(j, path);
    auto it = materialIndex_.find(s);
    if (it == materialIndex_.end()) r_.fail(path, "unknown material '" + s + "' (known: " + joinNames(materialNames_) + ")");
    return it->second;
  }

  void placement(const Json& j, const std::string& path, std::string name) {
    r_.checkKeys(j, path, {"name", "gltf", "transform", "materialOverrides", "lights", "dynamic"}, "a glTF placement");
    const std::string gltfPath = child(path, "gltf");
    if (name.empty()) name = fs::path(r_.nonEmptyString(j.at("gltf"), gltfPath)).stem().string();
    glm::mat4 xf(1.0f);
    if (const Json* v = Reader::find(j, "transform")) xf = transform(*v, child(path, "transform"));
    bool dynamic = false;
    if (const Json* v = Reader::find(j, "dynamic")) dynamic = r_.boolean(*v, child(path, "dynamic"));
    bool keepLights = true;
    if (const Json* v = Reader::find(j, "lights")) {
      const std::string p = child(path, "lights");
      const std::string s = r_.string(*v, p);
      if (s != "keep" && s != "drop") r_.fail(p, "expected 'keep' or 'drop', got '" + s + "'");
      keepLights = s == "keep";
    }
    Placed& placed = loadGltfCached(j.at("gltf"), gltfPath);
    const MaterialOverrides overrides = materialOverrides(j, path, placed.scene);
    const std::string prefix = name + "/";
    if (!placed.placed) addPlacedFile(placed, prefix, gltfPath);
    const std::vector<std::uint32_t> materialMap = placedMaterials(placed, overrides, prefix, gltfPath);
    addPlacedInstances(placed, materialMap, prefix, gltfPath, xf, dynamic);
    if (keepLights) addPlacedLights(placed.scene, prefix, path, xf);
  }

  // materialOverrides: glTF material name (or "*" for all) → material of this file.
  struct MaterialOverrides {
    std::optional<std::uint32_t> all;
    std::map<std::string, std::uint32_t> byName;
  };

  MaterialOverrides materialOverrides(const Json& j, const std::string& path, const Scene& g) const {
    MaterialOverrides out;
    const Json* v = Reader::find(j, "materialOverrides");
    if (!v) return out;
    const std::string p = child(path, "materialOverrides");
    r_.object(*v, p);
    std::set<std::string> known;
    for (const Material& m : g.materials) known.insert(m.name);
    for (const auto& [key, value] : v->items()) {
      const std::string kp = child(p, key);
      const std::uint32_t target = materialByName(value, kp);
      if (key == "*") {
        out.all = target;
      } else {
        if (!known.count(key)) {
          std::vector<std::string> names;
          for (const Material& m : g.materials)
            if (std::find(names.begin(), names.end(), m.name) == names.end()) names.push_back(m.name);
          r_.fail(kp, "no material named '" + key + "' in the glTF file (known: " + joinNames(names) + ")");
        }
        out.byName[key] = target;
      }
    }
    return out;
  }

  // The file's meshes and textures join the scene once, named after its first placement.
  void addPlacedFile(Placed& placed, const std::string& prefix, const std::string& gltfPath) {
    const Scene& g = placed.scene;
    std::uint64_t bytes = 0;
    for (const Mesh& m : g.meshes) bytes += m.bytes() + prefix.size();
    for (const Texture& t : g.textures) bytes += t.rgba8.size() + prefix.size();
    charge(gltfPath, "the glTF file's meshes and textures", bytes);
    placed.placed = true;
    placed.meshBase = static_cast<std::uint32_t>(scene_.meshes.size());
    placed.textureBase = static_cast<int>(scene_.textures.size());
    placed.materialCopy.assign(g.materials.size(), -1);
    for (const Mesh& m : g.meshes) {
      scene_.meshes.push_back(m);
      scene_.meshes.back().name = prefix + m.name;
    }
    for (const Texture& t : g.textures) {
      scene_.textures.push_back(t);
      scene_.textures.back().name = prefix + t.name;
    }
  }

  // Overridden materials map to the scene's material; the others to one shared copy with the texture
  // indices shifted, made when a placement first needs it.
  std::vector<std::uint32_t> placedMaterials(Placed& placed, const MaterialOverrides& overrides,
                                             const std::string& prefix, const std::string& gltfPath) {
    const Scene& g = placed.scene;
    std::vector<std::uint32_t> materialMap(g.materials.size());
    for (std::size_t i = 0; i < g.materials.size(); ++i) {
      const Material& gm = g.materials[i];
      auto o = overrides.byName.find(gm.name);
      if (o != overrides.byName.end()) {
        materialMap[i] = o->second;
      } else if (overrides.all) {
        materialMap[i] = *overrides.all;
      } else {
        if (placed.materialCopy[i] < 0) {
          charge(gltfPath, "a copy of the glTF file's material", sizeof(Material) + prefix.size() + gm.name.size());
          Material m = gm;
          m.name = prefix + gm.name;
          if (m.kdTexture >= 0) m.kdTexture += placed.textureBase;
          if (m.normalTexture >= 0) m.normalTexture += placed.textureBase;
          if (m.emissiveTexture >= 0) m.emissiveTexture += placed.textureBase;
          placed.materialCopy[i] = static_cast<std::int64_t>(scene_.materials.size());
          scene_.materials.push_back(std::move(m));
        }
        materialMap[i] = static_cast<std::uint32_t>(placed.materialCopy[i]);
      }
    }
    return materialMap;
  }

  void addPlacedInstances(const Placed& placed, const std::vector<std::uint32_t>& materialMap,
                          const std::string& prefix, const std::string& gltfPath, const glm::mat4& worldFromFile,
                          bool dynamic) {
    const Scene& g = placed.scene;
    for (const Instance& gi : g.instances) {
      if (gi.mesh >= g.meshes.size() || gi.material >= g.materials.size())
        r_.fail(gltfPath, "the glTF loader returned an instance with an out-of-range index");
      charge(gltfPath, "the placement's instances", sizeof(Instance) + prefix.size() + gi.name.size());
      Instance inst = gi;
      inst.name = prefix + gi.name;
      inst.mesh = placed.meshBase + gi.mesh;
      inst.material = materialMap[gi.material];
      inst.worldFromObject = worldFromFile * gi.worldFromObject;
      inst.dynamic = gi.dynamic || dynamic;
      scene_.instances.push_back(std::move(inst));
    }
  }

  void addPlacedLights(const Scene& g, const std::string& prefix, const std::string& path,
                       const glm::mat4& worldFromFile) {
    const glm::mat3 linear(worldFromFile);
    for (const Light& gl : g.lights) {
      Light l = gl;
      l.name = prefix + gl.name;
      l.posW = glm::vec3(worldFromFile * glm::vec4(gl.posW, 1.0f));
      // Directions move with the placement; range and attenuation stay in the file's units.
      glm::vec3 d = linear * gl.dirW;
      const float len = glm::length(d);
      l.dirW = len > 0.0f ? d / len : gl.dirW;
      addLight(std::move(l), path);
    }
  }

  glm::mat4 transform(const Json& j, const std::string& path) const {
    r_.object(j, path);
    r_.checkKeys(j, path, {"translate", "rotate", "scale", "matrix"});
    if (const Json* mj = Reader::find(j, "matrix")) {
      const std::string p = child(path, "matrix");
      if (j.size() > 1) r_.fail(p, "'matrix' cannot be combined with translate/rotate/scale");
      if (!mj->is_array() || mj->size() != 16)
        r_.fail(p, "expected 16 numbers (column-major), got " + Reader::describe(*mj));
      glm::mat4 m(0.0f);
      for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
          const auto k = static_cast<std::size_t>(c * 4 + row);
          m[c][row] = r_.number((*mj)[k], child(p, k));
        }
      // Instances are rigid placements: a projective bottom row would break normals and ray transforms.
      if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
        r_.fail(p, "not an affine transform: elements 3, 7, 11 must be 0 and 15 must be 1 (column-major)");
      const float det = glm::determinant(glm::mat3(m));
      if (!std::isfinite(det) || std::abs(det) < 1e-12f) r_.fail(p, "the matrix is singular (determinant 0)");
      if (det < 0.0f) r_.fail(p, "the matrix mirrors (negative determinant), which flips triangle winding; not supported");
      return m;
    }
    glm::mat4 m(1.0f);
    if (const Json* v = Reader::find(j, "translate")) m = glm::translate(m, r_.vec3(*v, child(path, "translate")));
    if (const Json* v = Reader::find(j, "rotate")) m = m * rotation(*v, child(path, "rotate"));
    if (const Json* v = Reader::find(j, "scale"))
      // Mirroring (negative) or flattening (zero) scales would flip or collapse triangles.
      m = glm::scale(m, r_.vec3(*v, child(path, "scale"), Range{0.0, 1e6, true}, true));
    return m;
  }

  glm::mat4 rotation(const Json& j, const std::string& path) const {
    if (j.is_object()) {
      r_.checkKeys(j, path, {"axis", "angle"});
      const std::string ap = child(path, "axis");
      glm::vec3 axis = r_.vec3(r_.require(j, path, "axis"), ap);
      const float len = glm::length(axis);
      if (!(len > 1e-12f) || !std::isfinite(len)) r_.fail(ap, "axis must be a non-zero vector");
      const float angle = r_.number(r_.require(j, path, "angle", "degrees"), child(path, "angle"));
      return glm::rotate(glm::mat4(1.0f), glm::radians(angle), axis / len);
    }
    if (!j.is_array()) r_.fail(path, std::string("expected [x, y, z] Euler degrees or {\"axis\", \"angle\"}, got ") + Reader::typeName(j));
    const glm::vec3 e = r_.vec3(j, path);
    // xyz Euler: about X first, then Y, then Z (fixed axes), so R = Rz·Ry·Rx.
    glm::mat4 rz = glm::rotate(glm::mat4(1.0f), glm::radians(e.z), glm::vec3(0, 0, 1));
    glm::mat4 ry = glm::rotate(glm::mat4(1.0f), glm::radians(e.y), glm::vec3(0, 1, 0));
    glm::mat4 rx = glm::rotate(glm::mat4(1.0f), glm::radians(e.x), glm::vec3(1, 0, 0));
    return rz * ry * rx;
  }

  // ---- camera and render settings ----
  void camera(const Json& j, const std::string& path) {
    r_.object(j, path);
    r_.checkKeys(j, path,
                 {"position", "target", "up", "fov", "near", "far", "orthographic", "height", "aperture", "focusDistance",
                  "shutter"});
    Camera& c = scene_.camera;
    if (const Json* v = Reader::find(j, "position")) c.posW = r_.vec3(*v, child(path, "position"));
    if (const Json* v = Reader::find(j, "target")) c.targetW = r_.vec3(*v, child(path, "target"));
    if (const Json* v = Reader::find(j, "up")) c.upW = r_.vec3(*v, child(path, "up"));
    if (const Json* v = Reader::find(j, "fov")) c.yFovDeg = r_.number(*v, child(path, "fov"), Range{0.0, 180.0, true, true});
    if (const Json* v = Reader::find(j, "near")) c.nearZ = r_.number(*v, child(path, "near"), kPositive);
    if (const Json* v = Reader::find(j, "far")) {
      const std::string p = child(path, "far");
      if (v->is_string()) {
        if (v->get<std::string>() != "infinite") r_.fail(p, "expected a number or \"infinite\", got '" + v->get<std::string>() + "'");
        c.farZ = std::numeric_limits<float>::infinity();
      } else {
        c.farZ = r_.number(*v, p, kPositive);
      }
    }
    if (!(c.farZ > c.nearZ))
      r_.fail(child(path, "far"), "far (" + formatNumber(c.farZ) + ") must be greater than near (" + formatNumber(c.nearZ) + ")");
    if (const Json* v = Reader::find(j, "orthographic")) c.orthographic = r_.boolean(*v, child(path, "orthographic"));
    if (const Json* v = Reader::find(j, "height")) c.orthoHeight = r_.number(*v, child(path, "height"), kPositive);
    if (const Json* v = Reader::find(j, "aperture")) {
      c.aperture = r_.number(*v, child(path, "aperture"), Range{0.0});
      if (c.aperture > 0.0f && c.orthographic)
        r_.fail(child(path, "aperture"), "an orthographic camera has no lens (aperture needs a perspective camera)");
    }
    if (const Json* v = Reader::find(j, "focusDistance"))
      c.focusDistance = r_.number(*v, child(path, "focusDistance"), kPositive);
    if (const Json* v = Reader::find(j, "shutter")) c.shutter = r_.number(*v, child(path, "shutter"), Range{0.0});
    const glm::vec3 forward = c.targetW - c.posW;
    if (!(glm::length(forward) > 1e-6f)) r_.fail(child(path, "target"), "target must differ from position");
    const float upLen = glm::length(c.upW);
    if (!(upLen > 1e-12f)) r_.fail(child(path, "up"), "up must be a non-zero vector");
    if (glm::length(glm::cross(glm::normalize(forward), c.upW / upLen)) < 1e-4f)
      r_.fail(child(path, "up"), "up is parallel to the view direction (target - position)");
  }

  // ---- environment (docs/environment.md) ----
  // {"image": "sky.hdr"} or {} (the sky, its colours given or the defaults); intensity, rotation, ambient.
  void environment(const Json& j, const std::string& path) {
    r_.object(j, path);
    r_.checkKeys(j, path, {"image", "zenith", "horizon", "ground", "intensity", "rotation", "ambient"}, "an environment");
    Environment& e = scene_.environment;
    e.kind = Environment::Kind::Sky;
    if (const Json* v = Reader::find(j, "image")) {
      const std::string p = child(path, "image");
      for (const char* key : {"zenith", "horizon", "ground"})
        if (Reader::find(j, key)) r_.fail(child(path, key), "an environment image has no sky colours");
      const std::string file = resolve(*v, p);
      Result<std::shared_ptr<const EnvironmentMap>> map = loadEnvironmentMap(file);
      if (!map) r_.fail(p, map.error().message);
      // The image joins this load's input, as a placed glTF file does: readHdr bounds it on its own.
      budget_.addInput((*map)->texels().size() * sizeof(glm::vec3));
      e.kind = Environment::Kind::Map;
      e.map = std::move(*map);
    }
    if (const Json* v = Reader::find(j, "zenith")) e.zenith = r_.color(*v, child(path, "zenith"));
    if (const Json* v = Reader::find(j, "horizon")) e.horizon = r_.color(*v, child(path, "horizon"));
    if (const Json* v = Reader::find(j, "ground")) e.ground = r_.color(*v, child(path, "ground"));
    if (const Json* v = Reader::find(j, "intensity")) e.intensity = r_.number(*v, child(path, "intensity"), Range{0.0, 1e6});
    if (const Json* v = Reader::find(j, "rotation")) e.rotationDeg = r_.number(*v, child(path, "rotation"), Range{-360.0, 360.0});
    if (const Json* v = Reader::find(j, "ambient")) e.lightsAmbient = r_.boolean(*v, child(path, "ambient"));
  }

  void render(const Json& j, const std::string& path) {
    r_.object(j, path);
    r_.checkKeys(j, path, {"width", "height", "preset", "maxDepth", "radiosity"});
    SceneRenderDefaults& d = scene_.render;
    if (const Json* v = Reader::find(j, "width")) d.width = r_.integer(*v, child(path, "width"), 1, kMaxImageSide);
    if (const Json* v = Reader::find(j, "height")) d.height = r_.integer(*v, child(path, "height"), 1, kMaxImageSide);
    if (const Json* v = Reader::find(j, "preset")) {
      const std::string p = child(path, "preset");
      d.preset = r_.string(*v, p);
      const std::vector<std::string> known = presetNames();
      if (std::find(known.begin(), known.end(), d.preset) == known.end())
        r_.fail(p, "unknown preset '" + d.preset + "' (known: " + joinNames(known) + ")");
    }
    if (const Json* v = Reader::find(j, "maxDepth")) d.maxDepth = r_.integer(*v, child(path, "maxDepth"), 0, kMaxDepthLimit);
    if (const Json* v = Reader::find(j, "radiosity")) d.radiosity = r_.boolean(*v, child(path, "radiosity")) ? 1 : 0;
  }

  Reader r_;
  std::optional<std::string> baseDir_;  // nullopt: no folder to resolve relative paths against
  Scene scene_;
  std::unordered_map<std::string, std::uint32_t> meshIndex_, materialIndex_;
  std::vector<std::string> meshNames_, materialNames_;  // in file order, for "known: ..." lists
  std::vector<std::string> lightSources_;               // JSON pointer each light came from
  std::map<std::string, Placed> gltfCache_;             // one load per file, shared by meshes and placements
  LoadBudget budget_{kBudgetBaseBytes, kBudgetBytesPerInputByte};
};

Result<Scene> parseImpl(std::string_view text, const std::string& name, std::optional<std::string> baseDir) {
  try {
    Json root = parseText(text, name);
    Builder builder{Reader(name), std::move(baseDir), text.size()};
    Scene scene = builder.build(root, fs::path(name).stem().string());
    // The builder checks everything it reads; validateScene is the contract the Renderer relies on,
    // so it is the last word (it also covers what glTF placements bring in).
    Result<void> valid = validateScene(scene);
    if (!valid) return Error{name + ": " + valid.error().message};
    for (const std::string& w : coplanarOverlaps(scene)) logWarning(name + ": " + w);
    return scene;
  } catch (const SceneFileError& e) {
    return Error{e.message};
  } catch (const std::bad_alloc&) {
    return Error{name + ": out of memory"};
  } catch (const std::exception& e) {
    return Error{name + ": " + e.what()};
  }
}

/// The repository's assets/scenes, for relative paths in the embedded default scene: looked for under
/// the working directory and above the executable (build trees sit inside or beside the checkout).
std::optional<std::string> findRepositoryScenes() {
  std::error_code ec;
  std::vector<fs::path> starts{fs::current_path(ec)};
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) starts.push_back(exe.parent_path());
  for (fs::path dir : starts) {
    for (int up = 0; up < 5 && !dir.empty(); ++up) {
      fs::path candidate = dir / "assets" / "scenes";
      if (fs::is_regular_file(candidate / "whitted.json", ec)) return candidate.string();
      if (dir == dir.parent_path()) break;
      dir = dir.parent_path();
    }
  }
  return std::nullopt;
}

}  // namespace

Result<Scene> parseSceneJson(std::string_view text, const std::string& name, const std::string& baseDir) {
  return parseImpl(text, name, baseDir.empty() ? std::string(".") : baseDir);
}

Result<Scene> loadSceneFile(const std::string& path) {
  try {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return Error{path + ": no such file"};
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) return Error{path + ": cannot read: " + ec.message()};
    if (size > kMaxFileBytes)
      return Error{path + ": " + std::to_string(size) + " bytes, more than the limit of " + std::to_string(kMaxFileBytes)};
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path + ": cannot open: " + std::strerror(errno)};
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    if (in.gcount() != static_cast<std::streamsize>(size)) return Error{path + ": read failed"};
    fs::path dir = fs::path(path).parent_path();
    return parseImpl(text, path, dir.empty() ? std::string(".") : dir.string());
  } catch (const std::exception& e) {
    return Error{path + ": " + e.what()};
  }
}

std::string_view defaultSceneText() { return findEmbedded("assets/scenes/whitted.json").value_or(std::string_view{}); }

Result<Scene> loadDefaultScene() {
  std::string_view text = defaultSceneText();
  if (text.empty()) return Error{"whitted.json: the default scene is not embedded in this binary"};
  std::optional<std::string> dir;
  try {
    dir = findRepositoryScenes();
  } catch (const std::exception&) {
    dir.reset();  // no folder: relative glTF references then fail with their own message
  }
  return parseImpl(text, "whitted.json", std::move(dir));
}

Result<std::shared_ptr<const EnvironmentMap>> loadEnvironmentMap(const std::string& path) {
  Result<ImageF> image = readHdr(path);
  if (!image) return image.error();
  return std::shared_ptr<const EnvironmentMap>(
      std::make_shared<EnvironmentMap>(image->width, image->height, std::move(image->rgb)));
}

}  // namespace tandem
