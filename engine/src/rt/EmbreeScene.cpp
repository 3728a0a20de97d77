#include "rt/EmbreeScene.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "core/RenderSpace.h"
#include "core/Solids.h"
#include "rt/Parallel.h"
#include "rt/RayMath.h"
#include "tandem/Log.h"

namespace tandem::rt {

namespace {

const char* errorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "none";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

std::atomic<long long> gLiveHandles{0};

}  // namespace

namespace detail {
void countHandle(int delta) { gLiveHandles.fetch_add(delta, std::memory_order_relaxed); }
}  // namespace detail

std::size_t liveEmbreeHandles() { return static_cast<std::size_t>(std::max<long long>(0, gLiveHandles.load())); }

DeviceHandle newDevice(const char* config) {
  RTCDevice d = rtcNewDevice(config);
  if (d) detail::countHandle(+1);
  return DeviceHandle(d);
}

SceneHandle newScene(RTCDevice device) {
  RTCScene s = rtcNewScene(device);
  if (s) detail::countHandle(+1);
  return SceneHandle(s);
}

bool EmbreeScene::maskCovers(std::uint32_t instance, std::uint32_t mesh, std::uint32_t triangle, float u, float v) const {
  if (instance >= instanceMask_.size() || instanceMask_[instance] < 0 || mesh >= meshMask_.size() || meshMask_[mesh] < 0)
    return true;  // this instance's material has no cut-outs (another instance of the mesh may)
  const MaskMaterial& mat = maskMaterials_[static_cast<std::size_t>(instanceMask_[instance])];
  const MaskMesh& mm = maskMeshes_[static_cast<std::size_t>(meshMask_[mesh])];
  std::size_t t = 3 * static_cast<std::size_t>(triangle);
  if (t + 2 >= mm.indices.size()) return true;
  // Embree's barycentrics: p = (1 − u − v)·p0 + u·p1 + v·p2; the uv interpolated as resolveHit does.
  glm::vec2 uv = (1.0f - u - v) * mm.uvs[mm.indices[t]] + u * mm.uvs[mm.indices[t + 1]] + v * mm.uvs[mm.indices[t + 2]];
  uv = glm::vec2(mat.uvTransform * glm::vec3(uv, 1.0f));
  float texA = sampleBilinear(mat.kdTexture, uv).a;
  return shading::tdCoverage(mat.packed, texA) > 0.0f;
}

// Intersection and occlusion filters of geometries with MASK cut-outs or single-sided instances: a hit on a
// hole, or on a single-sided opaque face from behind, is rejected and the ray goes on (shadow, reflection
// and refraction rays see what the raster's discards and face culling leave). An occlusion query is a
// shadow ray, traced from the surface but standing for the light's: a face blocks it when the face's front
// is towards the light, the ray's far end (as a shadow map drawn with back faces culled holds it), so a
// roof made of one single-sided plane still shades the room under it.
template <bool kShadow>
void EmbreeScene::faceFilter(const RTCFilterFunctionNArguments* args) {
  const auto* user = static_cast<const MaskFilterUser*>(args->geometryUserPtr);
  const EmbreeScene& owner = *user->owner;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const std::uint32_t instance = RTCHitN_instID(args->hit, args->N, i, 0);
    if (instance < owner.cullSign_.size() && owner.cullSign_[instance] != 0) {
      // Embree's Ng is the counter-clockwise normal; ray and Ng are both in the instance's object space here.
      const float along = RTCHitN_Ng_x(args->hit, args->N, i) * RTCRayN_dir_x(args->ray, args->N, i) +
                          RTCHitN_Ng_y(args->hit, args->N, i) * RTCRayN_dir_y(args->ray, args->N, i) +
                          RTCHitN_Ng_z(args->hit, args->N, i) * RTCRayN_dir_z(args->ray, args->N, i);
      if (float(owner.cullSign_[instance]) * (kShadow ? -along : along) > 0.0f) {
        args->valid[i] = 0;
        continue;
      }
    }
    std::uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    if (!owner.maskCovers(instance, user->mesh, prim, u, v)) args->valid[i] = 0;
  }
}

