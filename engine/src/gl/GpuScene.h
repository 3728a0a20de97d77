#pragma once
// The GL copy of a Scene: every mesh in one set of shared vertex / index buffers (SSBOs the shade pass
// reads by vertex number), per-instance transforms, packed materials and lights, the kd texture array
// and the toon ramps. A cache: rebuilt by upload(), patched by the update*() calls, never the source
// of truth. Only channels the scene uses are allocated (absent ones get a 16-byte stand-in binding).
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "gl/Bindings.h"
#include "gl/GlObjects.h"
#include "core/Environment.h"
#include "core/Radiosity.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::gl {

// Binding points and texture units: gl/Bindings.h (shaders/bindings.glsl).

/// The map a direct light gets when it casts shadows (ShadowMaps; shade.frag's TD_SHADOW_*): orthographic
/// for directional lights, perspective for spots up to kMaxSpotMapDeg, a cube for point lights and wider
/// spots, since a square frustum around a wider cone wastes most of its texels.
enum class ShadowMapKind : int { None = 0, Ortho = 1, Perspective = 2, Cube = 3 };
inline constexpr float kMaxSpotMapDeg = 60.0f;
inline ShadowMapKind shadowMapKind(const Light& light) {
  if (light.type == LightType::Directional) return ShadowMapKind::Ortho;
  if (light.type == LightType::Spot && light.outerConeDeg <= kMaxSpotMapDeg) return ShadowMapKind::Perspective;
  return ShadowMapKind::Cube;
}

/// What the scene uses, for choosing the shade pass's variant.
struct SceneFeatures {
  bool uvs = false, colors = false, kdTextures = false;
  bool normalMaps = false;     // some material has a normal map and a mesh using it has tangents
  bool emissiveTextures = false;
  bool alphaMask = false;      // some material is MASK with a cutoff: the visibility pass discards
  bool alphaBlend = false;     // some material is BLEND: coverage scales local shading
  bool gouraud = false, toon = false;  // after the shading override
  int lightCount = 0;          // direct lights: the shade loop's compile-time bound
  /// Direct light j's type and shadow-map kind, 4 bits each (shade.frag's TD_LIGHT_KINDS): the shade
  /// pass compiles only the code of the lights the scene has. Light j's type (TD_LIGHT_*) is in bits
  /// 4j..4j+1 (0 for an area light, whose type the shader reads from its record), the kind of map it
  /// casts with (shadowMapKind) in bits 4j+2..4j+3.
  std::uint32_t lightKinds = 0;
  bool areaLights = false;     // some direct light is an area light: the shade pass compiles their sampling
  int uniformMaterials = 0;    // material count when they fit a uniform block, else 0 (SSBO)
  bool exact = false;          // some instance is an exact solid: ids may name a hit on it (TD_EXACT_TRIANGLE)
  bool procedural = false;     // some material has a procedural texture (procedural.glsl is compiled in)
  bool environment = false;         // the environment varies with direction (a sky or an image)
  bool environmentAmbient = false;  // and lights the ambient term (EnvironmentLookup::lightsAmbient)
};

/// Instances that look reflections up in a probe (their material has kr > 0 or kt > 0, or is BLEND).
std::vector<std::uint32_t> probeInstances(const Scene& scene);

/// Which probes a scene gets (FrameSettings::probeLimit): every probeInstances instance while there are no
/// more than `limit`; past it, `limit` of them chosen far apart (the largest first, then each the farthest
/// from those chosen: farthest-point sampling of their bounds' centres), the others sharing the nearest one's.
struct ProbeLayout {
  std::vector<std::uint32_t> probes;  // per slot: the instance its probe is drawn for (from its centre, without it)
  std::vector<std::int32_t> slotOf;   // per instance: the slot its reflections are looked up in, -1 for none
};
ProbeLayout probeLayout(const Scene& scene, int limit);

/// The coarse copies a probe's face draws small objects with (GpuScene::ensureProbeLod): level l + 1 has each
/// mesh's vertices clustered in kProbeLodCells[l] cells along its bounds' longest side (core/MeshLod.h).
inline constexpr std::array<int, 2> kProbeLodCells = {16, 4};
/// The level a face draws an object with whose bounds span at most `texels` texels of it: the coarsest whose
/// cells are no more than two texels there, 0 (the mesh itself) when none is.
int probeLodLevel(float texels);

