#pragma once
// The CPU ray pass on Embree 3 (no GL here: its tests need no context).
//
// Hybrid use (Renderer, every frame):
//   prepare:  setScene() once per scene; updateTransforms() when instances moved (top-level
//             commit only). Never called while trace() runs.
//   rays:     trace(scene, camera, settings, visibility, out)
// Reference use: renderReference() — primary visibility by camera rays, N×N jittered samples.
//
// Ray grid: with settings.rayScale = s, the grid is ceil(W/s) × ceil(H/s); grid pixel (gx, gy) stands for
// full-resolution pixel (min(gx·s + s/2, W−1), min(gy·s + s/2, H−1)), whose ids and camera ray it uses.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/Radiosity.h"
#include "core/ResolvedPixel.h"
#include "rt/RayBuffers.h"
#include "tandem/FrameStats.h"
#include "tandem/Image.h"
#include "tandem/PixelTrace.h"
#include "tandem/Progress.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::rt {

struct RayCapture;
struct RayReuse;
struct RayTracerState;
class ShadowCertainty;
struct FrameShading;

// VisibilityBuffer and RayOutputs: rt/RayBuffers.h.

class RayTracer {
 public:
  /// threads = 0: all hardware threads. Fails (error value) if Embree cannot create a device.
  static Result<std::unique_ptr<RayTracer>> create(int threads = 0);
  ~RayTracer();
  RayTracer(const RayTracer&) = delete;
  RayTracer& operator=(const RayTracer&) = delete;

  /// Builds the two-level Embree scene: one static BLAS per mesh, instanced. Embree errors (out of
  /// memory included) come back as an error value and leave the previous scene in place. `anchor`: the origin
  /// of render space (core/RenderSpace.h; none: the scene camera's position, renderAnchor).
  Result<void> setScene(const Scene& scene, float shutter = 0.0f, std::optional<glm::vec3> anchor = std::nullopt);
  /// Re-reads every instance's transform (static or dynamic) and motion and commits the top level only: no
  /// mesh's BVH is rebuilt. `shutter` (Camera::shutter): instances that move while it is open get Embree
  /// motion-blur time steps (docs/motion-blur.md); every frame's rays then carry a time. `anchor`: a new origin
  /// of render space (the floating origin: anchorDue), every instance re-read relative to it.
  void updateTransforms(const Scene& scene, float shutter = 0.0f, std::optional<glm::vec3> anchor = std::nullopt);
  /// The shutter the ray scene's motion was made for (0 before setScene).
  float shutter() const;
  /// The ray scene's origin of render space (setScene's or the last updateTransforms'; 0 before setScene).
  glm::vec3 anchor() const;

  /// The hybrid ray pass: per grid pixel, the exact primary hit of the visible triangle, then shadow
  /// rays, Whitted reflection and refraction as the settings ask. Never fails. With `reuse` (the camera
  /// still, something moved: rt/RayReuse.h), primary shadow rays clear of what moved keep the answers of
  /// the frame `reuse` holds, which must not be `out`. With `only` (one byte per full-resolution pixel, an
  /// adaptive round's selection), a grid pixel whose stand-in pixel is 0 there is traced as the sky is:
  /// nothing; `visibility` itself is read, never changed.
  void trace(const Scene& scene, const Camera& camera, const FrameSettings& settings,
             const VisibilityBuffer& visibility, RayOutputs& out, const RayReuse* reuse = nullptr,
             std::span<const std::uint8_t> only = {});

  /// Exact solids in the hybrid frame (docs/csg.md, "In the raster frame"): each pixel the raster drew with an
  /// exact solid's proxy is resolved by its camera ray, which finds the solid's exact hit, a surface behind the
  /// proxy, or nothing. `visibility` (read back from the raster) then holds what the ray found there (a hit
  /// on a solid as (instance + 1, kExactTriangle); a pixel it changed loses its GL shadow proof), and `out` one record per pixel it changed (in an order fixed for any thread count)
  /// for the GL's visibility buffer. While the camera is within a proxy's bounds (the raster cannot see the
  /// proxy's near side there) every pixel is resolved. The rays are added to `counts.resolved`. Nothing to
  /// do, and `out` empty, in a scene without exact solids.
  void resolveExact(const Scene& scene, const Camera& camera, VisibilityBuffer& visibility,
                    std::vector<ResolvedPixel>& out, RayCounts& counts);

