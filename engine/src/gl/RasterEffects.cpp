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

std::vector<Bounds> instanceBounds(const Scene& scene, const std::vector<Bounds>& meshes, glm::vec3 anchor,
                                   float shutter, float u) {
  std::vector<Bounds> out(scene.instances.size());
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Bounds& b = meshes[inst.mesh];
    if (b.empty()) continue;
    // A moving instance where time u of the shutter puts it, as the GL copy draws it (GpuScene::updateInstances).
    const glm::mat4 m = isMoving(inst, shutter) ? motionAt(motionSteps(inst, shutter, anchor), u)
                                                : toRenderSpace(inst.worldFromObject, anchor);
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
void ShadowMaps::reserveTargets(int layers, int cubes) {
  if (layers != layers_ || (layers > 0 && !maps_)) {
    maps_.reset();
    if (layers > 0) {
      maps_ = createTexture2DArray("shadow maps", kChannelShadowMaps.internal, kMapSize, kMapSize, layers, 1);
      depthCompare(maps_);
    }
    layers_ = layers;
  }
  if (cubes != cubes_ || (cubes > 0 && !cubeMaps_)) {
    cubeMaps_.reset();
    if (cubes > 0) {
      cubeMaps_ = createTextureCube("shadow cube maps", kChannelShadowMaps.internal, kCubeSize, cubes);
      depthCompare(cubeMaps_);
    }
    cubes_ = cubes;
  }
  if (!fbo_) {
    fbo_ = createFramebuffer("shadow map");
    glNamedFramebufferDrawBuffer(fbo_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(fbo_.id(), GL_NONE);
  }
}

void ShadowMaps::update(const Scene& scene, const GpuScene& gpu, const VisibilityPass& raster, const Bounds& world) {
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
  if (jobs.empty() || world.empty()) {
    release();
    return;
  }
  reserveTargets(layers, cubes);
  if (!cubeDepths_) {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    cubeDepths_ = Sampler(id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  }

  // Slope-scaled bias in the map itself; reversed-Z, so negative moves occluders away from the light.
  // The shade pass adds a normal offset of 1.5 texels, which handles grazing angles.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(-1.5f, -4.0f);
  float radius = std::max(0.5f * glm::length(world.hi - world.lo), 1e-3f);
  for (const Job& job : jobs) {
    // In render space, as the bounds and the GL copy of the scene (gpu.anchor()).
    Light l = *lights[static_cast<std::size_t>(job.light)];
    l.posW = toRenderSpace(l.posW, gpu.anchor());
    GpuShadow& rec = records[static_cast<std::size_t>(job.light)];
    if (l.type == LightType::Directional) {
      const Camera c = directionalShadowCamera(l, world, radius);
      glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, maps_.id(), 0, job.slot);
      raster.renderInto(fbo_.id(), kMapSize, kMapSize, gpu, c);
      rec.clipFromWorldRelative = clipFromWorldRelative(c);
      rec.originKind = glm::vec4(c.posW, kKindOrtho);
      rec.params = glm::vec4(float(job.slot), c.nearZ, c.farZ, c.orthoHeight / float(kMapSize));
      continue;
    }
    // Spot and point: perspective from the light, far enough for the whole scene (or the range).
    float farZ = farthest(world, l.posW) * 1.01f + 1e-3f;
    if (l.range > 0.0f) farZ = std::min(farZ, l.range);
    float nearZ = std::max(farZ * 1e-4f, 1e-5f * radius);
    if (!job.cube) {
      const Camera c = spotShadowCamera(l, nearZ, farZ);
      glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, maps_.id(), 0, job.slot);
      raster.renderInto(fbo_.id(), kMapSize, kMapSize, gpu, c);
      rec.clipFromWorldRelative = clipFromWorldRelative(c);
      rec.originKind = glm::vec4(l.posW, kKindPerspective);
      rec.params = glm::vec4(float(job.slot), nearZ, farZ,
                             2.0f * std::tan(glm::radians(c.yFovDeg) * 0.5f) / float(kMapSize));
    } else {
      for (int face = 0; face < 6; ++face) {
        glNamedFramebufferTextureLayer(fbo_.id(), GL_DEPTH_ATTACHMENT, cubeMaps_.id(), 0, 6 * job.slot + face);
        raster.renderInto(fbo_.id(), kCubeSize, kCubeSize, gpu, cubeFaceCamera(l.posW, face, nearZ, farZ));
      }
      rec.originKind = glm::vec4(l.posW, kKindCube);
      rec.params = glm::vec4(float(job.slot), nearZ, farZ, 2.0f / float(kCubeSize));
    }
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(0.0f, 0.0f);
  if (!records_) records_ = createBuffer("shadow records", sizeof(records), records.data());
  else glNamedBufferSubData(records_.id(), 0, sizeof(records), records.data());
}

void ShadowMaps::release() {
  cubeDepths_.reset();
  maps_.reset();
  cubeMaps_.reset();
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