class GpuScene {
 public:
  /// `anchor`: the origin of render space (core/RenderSpace.h; none: the scene camera's position).
  /// `probeLimit`: FrameSettings::probeLimit, which the probe layout (probes()) follows.
  void upload(const Scene& scene, std::optional<ShadingModel> shadingOverride,
              std::optional<glm::vec3> anchor = std::nullopt, int probeLimit = FrameSettings{}.probeLimit);
  /// The probes and the slot each instance reads (the shade pass finds it in GpuInstance.meshMaterial.z, slot
  /// + 1, 0 for none), as upload() laid them out.
  const ProbeLayout& probes() const { return probes_; }
  int probeLimit() const { return probeLimit_; }
  /// A new origin of render space (the floating origin: anchorDue): instances and lights are held relative to
  /// the anchor, so the caller re-packs both (updateInstances, updateLights) before the next draw.
  void setAnchor(glm::vec3 anchor) { anchor_ = anchor; }
  /// Rewrites every instance record (a few hundred bytes each): cheaper than tracking which moved. With a
  /// shutter (Camera::shutter), instances that move while it is open are drawn where time u ∈ [0, 1] of it
  /// puts them (core/Motion.h motionAt, the transform the ray scene gives rays of that time).
  void updateInstances(const Scene& scene, float shutter = 0.0f, float u = 0.5f);
  /// Throughput mode (docs/pipeline.md): two sets of instance records, so that the frame in flight is shaded
  /// with the transforms it was drawn with while the next frame is drawn with its own. The slot (0 or 1)
  /// selects the set bind(), bindShading() and updateInstances() use; slot 1 is made on first use as a copy
  /// of slot 0's records, and upload() drops it.
  int instanceSlot() const { return slot_; }
  void setInstanceSlot(int slot);
  /// Frees the slot not in use; the one in use becomes slot 0.
  void dropOtherInstanceSlot() {
    otherSlot_ = {};
    slot_ = 0;
  }
  void updateLights(const Scene& scene);
  /// Re-packs materials when the shading override changes.
  void updateMaterials(const Scene& scene, std::optional<ShadingModel> shadingOverride);

  /// Binds the SSBOs and textures (kd array on unit `kdUnit`, ramps on `rampUnit`). The kd array holds
  /// every sRGB texture (base colour and emissive), layer = Scene::textures index.
  void bind(GLuint kdUnit, GLuint rampUnit) const;
  /// What the shade pass reads besides bind(): buffer-texture views (kUnit*Tex) and uniform blocks.
  void bindShading() const;
  /// The radiosity solution the shade pass reads (TD_USE_RADIOSITY; core/Radiosity.h), uploaded when its
  /// version differs from the one held; null releases it.
  void uploadRadiosity(const RadiosityField* field);
  bool hasRadiosity() const { return radiosityVersion_ != 0; }
  /// The version of the solution held (RadiosityField::version), 0 for none.
  std::uint64_t radiosityVersion() const { return radiosityVersion_; }
  void bindRadiosity() const;
  /// All instances in one glMultiDrawElementsIndirect; the visibility shader reads the instance from a
  /// per-instance attribute offset by each command's baseInstance.
  void drawAll() const { draw(Instances::All); }
  /// Which instances a draw takes: all, those not marked Instance::dynamic, or only those (the raster
  /// effects keep what the static ones draw and draw the dynamic ones over it).
  enum class Instances { All, Static, Dynamic };
  /// With `seen` (one value per instance), only the instances it marks: 0 not drawn, 1 drawn, 1 + l drawn with
  /// the coarse copy of level l (probeLodLevel; as 1 before ensureProbeLod): a face's culled draw (seenBy).
  /// Single-sided opaque materials (passedFromBehind) lose their back faces, in views and in a light's shadow
  /// maps alike (a face turned away from the light lets its light through, docs/gltf.md).
  void draw(Instances which, const std::vector<std::uint8_t>* seen = nullptr) const;
  int dynamicCount() const { return dynamicDraws_; }
  /// Makes the coarse copies of the meshes (kProbeLodCells) the first time a probe is drawn, not at upload:
  /// presets without raster reflections never pay for them. They index the meshes' own vertices and follow
  /// the meshes' triangles in the index buffer; a face's visibility ids name their triangles past the mesh's
  /// own (the shade pass reads them there). A copy that would keep more than half of a mesh's triangles is
  /// not made (that level draws the mesh), nor is one of an exact solid.
  void ensureProbeLod(const Scene& scene);

