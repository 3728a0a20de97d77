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
/// direction up in it. Objects that span few texels of a face are drawn there with their coarse copies
/// (GpuScene::ensureProbeLod, which the caller runs first).
/// Per mesh: the widest angle between its normals (the vertex normals, or the faces' without them) and their
/// mean direction, π when they point every way: how far a mirror of that shape spreads what it reflects.
std::vector<float> meshNormalSpread(const Scene& scene);

/// Per probe slot, how much of the probe's detail the frame can show, in (0, 1]: the finest detail any object
/// reading it can show on screen against the face's texels. A curved mirror of D pixels whose normals spread
/// α shows the directions it reflects at about D / 2α pixels per radian (a sphere: D / 2π); a flat one, and
/// anything that refracts or blends (what is seen through it keeps the view's scale), at the view's own
/// H / fovY; a face has faceSize / 2 texels per radian at its centre. An object that holds the camera, or an
/// orthographic view, asks for everything. `view` in render space (the GL copy's), `instances` its bounds.
std::vector<float> probeDetail(const Scene& scene, const ProbeLayout& layout, const std::vector<Bounds>& instances,
                               const std::vector<float>& normalSpread, const Camera& view, int viewHeight,
                               int faceSize);

class ReflectionProbes {
 public:
  /// Re-renders the probes of the GL copy's layout (GpuScene::probes) with faces of `faceSize`² texels (a power
  /// of two; FrameSettings::probeSize), made anew when their number or size changed. `local` are the inputs of
  /// the probes' shade pass (no ray results, no probes: one bounce). `budget` > 0: only the first `budget`
  /// slots (the layout's order: the largest object first, then the farthest from those chosen), every other
  /// one the environment alone (a probe drawn with nothing in it, copied) until updateSlots draws it.
  /// Returns how many probes it drew.
  /// `detail` (probeDetail, per slot; empty: all 1) scales the texels an object spans in a face before its
  /// level of detail is chosen (probeLodLevel).
  int update(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade, const ShadeInputs& local,
             const std::vector<Bounds>& instances, int faceSize, int budget = 0, const std::vector<float>& detail = {});
  /// Re-renders only the probes in `slots` (all six faces each); their number must be unchanged since
  /// the last update().
  void updateSlots(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade, const ShadeInputs& local,
                   const std::vector<Bounds>& instances, const std::vector<int>& slots,
                   const std::vector<float>& detail = {});
  void release();
  /// The cube-map array (layer = probe slot) the shade pass looks reflected directions up in.
  const Texture& cubes() const { return cubes_; }
  int probeCount() const { return count_; }
  int faceSize() const { return faceSize_; }

 private:
  // Draws slot `slot`'s six faces (with nothing in them when `empty`) and its mip chain.
  void drawSlot(const GpuScene& gpu, const VisibilityPass& raster, ShadePass& shade, const ShadeInputs& local,
                const std::vector<Bounds>& instances, int slot, bool empty, float detail);
  Texture cubes_, ids_, depth_;
  Texture sampledDepth_;  // what toon outlines read while depth_ is attached to the face (64 KiB)
  Framebuffer rasterFbo_, shadeFbo_;
  Framebuffer mipRead_, mipDraw_;  // the mip chain of a re-rendered probe, level by level
  std::vector<std::uint32_t> probes_;  // the instance of each slot (GpuScene::probes(): the probe layout)
  std::vector<std::uint8_t> seen_;     // the face being drawn: which instances it may see (seenBy), at which
                                       // level of detail (GpuScene::draw)
  int count_ = 0;
  int faceSize_ = 0;
  int levels_ = 0;  // faceSize² down to 1²
};

}  // namespace tandem::gl
