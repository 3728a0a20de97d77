#pragma once
// The Embree device and the two-level Embree scene built from tandem::Scene: one static BLAS per mesh
// (built once, high quality), instanced into a top-level scene whose instances (static or dynamic) move
// by rtcSetGeometryTransform + a top-level commit. Owns every Embree handle it makes (RAII, move-only).
// Thread safety: const members may run from any number of threads; build/updateTransforms must not run
// while rays are in flight (Embree v3: never commit a scene that is being traced).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "core/Motion.h"
#include "core/ResolvedPixel.h"
#include "rt/SurfaceShading.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem::rt {

/// Embree devices and scenes this process holds (every one is owned by exactly one handle below), so
/// leak checks can ask for an exact count rather than infer it from memory.
std::size_t liveEmbreeHandles();

namespace detail {
void countHandle(int delta);
}

struct DeviceDeleter {
  void operator()(RTCDeviceTy* d) const {
    rtcReleaseDevice(d);
    detail::countHandle(-1);
  }
};
struct SceneDeleter {
  void operator()(RTCSceneTy* s) const {
    rtcReleaseScene(s);
    detail::countHandle(-1);
  }
};
using DeviceHandle = std::unique_ptr<RTCDeviceTy, DeviceDeleter>;
using SceneHandle = std::unique_ptr<RTCSceneTy, SceneDeleter>;
/// The only ways handles are made, so the count stays exact.
DeviceHandle newDevice(const char* config);
SceneHandle newScene(RTCDevice device);

/// The device with its error and memory callbacks. Errors go to tandem::log and are remembered so the
/// operation that caused them can return an error value.
class EmbreeDevice {
 public:
  static Result<std::unique_ptr<EmbreeDevice>> create();
  RTCDevice get() const { return device_.get(); }
  /// Forgets the last error; then firstError() says whether one happened since.
  void clearError();
  /// The first error since clearError(), as text ("" when none); also polls rtcGetDeviceError.
  std::string firstError();
  /// Embree allocations beyond this many bytes fail with RTC_ERROR_OUT_OF_MEMORY (0 = no limit).
  void setMemoryLimit(std::size_t bytes) { memoryLimit_.store(bytes); }
  std::size_t bytesInUse() const { return static_cast<std::size_t>(std::max<long long>(0, bytesInUse_.load())); }

 private:
  static void onError(void* self, RTCError code, const char* message);
  static bool onMemory(void* self, ssize_t bytes, bool post);
  DeviceHandle device_;
  std::atomic<long long> bytesInUse_{0};
  std::atomic<std::size_t> memoryLimit_{0};
  std::mutex errorMutex_;  // errors may come from Embree's build threads
  std::string errorText_;
};

class EmbreeScene {
 public:
  /// Builds every BLAS and the top level. Bad input (non-finite positions, indices out of range) and
  /// Embree errors (out of memory included) come back as an error value; nothing half-built escapes.
  /// `shutter`: the camera's (Camera::shutter); instances that move while it is open (Instance::velocity,
  /// angularVelocity) become Embree motion-blur instances with the time steps of core/Motion.h, and rays
  /// carry their time in [0, 1] (Camera::timeU, SurfaceHit::time).
  /// `anchor`: the origin of render space (none: the scene camera's position, renderAnchor).
  static Result<std::unique_ptr<EmbreeScene>> build(EmbreeDevice& device, const Scene& scene, float shutter = 0.0f,
                                                    std::optional<glm::vec3> anchor = std::nullopt);
  /// Moves instances to their current transforms and motions: per-geometry transform (or time steps) +
  /// top-level commit. A new `anchor` (the floating origin, core/RenderSpace.h) re-reads every instance.
  void updateTransforms(const Scene& scene, float shutter = 0.0f, std::optional<glm::vec3> anchor = std::nullopt);

  RTCScene top() const { return top_.get(); }
  /// The origin of render space (SurfaceShading.h, toRenderSpace): build's, or the last updateTransforms'.
  /// Rays given to top() and the transforms below are relative to it.
  glm::vec3 anchor() const { return anchor_; }
  /// The instance's transform in render space (a moving instance's at the middle of the shutter).
  const InstanceTransform& transform(std::size_t instance) const { return transforms_[instance]; }
  /// The instance's transform at shutter time u ∈ [0, 1] as Embree interpolates it (motionAt of its steps):
  /// what a ray with that time hits. transform(instance) for an instance at rest. Every hit asks, so an
  /// instance at rest costs no copy: a moving one's transform is made in a per-thread slot, valid until this
  /// thread's next call (use it within the expression that asked).
  const InstanceTransform& transformAt(std::size_t instance, float u) const {
    const std::vector<glm::mat4>& steps = motionSteps_[instance];
    if (steps.empty()) return transforms_[instance];
    thread_local InstanceTransform moving;
    moving = makeInstanceTransform(motionAt(steps, u));  // the steps are in render space already
    moving.anchor = anchor_;
    return moving;
  }
  /// Whether some instance moves while the shutter is open (rays then see it where their time puts it).
  bool hasMotion() const { return moving_ > 0; }
  /// The shutter the motion steps were made for.
  float shutter() const { return shutter_; }
  std::size_t instanceCount() const { return transforms_.size(); }
  /// Whether the instance's mesh has this triangle (guards ids read back from the rasterizer).
  bool hasTriangle(std::size_t instance, std::uint32_t triangle) const {
    return instance < triangleCounts_.size() && triangle < triangleCounts_[instance];
  }
  /// Whether the instance's mesh is an exact solid (Mesh::exact): rays see the solid, the raster its proxy.
  bool isExact(std::size_t instance) const { return instance < exactInstances_.size() && exactInstances_[instance] != 0; }
  /// Whether a visibility id (instance, triangle) names a surface of the scene: a triangle of the instance's
  /// mesh, or (kExactTriangle) a point on its exact solid, as the frame's resolve step writes them.
  bool hasPrimary(std::size_t instance, std::uint32_t triangle) const {
    return triangle == kExactTriangle ? isExact(instance) : hasTriangle(instance, triangle);
  }
  bool anyExact() const { return std::find(exactInstances_.begin(), exactInstances_.end(), 1) != exactInstances_.end(); }
  /// Whether any geometry carries the alpha-mask filter (a MASK material with a kd texture and uvs).
  bool hasAlphaMaskFilter() const { return !maskMaterials_.empty(); }
  /// Whether rays may pass through some of the instance's triangles: its alpha-mask filter rejects hits, or
  /// its material is single-sided and opaque, so a ray meeting a triangle from behind goes on.
  bool letsRaysThrough(std::size_t instance) const {
    return (instance < instanceMask_.size() && instanceMask_[instance] >= 0) ||
           (instance < cullSign_.size() && cullSign_[instance] != 0);
  }
  /// Alpha MASK test at a hit with Embree's barycentrics (u, v): false where the point is a cut-out hole
  /// (tdCoverage of the kd texture's alpha, sampled as shading samples it, below the cutoff).
  bool maskCovers(std::uint32_t instance, std::uint32_t mesh, std::uint32_t triangle, float u, float v) const;

