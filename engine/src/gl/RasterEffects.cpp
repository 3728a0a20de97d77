#include "gl/RasterEffects.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "core/Motion.h"
#include "core/RenderSpace.h"
#include "core/Shading.h"

namespace tandem::gl {

namespace {

// shade.frag's TD_SHADOW_* kinds, as GpuShadow stores them.
constexpr float kKindOrtho = float(ShadowMapKind::Ortho), kKindPerspective = float(ShadowMapKind::Perspective),
                kKindCube = float(ShadowMapKind::Cube);

// Cube-map faces in GL's order (+X, −X, +Y, −Y, +Z, −Z), as cameras: looking along `forward` with `up`,
// a camera's pixel (x, y) (y up, as framebuffer rows run) lands on the face texel (s, t) that GL's cube
// sampling (spec table "Selection of cube map images") picks for that direction, so a face rendered by
// the ordinary raster + shade passes is addressed by direction with no flip.
struct Face {
  glm::vec3 forward, up;
};
constexpr Face kFaces[6] = {{{1, 0, 0}, {0, -1, 0}},  {{-1, 0, 0}, {0, -1, 0}}, {{0, 1, 0}, {0, 0, 1}},
                            {{0, -1, 0}, {0, 0, -1}}, {{0, 0, 1}, {0, -1, 0}},  {{0, 0, -1}, {0, -1, 0}}};

}  // namespace

Camera cubeFaceCamera(glm::vec3 eye, int face, float nearZ, float farZ) {
  Camera c;
  c.posW = eye;
  c.targetW = eye + kFaces[face].forward;
  c.upW = kFaces[face].up;
  c.yFovDeg = 90.0f;
  c.nearZ = nearZ;
  c.farZ = farZ;
  return c;
}

namespace {

// Any unit vector not parallel to `d`, for an up vector.
glm::vec3 upFor(glm::vec3 d) { return std::abs(d.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0); }

glm::mat4 clipFromWorldRelative(const Camera& c) {
  return c.clipFromView(1.0f) * glm::mat4(glm::mat3(c.viewFromWorld()));
}

// Distances from `p` to the nearest and farthest points of the box.
float farthest(const Bounds& b, glm::vec3 p) {
  glm::vec3 d = glm::max(glm::abs(b.lo - p), glm::abs(b.hi - p));
  return glm::length(d);
}

void depthCompare(const Texture& t) {
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  // Reversed-Z: the stored depth is the nearest occluder's, the largest value; a receiver is lit when
  // it is at least as near as that (ref >= stored).
  glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL);
}

}  // namespace

std::vector<Bounds> meshBounds(const Scene& scene) {
  std::vector<Bounds> out(scene.meshes.size());
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    for (const glm::vec3& p : scene.meshes[m].positions) out[m].add(p);
  return out;
}

namespace {
// A moving instance where time u of the shutter puts it, as the GL copy draws it (GpuScene::updateInstances).
glm::mat4 renderTransform(const Instance& inst, glm::vec3 anchor, float shutter, float u) {
  return isMoving(inst, shutter) ? motionAt(motionSteps(inst, shutter, anchor), u) : toRenderSpace(inst.worldFromObject, anchor);
}
}  // namespace

std::vector<glm::mat4> instanceTransforms(const Scene& scene, glm::vec3 anchor, float shutter, float u) {
  std::vector<glm::mat4> out;
  out.reserve(scene.instances.size());
  for (const Instance& inst : scene.instances) out.push_back(renderTransform(inst, anchor, shutter, u));
  return out;
}

void seenBy(const glm::mat4& clipFromWorld, const std::vector<Bounds>& instances, std::vector<std::uint8_t>& seen) {
  seen.resize(instances.size());
  for (std::size_t i = 0; i < instances.size(); ++i) seen[i] = mayBeSeen(clipFromWorld, instances[i]) ? 1 : 0;
}