Result<std::unique_ptr<EmbreeDevice>> EmbreeDevice::create() {
  auto d = std::unique_ptr<EmbreeDevice>(new EmbreeDevice());
  // TANDEM_EMBREE_CONFIG: Embree's own device configuration (its rtcNewDevice string, e.g. "hugepages=1" or
  // "set_affinity=1"), for measuring its performance switches on a machine (docs/bench.md); unset: defaults.
  const char* config = std::getenv("TANDEM_EMBREE_CONFIG");
  d->device_ = newDevice(config);
  if (!d->device_) {
    RTCError code = rtcGetDeviceError(nullptr);
    std::string message = std::string("Embree: cannot create a device (") + errorName(code) + ")";
    logError(message);
    return Error{message};
  }
  rtcSetDeviceErrorFunction(d->device_.get(), &EmbreeDevice::onError, d.get());
  rtcSetDeviceMemoryMonitorFunction(d->device_.get(), &EmbreeDevice::onMemory, d.get());
  publishToBuilders(d.get());  // the callbacks run on Embree's build threads too
  return d;
}

void EmbreeDevice::onError(void* self, RTCError code, const char* message) {
  receivedFromBuilder(self);
  auto* d = static_cast<EmbreeDevice*>(self);
  std::string text = std::string("Embree ") + errorName(code) + (message ? std::string(": ") + message : std::string());
  logError(text);
  std::lock_guard<std::mutex> lock(d->errorMutex_);
  if (d->errorText_.empty()) d->errorText_ = text;
}

bool EmbreeDevice::onMemory(void* self, ssize_t bytes, bool /*post*/) {
  receivedFromBuilder(self);
  auto* d = static_cast<EmbreeDevice*>(self);
  std::size_t limit = d->memoryLimit_.load();
  if (bytes > 0 && limit > 0) {
    long long after = d->bytesInUse_.fetch_add(bytes) + bytes;
    if (after > static_cast<long long>(limit)) {
      // Refused: Embree cancels the call with RTC_ERROR_OUT_OF_MEMORY (reported through onError).
      d->bytesInUse_.fetch_sub(bytes);
      return false;
    }
    return true;
  }
  d->bytesInUse_.fetch_add(bytes);
  return true;
}

void EmbreeDevice::clearError() {
  rtcGetDeviceError(device_.get());  // reading it resets Embree's own sticky code
  std::lock_guard<std::mutex> lock(errorMutex_);
  errorText_.clear();
}

std::string EmbreeDevice::firstError() {
  RTCError code = rtcGetDeviceError(device_.get());
  std::lock_guard<std::mutex> lock(errorMutex_);
  if (errorText_.empty() && code != RTC_ERROR_NONE) errorText_ = std::string("Embree ") + errorName(code);
  return errorText_;
}

namespace {

// Bad input is refused here, before Embree sees it: Debian's Embree does not skip invalid data.
Result<void> checkEmbreeInput(const Scene& scene, const std::string& where) {
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.indices.size() % 3 != 0)
      return Error{where + ": mesh " + std::to_string(m) + ": index count is not a multiple of 3"};
    for (std::uint32_t i : mesh.indices)
      if (i >= mesh.positions.size())
        return Error{where + ": mesh " + std::to_string(m) + ": index " + std::to_string(i) + " out of range"};
    for (const glm::vec3& p : mesh.positions)
      if (!isFinite(p)) return Error{where + ": mesh " + std::to_string(m) + ": a position is NaN or infinite"};
    if (mesh.exact)
      if (const std::string bad = solid::validate(*mesh.exact); !bad.empty())
        return Error{where + ": mesh " + std::to_string(m) + ": exact solid: " + bad};
  }
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.mesh >= scene.meshes.size() || inst.material >= scene.materials.size())
      return Error{where + ": instance " + std::to_string(i) + ": mesh or material index out of range"};
    if (!isFinite(inst.velocity) || !isFinite(inst.angularVelocity))
      return Error{where + ": instance " + std::to_string(i) + ": motion is NaN or infinite"};
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(inst.worldFromObject[c].x) || !std::isfinite(inst.worldFromObject[c].y) ||
          !std::isfinite(inst.worldFromObject[c].z) || !std::isfinite(inst.worldFromObject[c].w))
        return Error{where + ": instance " + std::to_string(i) + ": transform is NaN or infinite"};
  }
  return {};
}

