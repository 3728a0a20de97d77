#pragma once
// The view behind see-through surfaces: the raster's thin transmission. A surface that lets light through
// without bending it (IOR 1: glTF's thin-walled KHR_materials_transmission, a BLEND surface's uncovered part)
// shows what lies behind it along the pixel's own ray. A probe drawn from the object's centre cannot show that
// (a lamp's shade would see its bulb from inside), so the frame's scene is drawn again from the frame's camera
// and the shade pass reads it at the same pixel (ShadeInputs::behindView, kProbeBehind), as the glTF viewers'
// transmission framebuffer. Two layers, as a closed shell needs (a shade's near wall, then its far wall or
// the bulb inside): the nearest see-through surfaces' depth is drawn first; "behind" is the scene peeled
// behind that depth (depth peeling), its see-through surfaces in turn reading "beyond", the scene without any.
// A third see-through layer is not seen (the rays see every one, to their depth).
#include <cstdint>
#include <vector>

#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/ShadePass.h"
#include "gl/VisibilityPass.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"

namespace tandem::gl {

/// Per instance: 0 where its material is see-through (IOR 1 and kt > 0, or BLEND), else 1; empty when no
/// instance is (the frame needs no view behind).
std::vector<std::uint8_t> behindViewInstances(const Scene& scene);

class BehindView {
 public:
  /// Draws the view behind from `camera` (render space, the frame's, jitter included) into width × height
  /// targets, made again when the size changes. `opaque`: behindViewInstances. Both layers are shaded with
  /// `local` (no rays, no reflections: one bounce); the near layer's see-through surfaces read the far one, and
  /// its surfaces that refract (IOR other than 1) the probes (`probes`, which hold one for each of them). An
  /// error names the target the GL refused (the view is then released and the frame reads its probes).
  Result<void> draw(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade, const ShadeInputs& local,
                    const Texture& probes, const Camera& camera, int width, int height,
                    const std::vector<std::uint8_t>& opaque);
  /// What the frame's see-through surfaces read: the scene behind the nearest of them.
  const Texture& colour() const { return behind_.colour; }
  bool held() const { return static_cast<bool>(behind_.colour); }
  void release();

 private:
  struct Layer {
    Texture ids, depth, colour;
    Framebuffer rasterFbo, shadeFbo;
  };
  Result<void> make(Layer& layer, const char* name, int width, int height);
  Layer behind_, beyond_;
  Texture nearest_;       // the nearest see-through surfaces' depth (reversed-Z; 0 where none)
  Texture sampledDepth_;  // what toon outlines read (ShadePass::samplesDepth)
  Framebuffer nearestFbo_;
  int width_ = 0, height_ = 0;
};

}  // namespace tandem::gl
