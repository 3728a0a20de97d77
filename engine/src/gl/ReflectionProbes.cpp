#include "gl/ReflectionProbes.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <limits>

namespace tandem::gl {

// ---------------------------------------------------------------------------------------------------
// Reflection probes
// ---------------------------------------------------------------------------------------------------

void ReflectionProbes::update(const GpuScene& gpu, const VisibilityPass& raster,
                              ShadePass& shade, const ShadeInputs& local,
                              const std::vector<Bounds>& instances, int faceSize) {
  assert(faceSize > 0 && (faceSize & (faceSize - 1)) == 0 && "probe faces: a power of two");
  std::vector<std::uint32_t> probes = gpu.probes().probes;
  if (probes.empty()) {
    release();
    return;
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
  std::vector<int> all(probes_.size());
  for (std::size_t slot = 0; slot < all.size(); ++slot) all[slot] = static_cast<int>(slot);
  updateSlots(gpu, raster, shade, local, instances, all);
}

void ReflectionProbes::updateSlots(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
                                   const ShadeInputs& local, const std::vector<Bounds>& instances,
                                   const std::vector<int>& slots) {
  assert(cubes_ && static_cast<int>(probes_.size()) == count_ && "updateSlots before update()");
  // Filtering across face edges, so the seams of a probe's small faces do not show in a smooth mirror.
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
  Bounds world;
  for (const Bounds& b : instances) world.add(b);
  float nearZ = std::max(1e-5f * glm::length(world.hi - world.lo), 1e-6f);
  for (int slot : slots) {
    assert(slot >= 0 && slot < count_);
    const std::uint32_t probe = probes_[static_cast<std::size_t>(slot)];
    glm::vec3 eye = instances[probe].centre();
    for (int face = 0; face < 6; ++face) {
      Camera c = cubeFaceCamera(eye, face, nearZ, std::numeric_limits<float>::infinity());
      seenBy(c.clipFromView(glm::ivec2(faceSize_)) * c.viewFromWorld(), instances, seen_);
      raster.renderInto(rasterFbo_.id(), faceSize_, faceSize_, gpu, c, probe, GpuScene::Instances::All, true, &seen_);
      glNamedFramebufferTextureLayer(shadeFbo_.id(), GL_COLOR_ATTACHMENT0, cubes_.id(), 0, 6 * slot + face);
      shade.shadeInto(shadeFbo_.id(), faceSize_, faceSize_, gpu, ids_, depth_, &sampledDepth_, c, local);
    }
  }
  // The mip chains of the re-rendered probes only, each level a linear blit of the one above (a 2×2 box, as
  // glGenerateTextureMipmap makes it). Generating the whole array's chains cost ~75 ms a frame for the game's
  // 19 probes on llvmpipe when two were re-rendered.
  if (!slots.empty()) {
    if (!mipRead_) mipRead_ = createFramebuffer("probe mip read"), mipDraw_ = createFramebuffer("probe mip draw");
    for (int slot : slots)
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