Error embreeFailure(EmbreeDevice& device, const std::string& where, const std::string& what) {
  std::string e = device.firstError();
  return Error{where + ": " + what + ": " + (e.empty() ? std::string("Embree failed") : e)};
}

}  // namespace

Result<std::unique_ptr<EmbreeScene>> EmbreeScene::build(EmbreeDevice& device, const Scene& scene, float shutter,
                                                        std::optional<glm::vec3> anchor) {
  device.clearError();
  const std::string where = scene.name.empty() ? std::string("scene") : "scene '" + scene.name + "'";
  if (auto checked = checkEmbreeInput(scene, where); !checked) return checked.error();

  auto out = std::unique_ptr<EmbreeScene>(new EmbreeScene());
  // Camera-relative: positions are kept relative to where the camera is, so their precision follows
  // the distance to the viewer rather than to the world origin (docs/numerics.md, "Position").
  out->anchor_ = anchor ? *anchor : renderAnchor(scene);
  out->shutter_ = shutter > 0.0f && std::isfinite(shutter) ? shutter : 0.0f;
  out->collectMaskCutouts(scene);
  out->collectSingleSided(scene);
  if (auto built = out->buildMeshScenes(device, scene, where); !built) return built.error();
  if (auto built = out->buildTopLevel(device, scene, where); !built) return built.error();
  return out;
}

// MASK cut-outs: which instances test a texture's alpha, and which meshes therefore need the filter.
// Cost follows the scene: geometries with no MASK instance get no filter at all.
void EmbreeScene::collectMaskCutouts(const Scene& scene) {
  instanceMask_.assign(scene.instances.size(), -1);
  meshMask_.assign(scene.meshes.size(), -1);
  std::vector<std::int32_t> materialMask(scene.materials.size(), -1);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Material& mat = scene.materials[inst.material];
    const Mesh& mesh = scene.meshes[inst.mesh];
    shading::GpuMaterial packed = shading::packMaterial(mat, static_cast<int>(inst.material), std::nullopt);
    bool masked = mat.alphaMode == AlphaMode::Mask && packed.texAlpha.w > 0.0f;
    // Without a texture (or uvs) the coverage is uniform: opacity ≥ cutoff keeps all, else nothing passes.
    if (!masked) continue;
    bool textured = mat.kdTexture >= 0 && static_cast<std::size_t>(mat.kdTexture) < scene.textures.size() &&
                    !mesh.uvs.empty() && mesh.uvs.size() == mesh.positions.size();
    if (!textured && shading::tdCoverage(packed, 1.0f) > 0.0f) continue;
    if (materialMask[inst.material] < 0) {
      MaskMaterial mm;
      mm.packed = packed;
      mm.uvTransform = mat.uvTransform;
      if (textured) mm.kdTexture = scene.textures[static_cast<std::size_t>(mat.kdTexture)];
      else {
        mm.kdTexture.width = mm.kdTexture.height = 1;  // uniform: one white texel, alpha 1
        mm.kdTexture.rgba8 = {255, 255, 255, 255};
      }
      materialMask[inst.material] = static_cast<std::int32_t>(maskMaterials_.size());
      maskMaterials_.push_back(std::move(mm));
    }
    instanceMask_[i] = materialMask[inst.material];
    if (meshMask_[inst.mesh] < 0) {
      MaskMesh mm;
      mm.indices = mesh.indices;
      mm.uvs = textured ? mesh.uvs : std::vector<glm::vec2>(mesh.positions.size(), glm::vec2(0.0f));
      meshMask_[inst.mesh] = static_cast<std::int32_t>(maskMeshes_.size());
      maskMeshes_.push_back(std::move(mm));
    }
  }
}

// Single-sided instances whose rays pass their back faces: opaque materials only, since a transmissive
// volume (glass, glTF's single-sided by default) refracts at its inner faces. Exact solids are closed and
// have no faces to cull. The sign follows the transform (setInstanceMotion).
void EmbreeScene::collectSingleSided(const Scene& scene) {
  singleSided_.assign(scene.instances.size(), 0);
  cullSign_.assign(scene.instances.size(), 0);
  meshCulled_.assign(scene.meshes.size(), 0);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Material& mat = scene.materials[inst.material];
    if (!passedFromBehind(mat) || scene.meshes[inst.mesh].exact) continue;
    singleSided_[i] = 1;
    meshCulled_[inst.mesh] = 1;
  }
}

