#include "gl/ReflectionProbes.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>

namespace tandem::gl {

std::vector<float> meshNormalSpread(const Scene& scene) {
  std::vector<float> out(scene.meshes.size(), glm::pi<float>());
  std::vector<glm::vec3> normals;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    normals.clear();
    if (mesh.normals.size() == mesh.positions.size()) {
      normals = mesh.normals;
    } else {
      for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        if (std::max({a, b, c}) >= mesh.positions.size()) continue;
        normals.push_back(glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]));
      }
    }
    glm::dvec3 sum(0.0);
    for (glm::vec3& n : normals) {
      const float len = glm::length(n);
      n = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f);
      sum += glm::dvec3(n);
    }
    const double len = glm::length(sum);
    if (!(len > 1e-6 * static_cast<double>(normals.size()))) continue;  // every way: π
    const glm::vec3 mean(sum / len);
    float widest = 0.0f;
    for (const glm::vec3& n : normals)
      if (n != glm::vec3(0.0f)) widest = std::max(widest, std::acos(std::clamp(glm::dot(n, mean), -1.0f, 1.0f)));
    out[m] = widest;
  }
  return out;
}

std::vector<float> probeDetail(const Scene& scene, const ProbeLayout& layout, const std::vector<Bounds>& instances,
                               const std::vector<float>& normalSpread, const Camera& view, int viewHeight,
                               int faceSize) {
  std::vector<float> need(layout.probes.size(), 0.0f);  // pixels per radian, per slot
  const float viewDensity = view.orthographic ? std::numeric_limits<float>::infinity()
                                              : static_cast<float>(viewHeight) / glm::radians(view.yFovDeg);
  const float tanHalf = std::tan(0.5f * glm::radians(view.yFovDeg));
  for (std::size_t i = 0; i < layout.slotOf.size() && i < instances.size(); ++i) {
    const int slot = layout.slotOf[i];
    if (slot < 0 || instances[i].empty()) continue;
    const Instance& inst = scene.instances[i];
    const Material& m = scene.materials[inst.material];
    float density = viewDensity;
    if (m.kt <= 0.0f && m.alphaMode != AlphaMode::Blend && !view.orthographic) {
      const float r = 0.5f * glm::length(instances[i].hi - instances[i].lo);
      const float d = glm::length(instances[i].centre() - view.posW);
      if (d > r) {
        const float pixels = static_cast<float>(viewHeight) * r / (d * tanHalf);  // its diameter on screen
        density = std::min(viewDensity, pixels / (2.0f * std::max(normalSpread[inst.mesh], 1e-6f)));
      }
    }
    need[static_cast<std::size_t>(slot)] = std::max(need[static_cast<std::size_t>(slot)], density);
  }
  std::vector<float> out(need.size());
  for (std::size_t s = 0; s < need.size(); ++s)
    out[s] = std::clamp(need[s] / (0.5f * static_cast<float>(faceSize)), 1e-3f, 1.0f);
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Reflection probes
// ---------------------------------------------------------------------------------------------------

int ReflectionProbes::update(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
                             const ShadeInputs& local, const std::vector<Bounds>& instances, int faceSize,
                             int budget, const std::vector<float>& detail) {
  assert(faceSize > 0 && (faceSize & (faceSize - 1)) == 0 && "probe faces: a power of two");
  std::vector<std::uint32_t> probes = gpu.probes().probes;
  if (probes.empty()) {
    release();
    return 0;
  }
  if (faceSize != faceSize_) release();
  faceSize_ = faceSize;
  levels_ = std::countr_zero(static_cast<unsigned>(faceSize)) + 1;
  if (static_cast<int>(probes.size()) != count_ || !cubes_) {
    count_ = static_cast<int>(probes.size());
    // Mipmapped: a glossy material looks its probe up at the level its lobe covers (docs/glossy.md).
    cubes_ = createTextureCube("reflection probes", kChannelProbes.internal, faceSize_, count_, levels_);
    glTextureParameteri(cubes_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(cubes_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(cubes_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(cubes_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(cubes_.id(), GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  }
  if (!ids_) {
    ids_ = createTexture2D("probe ids", kChannelIds.internal, faceSize_, faceSize_);
    setSampling(ids_, GL_NEAREST, GL_NEAREST);
    depth_ = createTexture2D("probe depth", kChannelDepth.internal, faceSize_, faceSize_);
    setSampling(depth_, GL_NEAREST, GL_NEAREST);
    sampledDepth_ = createTexture2D("probe depth (sampled copy)", kChannelDepth.internal, faceSize_, faceSize_);
    setSampling(sampledDepth_, GL_NEAREST, GL_NEAREST);
    rasterFbo_ = createFramebuffer("probe raster");
    glNamedFramebufferTexture(rasterFbo_.id(), GL_COLOR_ATTACHMENT0, ids_.id(), 0);
    glNamedFramebufferTexture(rasterFbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    glNamedFramebufferDrawBuffer(rasterFbo_.id(), GL_COLOR_ATTACHMENT0);
    shadeFbo_ = createFramebuffer("probe shade");
  }
  probes_ = std::move(probes);
  const int now = budget > 0 ? std::min(budget, count_) : count_;
  std::vector<int> drawn(static_cast<std::size_t>(now));
  for (int slot = 0; slot < now; ++slot) drawn[static_cast<std::size_t>(slot)] = slot;
  updateSlots(gpu, raster, shade, local, instances, drawn, detail);
  if (now < count_) {
    // The rest show the environment until their turn: one empty probe, its faces and mip levels copied.
    drawSlot(gpu, raster, shade, local, instances, now, true, 1.0f);
    for (int slot = now + 1; slot < count_; ++slot)
      for (int level = 0; level < levels_; ++level) {
        const int size = faceSize_ >> level;
        glCopyImageSubData(cubes_.id(), GL_TEXTURE_CUBE_MAP_ARRAY, level, 0, 0, 6 * now, cubes_.id(),
                           GL_TEXTURE_CUBE_MAP_ARRAY, level, 0, 0, 6 * slot, size, size, 6);
      }
  }
  return now;
}

void ReflectionProbes::updateSlots(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
                                   const ShadeInputs& local, const std::vector<Bounds>& instances,
                                   const std::vector<int>& slots, const std::vector<float>& detail) {
  assert(cubes_ && static_cast<int>(probes_.size()) == count_ && "updateSlots before update()");
  assert((detail.empty() || detail.size() == probes_.size()) && "updateSlots: one detail per slot");
  for (int slot : slots)
    drawSlot(gpu, raster, shade, local, instances, slot, false,
             detail.empty() ? 1.0f : detail[static_cast<std::size_t>(slot)]);
}

void ReflectionProbes::drawSlot(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
                                const ShadeInputs& local, const std::vector<Bounds>& instances, int slot,
                                bool empty, float detail) {
  assert(slot >= 0 && slot < count_);
  // Filtering across face edges, so the seams of a probe's small faces do not show in a smooth mirror.
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  Bounds world;
  for (const Bounds& b : instances) world.add(b);
  const float nearZ = std::max(1e-5f * glm::length(world.hi - world.lo), 1e-6f);
  const std::uint32_t probe = probes_[static_cast<std::size_t>(slot)];
  const glm::vec3 eye = instances[probe].centre();
  for (int face = 0; face < 6; ++face) {
    Camera c = cubeFaceCamera(eye, face, nearZ, std::numeric_limits<float>::infinity());
    seenBy(c.clipFromView(glm::ivec2(faceSize_)) * c.viewFromWorld(), instances, seen_);
    // A small object in the face is drawn with a coarse copy (GpuScene::ensureProbeLod): at 90° a unit at
    // distance z spans faceSize / 2z texels, so a box of half-diagonal r no nearer than d − r spans at most
    // faceSize·r / (d − r), of which the frame shows `detail` (probeDetail). The faces' cost is then the texels
    // they fill, not the scene's triangles.
    for (std::size_t i = 0; i < seen_.size(); ++i) {
      if (!seen_[i] || empty) {
        seen_[i] = 0;
        continue;
      }
      const float r = 0.5f * glm::length(instances[i].hi - instances[i].lo);
      const float gap = glm::length(instances[i].centre() - eye) - r;
      const float texels =
          gap > 0.0f ? detail * static_cast<float>(faceSize_) * r / gap : std::numeric_limits<float>::infinity();
      seen_[i] = static_cast<std::uint8_t>(1 + probeLodLevel(texels));
    }
    raster.renderInto(rasterFbo_.id(), faceSize_, faceSize_, gpu, c, probe, GpuScene::Instances::All, true, &seen_);
    glNamedFramebufferTextureLayer(shadeFbo_.id(), GL_COLOR_ATTACHMENT0, cubes_.id(), 0, 6 * slot + face);
    shade.shadeInto(shadeFbo_.id(), faceSize_, faceSize_, gpu, ids_, depth_, &sampledDepth_, c, local);
  }
  // The mip chain of this probe only, each level a linear blit of the one above (a 2×2 box, as
  // glGenerateTextureMipmap makes it). Generating the whole array's chains cost ~75 ms a frame for the game's
  // 19 probes on llvmpipe when two were re-rendered.
  if (!mipRead_) mipRead_ = createFramebuffer("probe mip read"), mipDraw_ = createFramebuffer("probe mip draw");
  for (int face = 0; face < 6; ++face)
    for (int level = 1; level < levels_; ++level) {
      const int src = faceSize_ >> (level - 1), dst = faceSize_ >> level;
      glNamedFramebufferTextureLayer(mipRead_.id(), GL_COLOR_ATTACHMENT0, cubes_.id(), level - 1, 6 * slot + face);
      glNamedFramebufferTextureLayer(mipDraw_.id(), GL_COLOR_ATTACHMENT0, cubes_.id(), level, 6 * slot + face);
      glNamedFramebufferReadBuffer(mipRead_.id(), GL_COLOR_ATTACHMENT0);
      glNamedFramebufferDrawBuffer(mipDraw_.id(), GL_COLOR_ATTACHMENT0);
      glBlitNamedFramebuffer(mipRead_.id(), mipDraw_.id(), 0, 0, src, src, 0, 0, dst, dst, GL_COLOR_BUFFER_BIT,
                             GL_LINEAR);
    }
}

void ReflectionProbes::release() {
  cubes_.reset();
  ids_.reset();
  depth_.reset();
  sampledDepth_.reset();
  rasterFbo_.reset();
  shadeFbo_.reset();
  mipRead_.reset();
  mipDraw_.reset();
  probes_.clear();
  count_ = 0;
  faceSize_ = levels_ = 0;
}

}  // namespace tandem::gl
