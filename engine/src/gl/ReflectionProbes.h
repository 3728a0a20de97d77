#pragma once
// Reflection probes: the raster stand-in for reflection and refraction rays. Baked with the visibility and
// shade passes (it sits above them: they know nothing of it; the shade pass reads the cube array it hands
// over in ShadeInputs::probeCubes).
#include <vector>

#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/RasterEffects.h"
#include "gl/ShadePass.h"
#include "gl/VisibilityPass.h"

namespace tandem::gl {

/// A cube map of the surroundings of each object whose material has kr > 0 or kt > 0 (GpuScene's probe
/// layout: at most FrameSettings::probeLimit, shared past it), rendered from the centre of its bounds without
/// the object itself and shaded
/// by the same shade pass with local shading only. The shade pass looks the reflected (and refracted)
/// direction up in it.
class ReflectionProbes {
 public:
  /// Re-renders every probe of the GL copy's layout (GpuScene::probes) with faces of `faceSize`² texels (a power
  /// of two; FrameSettings::probeSize), made anew when their number or size changed. `local` are the inputs of
  /// the probes' shade pass (no ray results, no probes: one bounce).
  void update(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade,
              const ShadeInputs& local, const std::vector<Bounds>& instances, int faceSize);
  /// Re-renders only the probes in `slots` (all six faces each); their number must be unchanged since
  /// the last update().
  void updateSlots(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade, const ShadeInputs& local,
                   const std::vector<Bounds>& instances, const std::vector<int>& slots);
  void release();
  /// The cube-map array (layer = probe slot) the shade pass looks reflected directions up in.
  const Texture& cubes() const { return cubes_; }
  int probeCount() const { return count_; }
  int faceSize() const { return faceSize_; }

 private:
  Texture cubes_, ids_, depth_;
  Texture sampledDepth_;  // what toon outlines read while depth_ is attached to the face (64 KiB)
  Framebuffer rasterFbo_, shadeFbo_;
  Framebuffer mipRead_, mipDraw_;  // the mip chain of a re-rendered probe, level by level
  std::vector<std::uint32_t> probes_;  // the instance of each slot (GpuScene::probes(): the probe layout)
  std::vector<std::uint8_t> seen_;     // the face being drawn: which instances it may see (seenBy)
  int count_ = 0;
  int faceSize_ = 0;
  int levels_ = 0;  // faceSize² down to 1²
};

}  // namespace tandem::gl