  /// Pure ray-traced frame (linear radiance, before tone mapping), settings.referenceSpp² jittered
  /// samples per pixel, seeded per pixel so the image does not depend on the thread count.
  void renderReference(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                       RayCounts& counts);

  /// The ray tree of one pixel, re-run on the calling thread with the inputs of a trace() (ray-grid pixel
  /// (gx, gy)) or a renderReference() (pixel (x, y)) on the current scene: rt/PixelTrace.h. Debugging
  /// calls, apart from the passes: their loops have no hook for them.
  PixelTrace tracePixel(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                        const VisibilityBuffer& visibility, int gx, int gy) const;
  PixelTrace tracePixelReference(const Scene& scene, const Camera& camera, const FrameSettings& settings, int x,
                                 int y) const;

  /// Primary visibility by camera rays through pixel centres: the same buffer the raster pass writes.
  void castVisibility(const Camera& camera, int width, int height, VisibilityBuffer& out);

  int threads() const;
  /// The radiosity solution the passes read in place of the ambient term (FrameShading::forFrame); null: none.
  /// Never called while a pass runs.
  void setRadiosity(std::shared_ptr<const RadiosityField> field);
  /// Bytes Embree reports in use on this tracer's device.
  std::size_t embreeBytes() const;
  /// Hybrid shadows (FrameSettings::hybridShadows): how many times the light-space maps were built (after
  /// the geometry or a light changed), and the bytes they hold.
  std::size_t shadowMapBuilds() const;
  /// Milliseconds the last trace() spent building them (0 when it did not).
  double lastShadowMapMs() const;
  std::size_t shadowMapBytes() const;
  /// Hybrid shadows proved in the GL (gl/ShadowProofPass.h): the maps a trace() with these inputs reads, built
  /// now when the geometry or a light changed (lastShadowMapMs), or null where it reads none (no hybrid
  /// shadows, motion blur) or the GL copy's render space (`glAnchor`) is not the ray scene's.
  const ShadowCertainty* shadowMapsFor(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                                       glm::vec3 glAnchor);

  /// trace() and renderReference() call `progress` (when set) as each tile finishes (tandem/Progress.h).
  void setProgressCallback(RayPassProgressCallback progress);
  /// Limit on Embree's memory (bytes, 0 = none): setScene fails with an out-of-memory error beyond it.
  void setEmbreeMemoryLimit(std::size_t bytes);

 private:
  // The bench's capture, its re-trace and per-ray shadow rays (rt/RayTracerBench.h) go through these;
  // the frame's calls pass no capture and batched shadow rays.
  friend class RayTracerBench;
  void hybridPass(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                  const VisibilityBuffer& visibility, RayOutputs& out, RayCapture* capture, bool batchedShadowRays,
                  const RayReuse* reuse = nullptr, std::span<const std::uint8_t> only = {});
  void referencePass(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                     RayCounts& counts, RayCapture* capture);
  // Capture: NoCapture or TileCapture (rt/TileCapture.h).
  template <class Capture>
  void hybridPassWith(const Scene& scene, const Camera& camera, const FrameSettings& settings,
                      const VisibilityBuffer& visibility, RayOutputs& out, RayCapture* capture,
                      bool batchedShadowRays, const RayReuse* reuse, std::span<const std::uint8_t> only);
  template <class Capture>
  void referencePassWith(const Scene& scene, const Camera& camera, const FrameSettings& settings, ImageF& out,
                         RayCounts& counts, RayCapture* capture);

  // Builds the hybrid shadows' maps when the geometry or a light changed since they were built.
  const ShadowCertainty& updateShadowMaps(const Scene& scene, const FrameShading& frame);
  explicit RayTracer(std::unique_ptr<RayTracerState> impl);
  std::unique_ptr<RayTracerState> impl_;  // rt/RayTracerState.h
};

}  // namespace tandem::rt