Result<void> EmbreeScene::buildMeshScenes(EmbreeDevice& device, const Scene& scene, const std::string& where) {
  RTCDevice dev = device.get();
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    SceneHandle blas = newScene(dev);
    if (!blas) return embreeFailure(device, where, "mesh " + std::to_string(m));
    // Static geometry traced for many frames: spend build time for traversal speed. ROBUST makes
    // traversal watertight, so shared edges never leak a ray (shadows and refraction through meshes), and
    // conservative, so whether a ray meets a triangle does not depend on the tree or on which rays share
    // its packet: reuse across frames keeps answers on that premise (docs/reuse.md).
    rtcSetSceneBuildQuality(blas.get(), RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(blas.get(), RTC_SCENE_FLAG_ROBUST);
    // An exact solid replaces its triangles for the rays (they are the raster's proxy).
    if (mesh.exact) {
      if (auto attached = attachSolid(device, *mesh.exact, m, blas.get(), where); !attached) return attached.error();
    } else if (mesh.triangleCount() > 0) {
      if (auto attached = attachTriangles(device, mesh, m, blas.get(), where); !attached) return attached.error();
    }
    rtcCommitScene(blas.get());
    if (!device.firstError().empty()) return embreeFailure(device, where, "mesh " + std::to_string(m));
    meshScenes_.push_back(std::move(blas));
  }
  return {};
}

Result<void> EmbreeScene::attachTriangles(EmbreeDevice& device, const Mesh& mesh, std::size_t m, RTCScene blas,
                                          const std::string& where) {
  RTCDevice dev = device.get();
  std::size_t triangles = mesh.triangleCount();
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!geom) return embreeFailure(device, where, "mesh " + std::to_string(m));
  // Embree-allocated buffers carry the readable padding after the last vertex that its SIMD loads need.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.positions.size()));
  auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), triangles));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geom);
    return embreeFailure(device, where, "mesh " + std::to_string(m) + " buffers");
  }
  std::memcpy(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  // Every triangle keeps its slot, degenerate ones included, so primID = the mesh's triangle index
  // (the rasterizer's gl_PrimitiveID); Embree itself never reports a zero-area triangle as hit.
  std::memcpy(indices, mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  // Cost follows the scene: a mesh no MASK or single-sided instance uses gets no filter.
  if (meshMask_[m] >= 0 || meshCulled_[m] != 0) {
    auto& user = maskUsers_.emplace_back(std::make_unique<MaskFilterUser>());
    user->owner = this;
    user->mesh = static_cast<std::uint32_t>(m);
    rtcSetGeometryUserData(geom, user.get());
    rtcSetGeometryIntersectFilterFunction(geom, &faceFilter<false>);
    rtcSetGeometryOccludedFilterFunction(geom, &faceFilter<true>);
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(blas, geom, 0);
  rtcReleaseGeometry(geom);
  return {};
}

namespace {

// Exact solids as Embree user geometry: one primitive per solid, its crossings found by core/Solids in
// double precision from the ray Embree hands over (in the instance's object space).
void solidBounds(const RTCBoundsFunctionArguments* args) {
  receivedFromBuilder(args->geometryUserPtr);
  const auto& s = *static_cast<const solid::Solid*>(args->geometryUserPtr);
  const solid::Bounds b = solid::bounds(s);
  // Outward by a little more than float rounding, and within what Embree's float boxes hold (a half-space
  // reaches 1e30 in its own space: clamped to 1e18).
  auto out = [](double v, double toward) {
    const double c = std::clamp(v, -1e18, 1e18);
    return static_cast<float>(c + toward * (1e-6 * std::abs(c) + 1e-30));
  };
  args->bounds_o->lower_x = out(b.lo.x, -1.0);
  args->bounds_o->lower_y = out(b.lo.y, -1.0);
  args->bounds_o->lower_z = out(b.lo.z, -1.0);
  args->bounds_o->upper_x = out(b.hi.x, 1.0);
  args->bounds_o->upper_y = out(b.hi.y, 1.0);
  args->bounds_o->upper_z = out(b.hi.z, 1.0);
}

template <class Rays>
bool firstSolidCrossing(const solid::Solid& s, Rays* rays, unsigned n, unsigned k, solid::Crossing& hit) {
  const solid::Ray ray{{RTCRayN_org_x(rays, n, k), RTCRayN_org_y(rays, n, k), RTCRayN_org_z(rays, n, k)},
                       {RTCRayN_dir_x(rays, n, k), RTCRayN_dir_y(rays, n, k), RTCRayN_dir_z(rays, n, k)}};
  return solid::firstHit(solid::intersect(s, ray), RTCRayN_tnear(rays, n, k), RTCRayN_tfar(rays, n, k), hit);
}

void solidIntersect(const RTCIntersectFunctionNArguments* args) {
  const auto& s = *static_cast<const solid::Solid*>(args->geometryUserPtr);
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] != -1) continue;
    solid::Crossing c;
    if (!firstSolidCrossing(s, rays, args->N, k, c)) continue;
    RTCRayN_tfar(rays, args->N, k) = static_cast<float>(c.t);
    RTCHitN_Ng_x(hits, args->N, k) = static_cast<float>(c.normal.x);
    RTCHitN_Ng_y(hits, args->N, k) = static_cast<float>(c.normal.y);
    RTCHitN_Ng_z(hits, args->N, k) = static_cast<float>(c.normal.z);
    RTCHitN_u(hits, args->N, k) = 0.0f;
    RTCHitN_v(hits, args->N, k) = 0.0f;
    RTCHitN_primID(hits, args->N, k) = args->primID;
    RTCHitN_geomID(hits, args->N, k) = args->geomID;
    RTCHitN_instID(hits, args->N, k, 0) = args->context->instID[0];
  }
}