 private:
  // MASK cut-outs (docs/gltf.md "Alpha modes"): the data the Embree filter reads, copied at build so it
  // does not depend on the Scene outliving this object. Only materials and meshes that need it are kept.
  struct MaskMaterial {
    shading::GpuMaterial packed;  // the alpha code tdCoverage reads
    glm::mat3 uvTransform{1.0f};
    Texture kdTexture;
  };
  struct MaskMesh {
    std::vector<std::uint32_t> indices;
    std::vector<glm::vec2> uvs;
  };
  struct MaskFilterUser {  // the filter's geometry user data: one per filtered BLAS geometry
    const EmbreeScene* owner = nullptr;
    std::uint32_t mesh = 0;
  };
  // Rejects hits on MASK holes and on single-sided opaque instances' back faces (seen from the light, for
  // the occlusion queries of shadow rays: kShadow).
  template <bool kShadow>
  static void faceFilter(const RTCFilterFunctionNArguments* args);
  // The steps of build, in order.
  void collectMaskCutouts(const Scene& scene);
  void collectSingleSided(const Scene& scene);
  Result<void> buildMeshScenes(EmbreeDevice& device, const Scene& scene, const std::string& where);
  Result<void> attachTriangles(EmbreeDevice& device, const Mesh& mesh, std::size_t m, RTCScene blas,
                               const std::string& where);
  Result<void> buildTopLevel(EmbreeDevice& device, const Scene& scene, const std::string& where);
  std::vector<MaskMaterial> maskMaterials_;
  std::vector<std::int32_t> instanceMask_;  // per instance: index into maskMaterials_, or -1
  std::vector<std::int32_t> meshMask_;      // per mesh: index into maskMeshes_, or -1
  std::vector<MaskMesh> maskMeshes_;
  std::vector<std::unique_ptr<MaskFilterUser>> maskUsers_;
  // Single-sided opaque instances (docs/gltf.md): per instance 0 (both sides are surfaces), or the sign s for
  // which a hit is from behind when s·(Ng·dir) > 0 in object space, where the filter sees the ray: -1 under a
  // mirroring transform (a front that is counter-clockwise in world space is clockwise in object space).
  std::vector<std::int8_t> cullSign_;
  std::vector<std::uint8_t> singleSided_;  // per instance: its material culls (the sign follows the transform)
  std::vector<std::uint8_t> meshCulled_;   // per mesh: some instance of it culls (its geometry gets the filter)
  // Exact solids (Mesh::exact, docs/csg.md): each one's tree, the user geometry's data. Owned here, so the
  // callbacks never depend on the Scene outliving this object.
  std::vector<std::unique_ptr<solid::Solid>> exactSolids_;
  Result<void> attachSolid(EmbreeDevice& device, const solid::Solid& solid, std::size_t m, RTCScene blas,
                           const std::string& where);
  std::vector<SceneHandle> meshScenes_;  // one BLAS per mesh
  SceneHandle top_;
  glm::vec3 anchor_{0.0f};
  bool rereadAll_ = false;  // a new anchor: every instance to be re-read (updateTransforms)
  std::vector<InstanceTransform> transforms_;  // the copy Embree holds (render space), used to rebuild hits
  std::vector<glm::mat4> worldFromObject_;     // the scene's world-space matrices, to detect moves
  std::vector<std::vector<glm::mat4>> motionSteps_;  // per instance: render-space time steps, empty at rest
  std::vector<glm::vec3> velocity_, angularVelocity_;  // the motions the steps were made from
  float shutter_ = 0.0f;
  std::size_t moving_ = 0;
  // An instance's transform, or time steps when it moves (geometry already attached or not).
  void setInstanceMotion(RTCGeometry geom, std::size_t i, const Instance& inst);
  std::vector<std::size_t> triangleCounts_;
  std::vector<std::uint8_t> exactInstances_;  // per instance: 1 where its mesh is an exact solid
};

}  // namespace tandem::rt