  int instanceCount() const { return instanceCount_; }
  int lightCount() const { return lightCount_; }
  bool hasKdTextures() const { return static_cast<bool>(kdTextures_); }
  std::optional<ShadingModel> shadingOverride() const { return override_; }
  /// The render-space anchor (core/RenderSpace.h), upload()'s or setAnchor()'s: instance transforms and lights
  /// are held relative to it, so cameras, bounds and lights handed to the passes must be too.
  glm::vec3 anchor() const { return anchor_; }
  const SceneFeatures& features() const { return features_; }
  /// The scene's environment (docs/environment.md) and its image's texture (TD_UNIT_ENVIRONMENT; 0: none).
  const EnvironmentLookup& environment() const { return environment_; }
  GLuint environmentMap() const { return environmentMap_ ? environmentMap_.id() : 0; }
  std::size_t gpuBytes() const { return bytes_; }

 private:
  // The steps of upload() after the geometry.
  void uploadInstances(const Scene& scene, const std::vector<glm::uvec4>& meshes);
  void uploadEnvironment(const Scene& scene);
  void uploadTextures(const Scene& scene, bool anyTangents);
  void bakeRamps(const Scene& scene);
  /// A mipmapped RGBA8 array (`format` sRGB or linear) with scene.textures[i] in layer i where layers[i];
  /// empty when no layer is wanted.
  Texture uploadTextureArray(const Scene& scene, const std::vector<bool>& layers, GLenum format, const char* label);

  Buffer positions_, normals_, uvs_, colors_, indices_, meshes_, instances_, materials_, lights_, uvTransforms_,
      tangents_;
  Buffer indirect_, instanceIds_;  // one draw command per instance: the static ones first, then the dynamic ones
  int staticDraws_ = 0, dynamicDraws_ = 0;
  std::vector<std::uint32_t> drawInstance_;  // the instance each draw command draws
  std::vector<std::uint8_t> drawCulled_;     // per command: its material is single-sided (back faces culled)
  // Per command block (0: the meshes, l: level l's copies) the draw commands follow one another: block l's
  // command k draws drawInstance_[k]; its baseInstance is l·instances + instance, where the instance ids and
  // the primitive bases (what the copy's triangle numbers are offset by) are read.
  // `copies`: per mesh and level, its copy's first index and triangles (none: block 0 alone).
  void writeDrawCommands(const Scene& scene, const std::vector<std::array<glm::uvec2, kProbeLodCells.size()>>& copies);
  std::vector<glm::uvec4> meshRecords_;  // packGeometry's: first vertex, first index, flags, triangles
  Buffer primitiveBases_;
  int lodLevels_ = 0;                    // command blocks past the first (kProbeLodCells.size() once made)
  std::size_t indexCount_ = 0;
  ProbeLayout probes_;
  int probeLimit_ = FrameSettings{}.probeLimit;
  // Views of the buffers above for the shade pass (see createBufferTexture).
  Texture positionsTex_, normalsTex_, uvsTex_, colorsTex_, indicesTex_, meshesTex_, instancesTex_, instanceIdsTex_,
      uvTransformsTex_, tangentsTex_;
  VertexArray vao_;
  Texture kdTextures_, toonRamps_, normalMaps_;
  EnvironmentLookup environment_;
  Texture environmentMap_;
  Buffer radiosityTable_, radiosityValues_;
  Texture radiosityTableTex_, radiosityValuesTex_;
  std::uint64_t radiosityVersion_ = 0;  // RadiosityField::version held; 0: none
  glm::uvec2 radiosityBytes_{0u};       // the two buffers' sizes
  // The instance records of the slot not in use (instances_ and its two views are the slot in use).
  struct InstanceSet {
    Buffer records;
    Texture view, idsView;
  };
  InstanceSet otherSlot_;
  int slot_ = 0;
  int instanceCount_ = 0;
  int lightCount_ = 0;
  std::optional<ShadingModel> override_;
  glm::vec3 anchor_{0.0f};
  SceneFeatures features_;
  std::size_t bytes_ = 0;
};

}  // namespace tandem::gl