void solidOccluded(const RTCOccludedFunctionNArguments* args) {
  const auto& s = *static_cast<const solid::Solid*>(args->geometryUserPtr);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] != -1) continue;
    solid::Crossing c;
    if (firstSolidCrossing(s, args->ray, args->N, k, c))
      RTCRayN_tfar(args->ray, args->N, k) = -std::numeric_limits<float>::infinity();
  }
}

}  // namespace

Result<void> EmbreeScene::attachSolid(EmbreeDevice& device, const solid::Solid& s, std::size_t m, RTCScene blas,
                                      const std::string& where) {
  RTCGeometry geom = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_USER);
  if (!geom) return embreeFailure(device, where, "mesh " + std::to_string(m) + " (exact solid)");
  auto& owned = exactSolids_.emplace_back(std::make_unique<solid::Solid>(s));
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  rtcSetGeometryUserData(geom, owned.get());
  publishToBuilders(owned.get());  // read by solidBounds on Embree's build threads
  rtcSetGeometryBoundsFunction(geom, &solidBounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, &solidIntersect);
  rtcSetGeometryOccludedFunction(geom, &solidOccluded);
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(blas, geom, 0);
  rtcReleaseGeometry(geom);
  return {};
}

Result<void> EmbreeScene::buildTopLevel(EmbreeDevice& device, const Scene& scene, const std::string& where) {
  RTCDevice dev = device.get();
  top_ = newScene(dev);
  if (!top_) return embreeFailure(device, where, "top level");
  // The top level is rebuilt whenever an instance moves: a fast build beats a better tree there. ROBUST
  // here too: a rebuilt top level must not change what an unmoved instance's triangles answer (reuse).
  rtcSetSceneFlags(top_.get(), RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(top_.get(), RTC_BUILD_QUALITY_LOW);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
    if (!geom) return embreeFailure(device, where, "instance " + std::to_string(i));
    rtcSetGeometryInstancedScene(geom, meshScenes_[inst.mesh].get());
    transforms_.emplace_back();
    worldFromObject_.push_back(inst.worldFromObject);
    motionSteps_.emplace_back();
    velocity_.push_back(inst.velocity);
    angularVelocity_.push_back(inst.angularVelocity);
    setInstanceMotion(geom, i, inst);
    // geomID = instance index, so a hit's instID is the Scene::instances index the rasterizer writes.
    rtcAttachGeometryByID(top_.get(), geom, static_cast<unsigned>(i));
    rtcReleaseGeometry(geom);
    triangleCounts_.push_back(scene.meshes[inst.mesh].triangleCount());
    exactInstances_.push_back(scene.meshes[inst.mesh].exact ? 1 : 0);
  }
  rtcCommitScene(top_.get());
  if (!device.firstError().empty()) return embreeFailure(device, where, "top level");
  return {};
}

