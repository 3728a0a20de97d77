#include "gl/GpuScene.h"

#include "core/RenderSpace.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

#include "core/Finite.h"
#include "core/MeshLod.h"
#include "core/Motion.h"
#include "core/RenderSpace.h"
#include "core/Shading.h"

namespace tandem::gl {

std::vector<std::uint32_t> probeInstances(const Scene& scene) {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Material& m = scene.materials[scene.instances[i].material];
    // BLEND surfaces show what is behind them through their uncovered part: the probe's refraction term.
    if (m.kr > 0.0f || m.kt > 0.0f || m.alphaMode == AlphaMode::Blend) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

ProbeLayout probeLayout(const Scene& scene, int limit) {
  ProbeLayout layout;
  layout.slotOf.assign(scene.instances.size(), -1);
  const std::vector<std::uint32_t> wanting = probeInstances(scene);
  const std::size_t count = std::min(wanting.size(), static_cast<std::size_t>(std::max(limit, 1)));
  if (wanting.size() <= count) {
    layout.probes = wanting;
  } else {
    // World bounds of each instance that wants one: its mesh's box, transformed (centre and radius).
    std::vector<glm::dvec3> centre(wanting.size());
    std::vector<double> radius(wanting.size());
    std::vector<std::pair<glm::vec3, glm::vec3>> meshBox(scene.meshes.size(), {glm::vec3(0.0f), glm::vec3(0.0f)});
    std::vector<bool> boxed(scene.meshes.size(), false);
    for (std::size_t k = 0; k < wanting.size(); ++k) {
      const Instance& inst = scene.instances[wanting[k]];
      if (!boxed[inst.mesh] && !scene.meshes[inst.mesh].positions.empty()) {
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        for (const glm::vec3& p : scene.meshes[inst.mesh].positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        meshBox[inst.mesh] = {lo, hi};
        boxed[inst.mesh] = true;
      }
      const auto& [lo, hi] = meshBox[inst.mesh];
      const glm::dvec3 c = (glm::dvec3(lo) + glm::dvec3(hi)) * 0.5, half = (glm::dvec3(hi) - glm::dvec3(lo)) * 0.5;
      const glm::dmat4 m(inst.worldFromObject);
      centre[k] = glm::dvec3(m * glm::dvec4(c, 1.0));
      const glm::dmat3 linear(m);
      glm::dvec3 extent(0.0);  // the box's half extent in world space: |M|·half
      for (int axis = 0; axis < 3; ++axis) extent += glm::abs(linear[axis]) * half[axis];
      radius[k] = glm::length(extent);
      if (!std::isfinite(radius[k]) || !allFinite(centre[k])) centre[k] = glm::dvec3(0.0), radius[k] = 0.0;
    }
    // Farthest-point sampling: the largest first, then each time the one farthest from those chosen.
    std::vector<double> nearest(wanting.size(), std::numeric_limits<double>::infinity());
    std::size_t next = static_cast<std::size_t>(std::max_element(radius.begin(), radius.end()) - radius.begin());
    std::vector<std::size_t> chosen;
    while (chosen.size() < count) {
      chosen.push_back(next);
      nearest[next] = -1.0;  // chosen: never again
      for (std::size_t k = 0; k < wanting.size(); ++k)
        if (nearest[k] >= 0.0) nearest[k] = std::min(nearest[k], glm::distance(centre[k], centre[next]));
      next = static_cast<std::size_t>(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
    }
    std::sort(chosen.begin(), chosen.end());  // slots in instance order
    for (std::size_t k : chosen) layout.probes.push_back(wanting[k]);
    for (std::size_t k = 0; k < wanting.size(); ++k) {
      std::size_t best = 0;
      for (std::size_t s = 1; s < chosen.size(); ++s)
        if (glm::distance(centre[k], centre[chosen[s]]) < glm::distance(centre[k], centre[chosen[best]])) best = s;
      layout.slotOf[wanting[k]] = static_cast<std::int32_t>(best);
    }
    return layout;
  }
  for (std::size_t slot = 0; slot < layout.probes.size(); ++slot)
    layout.slotOf[layout.probes[slot]] = static_cast<std::int32_t>(slot);
  return layout;
}

namespace {

struct GpuInstance {
  glm::mat4 worldFromObject;
  glm::mat4 normalFromObject;
  glm::uvec4 meshMaterial;
};
static_assert(sizeof(GpuInstance) == 144, "GpuInstance must match its std430 layout in scene.glsl");

struct DrawCommand {
  GLuint count, instanceCount, firstIndex;
  GLint baseVertex;
  GLuint baseInstance;
};

constexpr std::uint32_t kHasNormals = 1, kHasUvs = 2, kHasColors = 4, kHasTangents = 8;
constexpr int kMaxTextureSize = 2048;

template <class T>
Buffer bufferOf(std::string_view label, const std::vector<T>& v) {
  return createBuffer(label, v.size() * sizeof(T), v.data());
}

// Instance transforms in render space (core/RenderSpace.h): their translations rebased on the anchor in
// double, so vertices far from the world origin are transformed with small, precise numbers.
std::vector<GpuInstance> packInstances(const Scene& scene, const ProbeLayout& probes, glm::vec3 anchor,
                                       float shutter = 0.0f, float u = 0.5f) {
  std::vector<GpuInstance> out;
  out.reserve(scene.instances.size());
  for (const Instance& inst : scene.instances) {
    GpuInstance g;
    // A moving instance at shutter time u: its render-space steps blended as the ray scene blends them.
    g.worldFromObject = isMoving(inst, shutter) ? motionAt(motionSteps(inst, shutter, anchor), u)
                                                : toRenderSpace(inst.worldFromObject, anchor);
    glm::mat3 m(g.worldFromObject);  // the upper 3x3 render space keeps from world space
    float det = glm::determinant(m);
    // A singular transform has no inverse: a zero matrix makes every normal fall back to Ng, as on the CPU.
    g.normalFromObject = std::isfinite(det) && det != 0.0f ? glm::mat4(glm::transpose(glm::inverse(m))) : glm::mat4(0.0f);
    g.meshMaterial = glm::uvec4(inst.mesh, inst.material, 0, 0);
    out.push_back(g);
  }
  // z = reflection-probe slot + 1 (0 = none), as the probe layout assigns them.
  for (std::size_t i = 0; i < out.size() && i < probes.slotOf.size(); ++i)
    out[i].meshMaterial.z = static_cast<std::uint32_t>(probes.slotOf[i] + 1);
  return out;
}

// Bilinear resize of 8-bit RGBA in its stored encoding: textures of one scene are nearly always one
// size already, and this only runs for the odd one out.
std::vector<std::uint8_t> resizeRgba8(const tandem::Texture& t, int w, int h) {
  if (t.width == w && t.height == h) return t.rgba8;
  std::vector<std::uint8_t> out(static_cast<std::size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float sx = std::clamp((float(x) + 0.5f) * float(t.width) / float(w) - 0.5f, 0.0f, float(t.width - 1));
      float sy = std::clamp((float(y) + 0.5f) * float(t.height) / float(h) - 0.5f, 0.0f, float(t.height - 1));
      int x0 = int(sx), y0 = int(sy);
      int x1 = std::min(x0 + 1, t.width - 1), y1 = std::min(y0 + 1, t.height - 1);
      float fx = sx - float(x0), fy = sy - float(y0);
      for (int c = 0; c < 4; ++c) {
        auto at = [&](int xx, int yy) { return float(t.rgba8[(static_cast<std::size_t>(yy) * t.width + xx) * 4 + c]); };
        float v = (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
        out[(static_cast<std::size_t>(y) * w + x) * 4 + c] = static_cast<std::uint8_t>(std::lround(v));
      }
    }
  return out;
}

// Tangents are uploaded only for meshes drawn with a normal-mapped material (the only readers).
std::vector<bool> normalMappedMeshes(const Scene& scene) {
  std::vector<bool> meshNormalMapped(scene.meshes.size(), false);
  for (const Instance& inst : scene.instances)
    if (inst.mesh < scene.meshes.size() && scene.materials[inst.material].normalTexture >= 0)
      meshNormalMapped[inst.mesh] = true;
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const Mesh& m = scene.meshes[i];
    meshNormalMapped[i] = meshNormalMapped[i] && m.tangents.size() == m.positions.size() && !m.uvs.empty();
  }
  return meshNormalMapped;
}

// Every mesh's vertices in one shared set of arrays; a channel no mesh has stays empty, one that some
// meshes lack is filled with a neutral value for them (and their flag says so).
struct PackedGeometry {
  std::vector<float> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> colors, tangents;
  std::vector<std::uint32_t> indices;  // absolute, so no base vertex is needed
  std::vector<glm::uvec4> meshes;      // first vertex, first index, flags, triangle count
  bool anyUvs = false, anyColors = false, anyTangents = false;
};

PackedGeometry packGeometry(const Scene& scene) {
  PackedGeometry g;
  std::size_t vertexCount = 0, indexCount = 0;
  bool anyNormals = false;
  const std::vector<bool> meshNormalMapped = normalMappedMeshes(scene);
  for (bool mapped : meshNormalMapped) g.anyTangents |= mapped;
  for (const Mesh& m : scene.meshes) {
    vertexCount += m.positions.size();
    indexCount += m.indices.size();
    anyNormals |= !m.normals.empty();
    g.anyUvs |= !m.uvs.empty();
    g.anyColors |= !m.colors.empty() && m.colors.size() == m.positions.size();
  }
  g.positions.reserve(vertexCount * 3);
  g.indices.reserve(indexCount);
  if (anyNormals) g.normals.reserve(vertexCount * 3);
  if (g.anyUvs) g.uvs.reserve(vertexCount);
  if (g.anyColors) g.colors.reserve(vertexCount);
  if (g.anyTangents) g.tangents.reserve(vertexCount);
  for (std::size_t mi = 0; mi < scene.meshes.size(); ++mi) {
    const Mesh& m = scene.meshes[mi];
    auto first = static_cast<std::uint32_t>(g.positions.size() / 3);
    std::uint32_t flags = 0;
    for (const glm::vec3& p : m.positions) g.positions.insert(g.positions.end(), {p.x, p.y, p.z});
    if (anyNormals) {
      if (!m.normals.empty()) flags |= kHasNormals;
      for (std::size_t i = 0; i < m.positions.size(); ++i) {
        glm::vec3 n = m.normals.empty() ? glm::vec3(0.0f) : m.normals[i];
        g.normals.insert(g.normals.end(), {n.x, n.y, n.z});
      }
    }
    if (g.anyUvs) {
      if (!m.uvs.empty()) flags |= kHasUvs;
      for (std::size_t i = 0; i < m.positions.size(); ++i) g.uvs.push_back(m.uvs.empty() ? glm::vec2(0.0f) : m.uvs[i]);
    }
    if (g.anyColors) {
      bool has = m.colors.size() == m.positions.size() && !m.colors.empty();
      if (has) flags |= kHasColors;
      for (std::size_t i = 0; i < m.positions.size(); ++i) g.colors.push_back(has ? m.colors[i] : glm::vec4(1.0f));
    }
    if (g.anyTangents) {
      if (meshNormalMapped[mi]) flags |= kHasTangents;
      for (std::size_t i = 0; i < m.positions.size(); ++i)
        g.tangents.push_back(meshNormalMapped[mi] ? m.tangents[i] : glm::vec4(0.0f));
    }
    g.meshes.emplace_back(first, static_cast<std::uint32_t>(g.indices.size()), flags,
                          static_cast<std::uint32_t>(m.triangleCount()));
    for (std::uint32_t i : m.indices) g.indices.push_back(first + i);
  }
  return g;
}

}  // namespace

void GpuScene::upload(const Scene& scene, std::optional<ShadingModel> shadingOverride,
                      std::optional<glm::vec3> anchor, int probeLimit) {
  anchor_ = anchor ? *anchor : renderAnchor(scene);
  probeLimit_ = probeLimit;
  probes_ = probeLayout(scene, probeLimit);
  const PackedGeometry g = packGeometry(scene);
  features_.uvs = g.anyUvs;
  features_.colors = g.anyColors;
  features_.exact = std::any_of(scene.instances.begin(), scene.instances.end(),
                                [&](const Instance& inst) { return scene.meshes[inst.mesh].exact.has_value(); });
  positions_ = bufferOf("positions", g.positions);
  normals_ = bufferOf("normals", g.normals);
  uvs_ = bufferOf("uvs", g.uvs);
  colors_ = bufferOf("colors", g.colors);
  indices_ = bufferOf("indices", g.indices);
  indexCount_ = g.indices.size();
  meshes_ = bufferOf("meshes", g.meshes);
  tangents_ = bufferOf("tangents", g.tangents);
  // Empty channels keep a 16-byte stand-in buffer: the views are over whole buffers either way.
  positionsTex_ = createBufferTexture("positions view", GL_RGB32F, positions_);
  normalsTex_ = createBufferTexture("normals view", GL_RGB32F, normals_);
  uvsTex_ = createBufferTexture("uvs view", GL_RG32F, uvs_);
  colorsTex_ = createBufferTexture("colors view", GL_RGBA32F, colors_);
  indicesTex_ = createBufferTexture("indices view", GL_R32UI, indices_);
  meshesTex_ = createBufferTexture("meshes view", GL_RGBA32UI, meshes_);
  tangentsTex_ = createBufferTexture("tangents view", GL_RGBA32F, tangents_);
  bytes_ = (g.positions.size() + g.normals.size()) * sizeof(float) + g.uvs.size() * sizeof(glm::vec2) +
           (g.colors.size() + g.tangents.size()) * sizeof(glm::vec4) + g.indices.size() * sizeof(std::uint32_t);

  uploadInstances(scene, g.meshes);
  updateLights(scene);
  uploadEnvironment(scene);
  toonRamps_.reset();
  updateMaterials(scene, shadingOverride);
  uploadTextures(scene, g.anyTangents);
}

void GpuScene::uploadEnvironment(const Scene& scene) {
  environment_ = EnvironmentLookup(scene);
  // (variant flags: code llvmpipe compiles into the shader costs it even where a branch skips it, ~10 ms of a
  // 1280x720 frame's shade for the lookup alone)
  features_.environment = environment_.kind() != TD_ENV_BACKGROUND;
  features_.environmentAmbient = environment_.lightsAmbient();
  environmentMap_.reset();
  const EnvironmentMap* map = environment_.map();
  if (!map) return;
  // Level 0 only, read with textureLod 0 (the shade pass's pixels branch): linear filtering, the seam at u = 0
  // wrapped, the poles' rows clamped, as rt's sampleEquirect reads the texels.
  environmentMap_ = createTexture2D("environment", GL_RGB32F, map->width(), map->height());
  glTextureSubImage2D(environmentMap_.id(), 0, 0, 0, map->width(), map->height(), GL_RGB, GL_FLOAT,
                      map->texels().data());
  glTextureParameteri(environmentMap_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(environmentMap_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(environmentMap_.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(environmentMap_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  bytes_ += map->texels().size() * sizeof(glm::vec3);
}

// One draw command per instance, baseInstance = instance index.
void GpuScene::uploadInstances(const Scene& scene, const std::vector<glm::uvec4>& meshes) {
  instanceCount_ = static_cast<int>(scene.instances.size());
  otherSlot_ = {};
  slot_ = 0;
  instances_ = bufferOf("instances", packInstances(scene, probes_, anchor_));
  // Two views of one record: the matrices as floats, meshMaterial as integers (reading integer bits
  // through a float view would meet llvmpipe's denormal flushing).
  instancesTex_ = createBufferTexture("instances view", GL_RGBA32F, instances_);
  instanceIdsTex_ = createBufferTexture("instance ids view", GL_RGBA32UI, instances_);
  // The static instances' commands first, the dynamic ones after: each set is one contiguous range to draw.
  // (baseInstance names the instance, so the order changes no pixel: depth keeps the nearest either way.)
  staticDraws_ = dynamicDraws_ = 0;
  drawInstance_.clear();
  for (bool dynamic : {false, true})
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      if (scene.instances[i].dynamic != dynamic) continue;
      drawInstance_.push_back(static_cast<std::uint32_t>(i));
      ++(dynamic ? dynamicDraws_ : staticDraws_);
    }
  meshRecords_ = meshes;
  lodLevels_ = 0;
  vao_ = createVertexArray("visibility vao");
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
  writeDrawCommands(scene, {});
}

void GpuScene::writeDrawCommands(const Scene& scene,
                                 const std::vector<std::array<glm::uvec2, kProbeLodCells.size()>>& copies) {
  const std::size_t levels = copies.empty() ? 0 : kProbeLodCells.size();
  const auto n = static_cast<std::uint32_t>(instanceCount_);
  std::vector<DrawCommand> commands;
  std::vector<std::uint32_t> ids, bases;
  commands.reserve(drawInstance_.size() * (levels + 1));
  for (std::size_t level = 0; level <= levels; ++level) {
    auto range = [&](std::uint32_t mesh) {
      const glm::uvec4& record = meshRecords_[mesh];
      return level == 0 ? glm::uvec2(record.y, record.w) : copies[mesh][level - 1];
    };
    for (std::uint32_t i : drawInstance_) {
      const glm::uvec2 r = range(scene.instances[i].mesh);
      commands.push_back({r.y * 3, 1, r.x, 0, static_cast<GLuint>(level) * n + i});
    }
    // A copy's triangle t is the mesh's triangle (first − the mesh's first index) / 3 + t for the shade pass.
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t mesh = scene.instances[i].mesh;
      assert((range(mesh).x - meshRecords_[mesh].y) % 3 == 0 && "copies start on a triangle");
      ids.push_back(i);
      bases.push_back((range(mesh).x - meshRecords_[mesh].y) / 3);
    }
  }
  indirect_ = bufferOf("draw commands", commands);
  instanceIds_ = bufferOf("instance ids", ids);
  primitiveBases_ = bufferOf("primitive bases", bases);
  // Both per-instance attributes, divisor 1, offset by each command's baseInstance.
  const Buffer* attributes[2] = {&instanceIds_, &primitiveBases_};
  for (GLuint a = 0; a < 2; ++a) {
    glVertexArrayVertexBuffer(vao_.id(), a, attributes[a]->id(), 0, sizeof(std::uint32_t));
    glVertexArrayBindingDivisor(vao_.id(), a, 1);
    glEnableVertexArrayAttrib(vao_.id(), a);
    glVertexArrayAttribIFormat(vao_.id(), a, 1, GL_UNSIGNED_INT, 0);
    glVertexArrayAttribBinding(vao_.id(), a, a);
  }
}

int probeLodLevel(float texels) {
  for (std::size_t l = kProbeLodCells.size(); l-- > 0;)
    if (texels <= 2.0f * static_cast<float>(kProbeLodCells[l])) return static_cast<int>(l) + 1;
  return 0;
}

void GpuScene::ensureProbeLod(const Scene& scene) {
  if (lodLevels_ > 0 || instanceCount_ == 0) return;
  assert(meshRecords_.size() == scene.meshes.size() && "ensureProbeLod: the uploaded scene");
  std::vector<std::array<glm::uvec2, kProbeLodCells.size()>> copies(scene.meshes.size());
  std::vector<bool> wanted(scene.meshes.size(), false);
  for (const Instance& inst : scene.instances) wanted[inst.mesh] = wanted[inst.mesh] || !scene.meshes[inst.mesh].exact;
  std::vector<std::uint32_t> appended;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const glm::uvec4& record = meshRecords_[m];
    copies[m].fill(glm::uvec2(record.y, record.w));
    if (!wanted[m]) continue;
    for (std::size_t l = 0; l < kProbeLodCells.size(); ++l) {
      const std::vector<std::uint32_t> triangles = clusteredTriangles(scene.meshes[m], kProbeLodCells[l]);
      if (triangles.size() * 2 > scene.meshes[m].indices.size()) continue;  // saves too little: the mesh itself
      // Each copy after the meshes' own indices; its first index stays on a multiple of three.
      copies[m][l] = glm::uvec2(static_cast<std::uint32_t>(indexCount_ + appended.size()),
                                static_cast<std::uint32_t>(triangles.size() / 3));
      for (std::uint32_t v : triangles) appended.push_back(record.x + v);
    }
  }
  lodLevels_ = static_cast<int>(kProbeLodCells.size());
  if (!appended.empty()) {
    const std::size_t kept = indexCount_ * sizeof(std::uint32_t), added = appended.size() * sizeof(std::uint32_t);
    Buffer grown = createBuffer("indices", kept + added, nullptr);
    glCopyNamedBufferSubData(indices_.id(), grown.id(), 0, 0, static_cast<GLsizeiptr>(kept));
    glNamedBufferSubData(grown.id(), static_cast<GLintptr>(kept), static_cast<GLsizeiptr>(added), appended.data());
    indices_ = std::move(grown);
    indicesTex_ = createBufferTexture("indices view", GL_R32UI, indices_);
    glVertexArrayElementBuffer(vao_.id(), indices_.id());
    bytes_ += added;
  }
  writeDrawCommands(scene, copies);
}

// The sRGB array (base colour, emissive) and the linear one (normal maps), layer = scene texture index
// (what packMaterial stores) in both; a layer the other array's materials use stays empty.
void GpuScene::uploadTextures(const Scene& scene, bool anyTangents) {
  kdTextures_.reset();
  normalMaps_.reset();
  std::vector<bool> srgbLayer(scene.textures.size(), false), linearLayer(scene.textures.size(), false);
  auto mark = [&](std::vector<bool>& layers, int t) {
    if (t >= 0 && static_cast<std::size_t>(t) < layers.size()) layers[static_cast<std::size_t>(t)] = true;
  };
  bool anyEmissive = false;
  for (const Material& m : scene.materials) {
    mark(srgbLayer, m.kdTexture);
    mark(srgbLayer, m.emissiveTexture);
    mark(linearLayer, m.normalTexture);
    anyEmissive |= m.emissiveTexture >= 0;
  }
  kdTextures_ = uploadTextureArray(scene, srgbLayer, GL_SRGB8_ALPHA8, "kd textures");
  if (anyTangents) normalMaps_ = uploadTextureArray(scene, linearLayer, GL_RGBA8, "normal maps");
  features_.kdTextures = static_cast<bool>(kdTextures_);
  features_.emissiveTextures = anyEmissive && features_.kdTextures;
  features_.normalMaps = static_cast<bool>(normalMaps_);
}

Texture GpuScene::uploadTextureArray(const Scene& scene, const std::vector<bool>& layers, GLenum format,
                                     const char* label) {
  if (std::none_of(layers.begin(), layers.end(), [](bool b) { return b; })) return Texture();
  int w = 1, h = 1;
  for (std::size_t i = 0; i < scene.textures.size(); ++i)
    if (layers[i]) {
      w = std::max(w, scene.textures[i].width);
      h = std::max(h, scene.textures[i].height);
    }
  w = std::min(w, kMaxTextureSize);
  h = std::min(h, kMaxTextureSize);
  int levels = 1 + static_cast<int>(std::floor(std::log2(static_cast<float>(std::max(w, h)))));
  Texture array = createTexture2DArray(label, format, w, h, static_cast<int>(scene.textures.size()), levels);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (std::size_t i = 0; i < scene.textures.size(); ++i) {
    const tandem::Texture& t = scene.textures[i];
    if (!layers[i] || t.width <= 0 || t.height <= 0 ||
        t.rgba8.size() < static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height) * 4)
      continue;  // an empty layer samples as black; validateScene does not look inside textures
    std::vector<std::uint8_t> pixels = resizeRgba8(t, w, h);
    glTextureSubImage3D(array.id(), 0, 0, 0, static_cast<GLint>(i), w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glGenerateTextureMipmap(array.id());
  glTextureParameteri(array.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(array.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(array.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(array.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
  bytes_ += static_cast<std::size_t>(w) * h * 4 * scene.textures.size() * 4 / 3;
  return array;
}

// One row of TD_TOON_RAMP_SIZE texels per material, fetched by texel index (the C++ toonRampIndex).
void GpuScene::bakeRamps(const Scene& scene) {
  int rows = std::max<int>(1, static_cast<int>(scene.materials.size()));
  std::vector<float> ramps(static_cast<std::size_t>(rows) * TD_TOON_RAMP_SIZE, 0.0f);
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    shading::bakeToonRamp(scene.materials[m], &ramps[m * TD_TOON_RAMP_SIZE]);
  toonRamps_ = createTexture2D("toon ramps", GL_R32F, TD_TOON_RAMP_SIZE, rows);
  setSampling(toonRamps_, GL_NEAREST, GL_NEAREST);
  glTextureSubImage2D(toonRamps_.id(), 0, 0, 0, TD_TOON_RAMP_SIZE, rows, GL_RED, GL_FLOAT, ramps.data());
}

void GpuScene::updateInstances(const Scene& scene, float shutter, float u) {
  assert(static_cast<int>(scene.instances.size()) == instanceCount_ && "updateInstances: instance count changed");
  std::vector<GpuInstance> packed = packInstances(scene, probes_, anchor_, shutter, u);
  glNamedBufferSubData(instances_.id(), 0, static_cast<GLsizeiptr>(packed.size() * sizeof(GpuInstance)),
                       packed.data());
}

void GpuScene::setInstanceSlot(int slot) {
  assert((slot == 0 || slot == 1) && "setInstanceSlot: two slots");
  if (slot == slot_) return;
  if (!otherSlot_.records) {
    const std::size_t bytes = static_cast<std::size_t>(instanceCount_) * sizeof(GpuInstance);
    otherSlot_.records = createBuffer("instances (second slot)", bytes, nullptr);
    if (bytes > 0)
      glCopyNamedBufferSubData(instances_.id(), otherSlot_.records.id(), 0, 0, static_cast<GLsizeiptr>(bytes));
    otherSlot_.view = createBufferTexture("instances view (second slot)", GL_RGBA32F, otherSlot_.records);
    otherSlot_.idsView = createBufferTexture("instance ids view (second slot)", GL_RGBA32UI, otherSlot_.records);
  }
  std::swap(instances_, otherSlot_.records);
  std::swap(instancesTex_, otherSlot_.view);
  std::swap(instanceIdsTex_, otherSlot_.idsView);
  slot_ = slot;
}

void GpuScene::updateLights(const Scene& scene) {
  std::vector<shading::GpuLight> packed;
  features_.lightKinds = 0;
  features_.areaLights = false;
  int areaSlot = 0;
  for (const Light* l : scene.directLights()) {
    const bool area = isAreaLight(l->type);
    packed.push_back(shading::packLight(*l, areaSlot));
    areaSlot += area ? 1 : 0;
    features_.areaLights = features_.areaLights || area;
    const float type = packed.back().posType.w;
    packed.back().posType = glm::vec4(toRenderSpace(l->posW, anchor_), type);
    if (packed.size() <= TD_MAX_LIGHTS) {
      const int typeBits = area ? 0 : static_cast<int>(type);  // 2 bits: area lights read their record
      const auto code = static_cast<std::uint32_t>(typeBits | static_cast<int>(shadowMapKind(*l)) << 2);
      features_.lightKinds |= code << (4 * (packed.size() - 1));
    }
  }
  lightCount_ = static_cast<int>(packed.size());
  features_.lightCount = lightCount_;
  // Always TD_MAX_LIGHTS records: the uniform block declares that many, so a light turned ambient (or
  // back) only rewrites the contents.
  packed.resize(TD_MAX_LIGHTS, shading::GpuLight{});
  if (!lights_) {
    lights_ = bufferOf("lights", packed);
    return;
  }
  glNamedBufferSubData(lights_.id(), 0, static_cast<GLsizeiptr>(packed.size() * sizeof(shading::GpuLight)),
                       packed.data());
}

void GpuScene::updateMaterials(const Scene& scene, std::optional<ShadingModel> shadingOverride) {
  std::vector<shading::GpuMaterial> packed;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    packed.push_back(shading::packMaterial(scene.materials[m], static_cast<int>(m), shadingOverride));
  materials_ = bufferOf("materials", packed);
  std::vector<glm::mat4> uvTransforms;
  // Per-material record of 4 texels: the uv transform's columns (xyz) and, in the otherwise unused
  // fourth column, the transmission tint (rgb): GpuMaterial stays at 9 vec4s for the uniform block.
  for (const Material& m : scene.materials) {
    glm::mat4 record(m.uvTransform);
    record[3] = glm::vec4(m.transmissionTint, m.roughness);  // w: the probes' blur (docs/glossy.md)
    uvTransforms.push_back(record);
  }
  uvTransforms_ = bufferOf("uv transforms", uvTransforms);
  uvTransformsTex_ = createBufferTexture("uv transforms view", GL_RGBA32F, uvTransforms_);
  // Materials are indexed per pixel; from a uniform block llvmpipe gathers them with plain loads, from an
  // SSBO with a bounds-checked loop per lane. Scenes with more than fit keep the SSBO (a variant).
  GLint maxBlock = 0;
  glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &maxBlock);
  std::size_t bytes = packed.size() * sizeof(shading::GpuMaterial);
  features_.uniformMaterials = !packed.empty() && bytes <= static_cast<std::size_t>(maxBlock) ? static_cast<int>(packed.size()) : 0;
  bool anyToon = shadingOverride == ShadingModel::Toon ||
                 (!shadingOverride && std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
                   return m.shading == ShadingModel::Toon;
                 }));
  if (anyToon && !toonRamps_) bakeRamps(scene);
  features_.toon = anyToon;
  features_.gouraud = shadingOverride == ShadingModel::Gouraud ||
                      (!shadingOverride && std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
                        return m.shading == ShadingModel::Gouraud;
                      }));
  override_ = shadingOverride;
  // Single-sided opaque materials (glTF's default) draw with back faces culled, as the rays pass them
  // (passedFromBehind; exact solids are closed, and the rays see the solid): per command, for draw() to run
  // each stretch of equal sidedness as one call.
  drawCulled_.assign(drawInstance_.size(), 0);
  for (std::size_t k = 0; k < drawInstance_.size(); ++k) {
    const Instance& inst = scene.instances[drawInstance_[k]];
    drawCulled_[k] = inst.material < scene.materials.size() && passedFromBehind(scene.materials[inst.material]) &&
                             !scene.meshes[inst.mesh].exact
                         ? 1
                         : 0;
  }
  features_.alphaMask = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
    return m.alphaMode == AlphaMode::Mask && m.alphaCutoff > 0.0f;
  });
  features_.procedural = std::any_of(scene.materials.begin(), scene.materials.end(),
                                     [](const Material& m) { return m.procedural.type != Pattern::None; });
  features_.alphaBlend = std::any_of(scene.materials.begin(), scene.materials.end(), [](const Material& m) {
    return m.alphaMode == AlphaMode::Blend;
  });
}

void GpuScene::bind(GLuint kdUnit, GLuint rampUnit) const {
  const Buffer* buffers[] = {&positions_, &normals_, &uvs_, &colors_, &indices_,
                             &meshes_,    &instances_, &materials_, &lights_, &uvTransforms_};
  for (GLuint b = 0; b < std::size(buffers); ++b)
    if (*buffers[b]) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, buffers[b]->id());
  glBindTextureUnit(kdUnit, kdTextures_.id());
  glBindTextureUnit(rampUnit, toonRamps_.id());
  glBindTextureUnit(kUnitNormalMaps, normalMaps_.id());
}

void GpuScene::bindShading() const {
  const Texture* views[] = {&positionsTex_, &normalsTex_, &uvsTex_, &colorsTex_, &indicesTex_,
                            &meshesTex_, &instancesTex_, &instanceIdsTex_, &uvTransformsTex_};
  for (GLuint i = 0; i < std::size(views); ++i) glBindTextureUnit(kUnitPositionsTex + i, views[i]->id());
  glBindTextureUnit(kUnitTangentsTex, tangentsTex_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, kBlockLights, lights_.id());
  if (features_.uniformMaterials > 0) glBindBufferBase(GL_UNIFORM_BUFFER, kBlockMaterials, materials_.id());
}

void GpuScene::uploadRadiosity(const RadiosityField* field) {
  if (!field || field->empty()) {
    radiosityTable_ = {};
    radiosityValues_ = {};
    radiosityTableTex_ = {};
    radiosityValuesTex_ = {};
    radiosityVersion_ = 0;
    return;
  }
  if (field->version == radiosityVersion_) return;
  // Same sizes (more shots of one solve): the data goes into the buffers the views already show.
  const std::size_t tableBytes = field->table.size() * sizeof(glm::uvec2);
  const std::size_t valueBytes = field->values.size() * sizeof(glm::vec3);
  if (radiosityTable_ && radiosityBytes_ == glm::uvec2(tableBytes, valueBytes)) {
    glNamedBufferSubData(radiosityTable_.id(), 0, static_cast<GLsizeiptr>(tableBytes), field->table.data());
    glNamedBufferSubData(radiosityValues_.id(), 0, static_cast<GLsizeiptr>(valueBytes), field->values.data());
  } else {
    radiosityTable_ = bufferOf("radiosity table", field->table);
    radiosityValues_ = bufferOf("radiosity values", field->values);
    radiosityTableTex_ = createBufferTexture("radiosity table view", GL_RG32UI, radiosityTable_);
    radiosityValuesTex_ = createBufferTexture("radiosity values view", GL_RGB32F, radiosityValues_);
    radiosityBytes_ = glm::uvec2(tableBytes, valueBytes);
  }
  radiosityVersion_ = field->version == 0 ? 1 : field->version;
}

void GpuScene::bindRadiosity() const {
  glBindTextureUnit(kUnitRadiosityTableTex, radiosityTableTex_.id());
  glBindTextureUnit(kUnitRadiosityTex, radiosityValuesTex_.id());
}

void GpuScene::draw(Instances which, const std::vector<std::uint8_t>* seen) const {
  const int first = which == Instances::Dynamic ? staticDraws_ : 0;
  const int count = which == Instances::All ? staticDraws_ + dynamicDraws_
                    : which == Instances::Static ? staticDraws_
                                                 : dynamicDraws_;
  if (count == 0) return;
  assert((!seen || seen->size() == static_cast<std::size_t>(instanceCount_)) && "draw: one flag per instance");
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, indirect_.id());
  assert(drawCulled_.size() == drawInstance_.size() && "draw before updateMaterials");
  // Single-sided materials lose their back faces. Every view the scene is drawn in (the frame, probes' and
  // shadow maps' faces) is a proper rotation and projection, so a world-space counter-clockwise front is
  // one on screen too; the importers make mirrored instances' winding counter-clockwise in world space.
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  const int perBlock = staticDraws_ + dynamicDraws_;
  auto drawRange = [&](int from, int n, int level) {
    const bool cull = drawCulled_[static_cast<std::size_t>(from)] != 0;
    if (cull) glEnable(GL_CULL_FACE);
    else glDisable(GL_CULL_FACE);
    const auto command = static_cast<std::uintptr_t>(level * perBlock + from);
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(command * sizeof(DrawCommand)),
                                n, 0);
  };
  // Each run of neighbouring commands whose instances are seen at one level and share their sidedness: one call.
  // A culled instance would have drawn nothing (every fragment outside the view), so the target is the same
  // to the bit; what it saves is its vertices, which llvmpipe shades on one thread per draw.
  auto value = [&](int k) { return seen ? (*seen)[drawInstance_[static_cast<std::size_t>(k)]] : std::uint8_t{1}; };
  auto levelOf = [&](int k) { return std::min(std::max(int(value(k)) - 1, 0), lodLevels_); };
  for (int k = first; k < first + count;) {
    if (value(k) == 0) {
      ++k;
      continue;
    }
    int end = k + 1;
    while (end < first + count && value(end) != 0 && levelOf(end) == levelOf(k) &&
           drawCulled_[static_cast<std::size_t>(end)] == drawCulled_[static_cast<std::size_t>(k)])
      ++end;
    drawRange(k, end - k, levelOf(k));
    k = end;
  }
  glDisable(GL_CULL_FACE);  // as every other pass expects it
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindVertexArray(0);
}

}  // namespace tandem::gl
