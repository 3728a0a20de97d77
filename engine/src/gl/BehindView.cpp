#include "gl/BehindView.h"

#include <algorithm>
#include <bit>
#include <string>

namespace tandem::gl {

std::vector<std::uint8_t> behindViewInstances(const Scene& scene) {
  std::vector<std::uint8_t> opaque(scene.instances.size(), 1);
  bool any = false;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Material& m = scene.materials[scene.instances[i].material];
    if (m.ior == 1.0f && (m.kt > 0.0f || m.alphaMode == AlphaMode::Blend)) opaque[i] = 0, any = true;
  }
  if (!any) opaque.clear();
  return opaque;
}

Result<void> BehindView::make(Layer& layer, const char* name, int width, int height) {
  const std::string n(name);
  auto ids = tryCreateTexture2D(n + " ids", kChannelIds.internal, width, height);
  if (!ids) return ids.error();
  auto depth = tryCreateTexture2D(n + " depth", kChannelDepth.internal, width, height);
  if (!depth) return depth.error();
  auto colour = tryCreateTexture2D(n + " (level 0)", kChannelProbes.internal, width, height);
  if (!colour) return colour.error();
  colour->reset();  // the level-0 size was what might not fit; the mip chain adds a third of it
  // Mipmapped: rough see-through surfaces read it at the level their lobe covers (shade_probes.glsl).
  const int levels = std::bit_width(static_cast<unsigned>(std::max(width, height)));
  *colour = createTexture2D(n, kChannelProbes.internal, width, height, levels);
  layer.ids = std::move(*ids);
  layer.depth = std::move(*depth);
  layer.colour = std::move(*colour);
  setSampling(layer.ids, GL_NEAREST, GL_NEAREST);
  setSampling(layer.depth, GL_NEAREST, GL_NEAREST);
  glTextureParameteri(layer.colour.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(layer.colour.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(layer.colour.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(layer.colour.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  layer.rasterFbo = createFramebuffer(n + " raster");
  glNamedFramebufferTexture(layer.rasterFbo.id(), GL_COLOR_ATTACHMENT0, layer.ids.id(), 0);
  glNamedFramebufferTexture(layer.rasterFbo.id(), GL_DEPTH_ATTACHMENT, layer.depth.id(), 0);
  glNamedFramebufferDrawBuffer(layer.rasterFbo.id(), GL_COLOR_ATTACHMENT0);
  layer.shadeFbo = createFramebuffer(n + " shade");
  glNamedFramebufferTexture(layer.shadeFbo.id(), GL_COLOR_ATTACHMENT0, layer.colour.id(), 0);
  if (auto complete = checkFramebufferComplete(layer.rasterFbo, n + " raster"); !complete) return complete;
  return checkFramebufferComplete(layer.shadeFbo, n + " shade");
}

Result<void> BehindView::draw(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
                              const ShadeInputs& local, const Texture& probes, const Camera& camera, int width,
                              int height, const std::vector<std::uint8_t>& opaque) {
  if (width != width_ || height != height_ || !behind_.colour) {
    release();
    for (auto [layer, name] : {std::pair{&behind_, "behind view"}, std::pair{&beyond_, "beyond view"}})
      if (auto made = make(*layer, name, width, height); !made) {
        release();
        return made;
      }
    auto nearest = tryCreateTexture2D("see-through depth", kChannelDepth.internal, width, height);
    if (!nearest) {
      release();
      return nearest.error();
    }
    nearest_ = std::move(*nearest);
    setSampling(nearest_, GL_NEAREST, GL_NEAREST);
    nearestFbo_ = createFramebuffer("see-through depth");
    glNamedFramebufferTexture(nearestFbo_.id(), GL_DEPTH_ATTACHMENT, nearest_.id(), 0);
    glNamedFramebufferDrawBuffer(nearestFbo_.id(), GL_NONE);
    width_ = width;
    height_ = height;
  }
  if (ShadePass::samplesDepth(gpu.features(), local.debugView) && !sampledDepth_) {
    sampledDepth_ = createTexture2D("behind view depth (sampled copy)", kChannelDepth.internal, width, height);
    setSampling(sampledDepth_, GL_NEAREST, GL_NEAREST);
  }
  const Texture* sampled = sampledDepth_ ? &sampledDepth_ : nullptr;
  // The nearest see-through surfaces (depth only), then the scene without them (beyond), then the scene behind
  // the nearest (behind), whose see-through surfaces, its far walls, read beyond at their pixel.
  std::vector<std::uint8_t> seeThrough(opaque.size());
  for (std::size_t i = 0; i < opaque.size(); ++i) seeThrough[i] = opaque[i] ? 0 : 1;
  raster.renderInto(nearestFbo_.id(), width, height, gpu, camera, std::nullopt, GpuScene::Instances::All, true,
                    &seeThrough);
  raster.renderInto(beyond_.rasterFbo.id(), width, height, gpu, camera, std::nullopt, GpuScene::Instances::All, true,
                    &opaque);
  ShadeInputs layer = local;
  layer.distanceInAlpha = true;  // how far behind each pixel's surface lies (a rough surface's blur)
  shade.shadeInto(beyond_.shadeFbo.id(), width, height, gpu, beyond_.ids, beyond_.depth, sampled, camera, layer);
  glGenerateTextureMipmap(beyond_.colour.id());
  raster.renderInto(behind_.rasterFbo.id(), width, height, gpu, camera, std::nullopt, GpuScene::Instances::All, true,
                    nullptr, &nearest_);
  ShadeInputs far = layer;
  far.probeCubes = &probes;
  far.probeEffects = kProbeRefract | kProbeBehind;
  far.behindView = &beyond_.colour;
  shade.shadeInto(behind_.shadeFbo.id(), width, height, gpu, behind_.ids, behind_.depth, sampled, camera, far);
  glGenerateTextureMipmap(behind_.colour.id());
  return {};
}

void BehindView::release() {
  behind_ = Layer{};
  beyond_ = Layer{};
  nearest_.reset();
  sampledDepth_.reset();
  nearestFbo_.reset();
  width_ = height_ = 0;
}

}  // namespace tandem::gl