bool mayBeSeen(const glm::mat4& clipFromWorld, const Bounds& b) {
  if (b.empty()) return false;
  // Per plane, whether every corner is beyond it: x < −w, x > w, y < −w, y > w, z < 0, z > w.
  bool out[6] = {true, true, true, true, true, true};
  for (int k = 0; k < 8; ++k) {
    const glm::vec4 c = clipFromWorld * glm::vec4((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y,
                                                  (k & 4) ? b.hi.z : b.lo.z, 1.0f);
    // A little slack: the test is in float and must never drop a box the draw would rasterize.
    const float w = c.w + 1e-4f * std::abs(c.w);
    out[0] = out[0] && c.x < -w;
    out[1] = out[1] && c.x > w;
    out[2] = out[2] && c.y < -w;
    out[3] = out[3] && c.y > w;
    out[4] = out[4] && c.z < -1e-4f * std::abs(c.w);
    out[5] = out[5] && c.z > w;
  }
  for (bool o : out)
    if (o) return false;
  return true;
}

std::vector<Bounds> instanceBounds(const Scene& scene, const std::vector<Bounds>& meshes, glm::vec3 anchor,
                                   float shutter, float u) {
  std::vector<Bounds> out(scene.instances.size());
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Bounds& b = meshes[inst.mesh];
    if (b.empty()) continue;
    const glm::mat4 m = renderTransform(inst, anchor, shutter, u);
    for (int k = 0; k < 8; ++k) {
      glm::vec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
      out[i].add(glm::vec3(m * glm::vec4(corner, 1.0f)));
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Shadow maps
// ---------------------------------------------------------------------------------------------------

namespace {

// Orthographic, fitted to the scene's bounds seen along the light; `world` and the camera in render space.
Camera directionalShadowCamera(const Light& l, const Bounds& world, float radius) {
  glm::vec3 centre = world.centre();
  glm::vec3 fwd = glm::normalize(l.dirW);
  glm::vec3 right = glm::normalize(glm::cross(fwd, upFor(fwd)));
  glm::vec3 up = glm::cross(right, fwd);
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (int k = 0; k < 8; ++k) {
    glm::vec3 p((k & 1) ? world.hi.x : world.lo.x, (k & 2) ? world.hi.y : world.lo.y,
                (k & 4) ? world.hi.z : world.lo.z);
    glm::vec3 q(glm::dot(p - centre, right), glm::dot(p - centre, up), glm::dot(p - centre, fwd));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  float pad = 0.01f * radius;
  Camera c;
  c.orthographic = true;
  c.posW = centre + right * (0.5f * (lo.x + hi.x)) + up * (0.5f * (lo.y + hi.y)) + fwd * (lo.z - 2.0f * pad);
  c.targetW = c.posW + fwd;
  c.upW = up;
  c.orthoHeight = std::max(hi.x - lo.x, hi.y - lo.y) + 2.0f * pad;
  c.nearZ = pad;
  c.farZ = (hi.z - lo.z) + 4.0f * pad;
  return c;
}

Camera spotShadowCamera(const Light& l, float nearZ, float farZ) {
  glm::vec3 fwd = glm::normalize(l.dirW);
  Camera c;
  c.posW = l.posW;
  c.targetW = l.posW + fwd;
  c.upW = upFor(fwd);
  c.yFovDeg = 2.0f * l.outerConeDeg + 2.0f;  // the square frustum holds the cone, plus PCF margin
  c.nearZ = nearZ;
  c.farZ = farZ;
  return c;
}

}  // namespace

// Keeps the targets while the number of maps and cube maps stays the same: lights move far more often
// than they are added or removed.
void ShadowMaps::reserveTargets(int layers, int cubes, bool withStatic) {
  if (layers != layers_ || (layers > 0 && !maps_)) {
    maps_.reset();
    staticMaps_.reset();
    if (layers > 0) {
      maps_ = createTexture2DArray("shadow maps", kChannelShadowMaps.internal, kMapSize, kMapSize, layers, 1);
      depthCompare(maps_);
    }
    layers_ = layers;
    drawn_.valid = false;
  }
  if (cubes != cubes_ || (cubes > 0 && !cubeMaps_)) {
    cubeMaps_.reset();
    staticCubeMaps_.reset();
    if (cubes > 0) {
      cubeMaps_ = createTextureCube("shadow cube maps", kChannelShadowMaps.internal, kCubeSize, cubes);
      depthCompare(cubeMaps_);
    }
    cubes_ = cubes;
    drawn_.valid = false;
  }
  // The static part of each face: only kept while something dynamic may move over it.
  if (!withStatic && (staticMaps_ || staticCubeMaps_)) {
    staticMaps_.reset();
    staticCubeMaps_.reset();
  }
  if (withStatic && layers > 0 && !staticMaps_) {
    staticMaps_ = createTexture2DArray("shadow maps (static)", kChannelShadowMaps.internal, kMapSize, kMapSize, layers, 1);
    drawn_.valid = false;
  }
  if (withStatic && cubes > 0 && !staticCubeMaps_) {
    staticCubeMaps_ = createTextureCube("shadow cube maps (static)", kChannelShadowMaps.internal, kCubeSize, cubes);
    drawn_.valid = false;
  }
  if (!fbo_) {
    fbo_ = createFramebuffer("shadow map");
    glNamedFramebufferDrawBuffer(fbo_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(fbo_.id(), GL_NONE);
  }
}

void ShadowMaps::update(const Scene& scene, const GpuScene& gpu, const VisibilityPass& raster,
                        const std::vector<Bounds>& instances, const std::vector<glm::mat4>& transforms,
                        std::uint64_t generation, bool everything) {
  facesDrawn_ = 0;
  std::vector<const Light*> lights = scene.directLights();
  std::array<GpuShadow, TD_MAX_LIGHTS> records{};
  struct Job {
    int light;
    bool cube;
    int slot;
  };
  std::vector<Job> jobs;
  int layers = 0, cubes = 0;
  for (std::size_t j = 0; j < lights.size() && j < TD_MAX_LIGHTS; ++j) {
    const Light& l = *lights[j];
    if (!l.castShadows) continue;
    bool cube = shadowMapKind(l) == ShadowMapKind::Cube;
    jobs.push_back({static_cast<int>(j), cube, cube ? cubes++ : layers++});
  }
  Bounds world;
  for (const Bounds& b : instances) world.add(b);
  if (jobs.empty() || world.empty()) {
    release();
    return;
  }
  const bool anyDynamic = gpu.dynamicCount() > 0;
  reserveTargets(layers, cubes, anyDynamic);
  if (!cubeDepths_) {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    cubeDepths_ = Sampler(id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  }

  // What changed since the maps were drawn. The lights' cameras are fitted to the scene's bounds grown by a
  // tenth: they stay put while the scene stays within them and does not shrink to half of them.
  std::vector<Light> lightsNow;
  for (const Light* l : lights) lightsNow.push_back(*l);
  const glm::vec3 extent = world.hi - world.lo;
  auto within = [](const Bounds& inner, const Bounds& outer) {
    return glm::all(glm::greaterThanEqual(inner.lo, outer.lo)) && glm::all(glm::lessThanEqual(inner.hi, outer.hi));
  };
  const bool fitHolds = drawn_.valid && within(world, drawn_.fit) &&
                        glm::length(drawn_.fit.hi - drawn_.fit.lo) <= 2.0f * glm::length(extent) + 1e-6f;
  // Everything: what every map depends on changed. Else each light's maps are drawn whole if that light
  // changed, and the others only where a dynamic instance moved.
  bool full = everything || !drawn_.valid || !fitHolds || drawn_.generation != generation ||
              drawn_.lights.size() != lightsNow.size() || drawn_.transforms.size() != transforms.size() || !anyDynamic;
  std::vector<Bounds> moved;  // where the dynamic instances that moved were and are
  for (std::size_t i = 0; !full && i < transforms.size(); ++i) {
    if (transforms[i] == drawn_.transforms[i]) continue;
    if (!scene.instances[i].dynamic) full = true;  // a static instance moved: its part must be drawn again
    moved.push_back(drawn_.bounds[i]);
    moved.push_back(instances[i]);
  }
  bool anyLightChanged = false;
  for (std::size_t j = 0; !full && j < lightsNow.size(); ++j) anyLightChanged = anyLightChanged || !(lightsNow[j] == drawn_.lights[j]);
  if (!full && moved.empty() && !anyLightChanged) return;  // nothing any map shows changed
  Bounds fit = fitHolds ? drawn_.fit : world;
  if (!fitHolds) {
    const glm::vec3 pad = 0.05f * extent + glm::vec3(1e-6f * glm::length(world.hi));
    fit.lo -= pad;
    fit.hi += pad;
  }

  // Slope-scaled bias in the map itself; reversed-Z, so negative moves occluders away from the light.
  // The shade pass adds a normal offset of 1.5 texels, which handles grazing angles.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(-1.5f, -4.0f);
  float radius = std::max(0.5f * glm::length(fit.hi - fit.lo), 1e-3f);
  faceClip_.assign(static_cast<std::size_t>(faceCount()), glm::mat4(0.0f));
  faceCamera_.assign(static_cast<std::size_t>(faceCount()), Camera{});
  // One face: everything into `live` (no dynamic instances), or the static part into `kept` and a copy of it
  // with the dynamic instances over it into `live`; on an incremental update, only the copy and the dynamic
  // instances, where the face sees something that moved.
  bool whole = full;  // the current light's maps are drawn whole
  auto drawFace = [&](const Camera& c, int size, const Texture& live, const Texture& kept, GLenum target, int layer,
                      int faceIndex) {
    faceCamera_[static_cast<std::size_t>(faceIndex)] = c;
    const glm::mat4& clip = faceClip_[static_cast<std::size_t>(faceIndex)] =
        c.clipFromView(glm::ivec2(size, size)) * c.viewFromWorld();
    if (!whole) {
      bool sees = false;
      for (const Bounds& b : moved) sees = sees || mayBeSeen(clip, b);
      if (!sees) return;
    }
    ++facesDrawn_;
    seenBy(clip, instances, seen_);  // each face draws what it may see (a cube face: about a sixth)
    if (!anyDynamic) {
      glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, live.id(), 0, layer);
      raster.renderInto(fbo_.id(), size, size, gpu, c, std::nullopt, GpuScene::Instances::All, true, &seen_);
      return;
    }
    if (whole) {
      glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, kept.id(), 0, layer);
      raster.renderInto(fbo_.id(), size, size, gpu, c, std::nullopt, GpuScene::Instances::Static, true, &seen_);
    }
    glCopyImageSubData(kept.id(), target, 0, 0, 0, layer, live.id(), target, 0, 0, 0, layer, size, size, 1);
    glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, live.id(), 0, layer);
    raster.renderInto(fbo_.id(), size, size, gpu, c, std::nullopt, GpuScene::Instances::Dynamic, /*clear=*/false,
                      &seen_);
  };
  for (const Job& job : jobs) {
    whole = full || !(lightsNow[static_cast<std::size_t>(job.light)] == drawn_.lights[static_cast<std::size_t>(job.light)]);
    // In render space, as the bounds and the GL copy of the scene (gpu.anchor()).
    Light l = *lights[static_cast<std::size_t>(job.light)];
    l.posW = toRenderSpace(l.posW, gpu.anchor());
    GpuShadow& rec = records[static_cast<std::size_t>(job.light)];
    if (l.type == LightType::Directional) {
      const Camera c = directionalShadowCamera(l, fit, radius);
      drawFace(c, kMapSize, maps_, staticMaps_, GL_TEXTURE_2D_ARRAY, job.slot, job.slot);
      rec.clipFromWorldRelative = clipFromWorldRelative(c);
      rec.originKind = glm::vec4(c.posW, kKindOrtho);
      rec.params = glm::vec4(float(job.slot), c.nearZ, c.farZ, c.orthoHeight / float(kMapSize));
      continue;
    }
    // Spot and point: perspective from the light, far enough for the whole scene (or the range).
    float farZ = farthest(fit, l.posW) * 1.01f + 1e-3f;
    if (l.range > 0.0f) farZ = std::min(farZ, l.range);
    float nearZ = std::max(farZ * 1e-4f, 1e-5f * radius);
    if (!job.cube) {
      const Camera c = spotShadowCamera(l, nearZ, farZ);
      drawFace(c, kMapSize, maps_, staticMaps_, GL_TEXTURE_2D_ARRAY, job.slot, job.slot);
      rec.clipFromWorldRelative = clipFromWorldRelative(c);
      rec.originKind = glm::vec4(l.posW, kKindPerspective);
      rec.params = glm::vec4(float(job.slot), nearZ, farZ,
                             2.0f * std::tan(glm::radians(c.yFovDeg) * 0.5f) / float(kMapSize));
    } else {
      for (int face = 0; face < 6; ++face)
        drawFace(cubeFaceCamera(l.posW, face, nearZ, farZ), kCubeSize, cubeMaps_, staticCubeMaps_,
                 GL_TEXTURE_CUBE_MAP_ARRAY, 6 * job.slot + face, layers_ + 6 * job.slot + face);
      rec.originKind = glm::vec4(l.posW, kKindCube);
      rec.params = glm::vec4(float(job.slot), nearZ, farZ, 2.0f / float(kCubeSize));
    }
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(0.0f, 0.0f);
  if (!records_) records_ = createBuffer("shadow records", sizeof(records), records.data());
  else glNamedBufferSubData(records_.id(), 0, sizeof(records), records.data());
  drawn_.valid = true;
  drawn_.generation = generation;
  drawn_.lights = std::move(lightsNow);
  drawn_.transforms = transforms;
  drawn_.bounds = instances;
  drawn_.fit = fit;
}

void ShadowMaps::release() {
  cubeDepths_.reset();
  maps_.reset();
  cubeMaps_.reset();
  staticMaps_.reset();
  staticCubeMaps_.reset();
  drawn_ = Drawn{};
  faceClip_.clear();
  faceCamera_.clear();
  fbo_.reset();
  records_.reset();
  layers_ = cubes_ = 0;
}

void ShadowMaps::bind(Placeholders& placeholders) const {
  placeholders.bindOr(kUnitShadowMaps, maps_.id(), Placeholders::Depth2DArrayCompare);
  placeholders.bindOr(kUnitShadowCubes, cubeMaps_.id(), Placeholders::DepthCubeArrayCompare);
  placeholders.bindOr(kUnitShadowCubesDepth, cubeMaps_.id(), Placeholders::DepthCubeArray);
  // The cube maps compare depths; this unit reads them as values through a sampler object that does not.
  glBindSampler(kUnitShadowCubesDepth, cubeMaps_ ? cubeDepths_.id() : 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, kBlockShadows, records_.id());
}

}  // namespace tandem::gl