void EmbreeScene::setInstanceMotion(RTCGeometry geom, std::size_t i, const Instance& inst) {
  transforms_[i] = makeInstanceTransform(inst.worldFromObject, anchor_);
  if (singleSided_[i] != 0)
    cullSign_[i] = glm::determinant(glm::mat3(inst.worldFromObject)) < 0.0f ? std::int8_t(-1) : std::int8_t(1);
  const bool wasMoving = !motionSteps_[i].empty();
  motionSteps_[i] = motionSteps(inst, shutter_, anchor_);
  const bool nowMoving = !motionSteps_[i].empty();
  if (nowMoving && !wasMoving) ++moving_;
  if (wasMoving && !nowMoving) --moving_;
  const std::vector<glm::mat4>& steps = motionSteps_[i];
  if (steps.empty()) {
    rtcSetGeometryTimeStepCount(geom, 1);
    rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transforms_[i].worldFromObject[0][0]);
  } else {
    // Embree interpolates the steps linearly over the ray's time in [0, 1], as motionAt does.
    rtcSetGeometryTimeStepCount(geom, static_cast<unsigned>(steps.size()));
    for (std::size_t k = 0; k < steps.size(); ++k)
      rtcSetGeometryTransform(geom, static_cast<unsigned>(k), RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &steps[k][0][0]);
  }
  rtcCommitGeometry(geom);
}

void EmbreeScene::updateTransforms(const Scene& scene, float shutter, std::optional<glm::vec3> anchor) {
  assert(scene.instances.size() == transforms_.size() && "updateTransforms: the scene's instances changed; call setScene");
  bool moved = false;
  const float open = shutter > 0.0f && std::isfinite(shutter) ? shutter : 0.0f;
  const bool newShutter = open != shutter_;
  shutter_ = open;
  // (rereadAll_ stays set until every instance was re-read: a re-read cut short by a throw is done again)
  if (anchor && *anchor != anchor_) anchor_ = *anchor, rereadAll_ = true;
  const bool newAnchor = rereadAll_;
  std::size_t n = std::min(scene.instances.size(), transforms_.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Instance& inst = scene.instances[i];
    // Static instances too: every instance is a top-level instance of its mesh's BLAS, so moving one
    // never needs a BLAS rebuilt (a full build of every mesh was a hitch of a whole frame or more).
    const bool hasMotion = inst.velocity != glm::vec3(0.0f) || inst.angularVelocity != glm::vec3(0.0f);
    const bool changed = inst.worldFromObject != worldFromObject_[i] || inst.velocity != velocity_[i] ||
                         inst.angularVelocity != angularVelocity_[i] ||
                         (newShutter && (hasMotion || !motionSteps_[i].empty()));
    if (!changed && !newAnchor) continue;
    bool finite = isFinite(inst.velocity) && isFinite(inst.angularVelocity);
    for (int c = 0; c < 4; ++c) finite = finite && isFinite(glm::vec3(inst.worldFromObject[c])) && std::isfinite(inst.worldFromObject[c].w);
    // Per-frame code never fails: a non-finite transform keeps the instance where it was (re-read against a
    // new anchor: what it was, held in worldFromObject_).
    if (finite) {
      worldFromObject_[i] = inst.worldFromObject;
      velocity_[i] = inst.velocity;
      angularVelocity_[i] = inst.angularVelocity;
    } else if (!newAnchor) {
      continue;
    }
    Instance held = inst;
    held.worldFromObject = worldFromObject_[i];
    held.velocity = velocity_[i];
    held.angularVelocity = angularVelocity_[i];
    setInstanceMotion(rtcGetGeometry(top_.get(), static_cast<unsigned>(i)), i, held);
    moved = true;
  }
  rereadAll_ = false;
  if (moved) rtcCommitScene(top_.get());  // the top level only: every BLAS stays as built
}

}  // namespace tandem::rt
