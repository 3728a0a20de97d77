#pragma once
// The raster pass: the visibility G-buffer (instance + 1, triangle) over reversed-Z float depth, and its
// read-back for the ray pass. Channel table: docs/gbuffer.md.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gl/GlObjects.h"
#include "core/ResolvedPixel.h"
#include "gl/GpuScene.h"
#include "gl/PixelReadback.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"

namespace tandem::gl {

class VisibilityPass {
 public:
  static Result<VisibilityPass> create();

  /// Reallocates the targets when the frame size changes. An error names the target the GL refused
  /// (out of memory, an incomplete framebuffer); the pass then holds no targets (width() 0) until a
  /// resize succeeds. The ids' read-back memory stays (a pending read-back is dropped): a dynamic resolution
  /// that steps down and back up does not map it again; a larger frame makes it again larger, one needing under
  /// a quarter of it smaller.
  Result<void> resize(int width, int height);
  /// Drops the targets (width() 0) and the read-back memory.
  void release();
  /// The GL memory resize(width, height) allocates.
  static std::size_t targetBytes(int width, int height);
  /// `camera` in render space, the space of the GL copy: toRenderSpace(cameraW, scene.anchor()).
  void render(const GpuScene& scene, const Camera& camera);
  /// The same raster into another target (a shadow map's depth, a probe face's ids + depth) of
  /// width × height pixels, seen from `camera` (aspect width / height); `excluded` (an instance index)
  /// is left out when given. Clears the target's depth to far (0) and its colour 0 (if any) to 0.
  /// `which`: all instances, or the static or dynamic ones only; with `clear` false the target keeps what it
  /// holds and the draw adds to it (the dynamic instances over a copy of what the static ones drew).
  /// `seen`: only the instances it flags (seenBy: those the view may see), the same target to the bit.
  /// `peelBehind` (a depth texture of the target's size): only fragments strictly behind it (depth peeling;
  /// its variant, compiled on first use, discards, so it loses the early depth test).
  void renderInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Camera& camera,
                  std::optional<std::uint32_t> excluded = std::nullopt,
                  GpuScene::Instances which = GpuScene::Instances::All, bool clear = true,
                  const std::vector<std::uint8_t>* seen = nullptr, const Texture* peelBehind = nullptr) const;
  /// The ids channel, row 0 = top (the ray pass's convention); `ids` is resized to width × height.
  void readIds(std::vector<glm::uvec2>& ids) {
    startReadIds();
    finishReadIds(ids);
  }
  /// readIds in two halves (gl/PixelReadback.h): start() after render() fences the GL's copy of the ids into
  /// mapped buffer memory, finish() waits for it and copies the rows out top-down. Draws into this pass
  /// between the two do not change what finish() gives.
  void startReadIds() { idReadback_.start(fbo_, kChannelIds, width_, height_); }
  bool readingIds() const { return idReadback_.pending(); }
  void finishReadIds(std::vector<glm::uvec2>& ids) { idReadback_.finish(ids); }

  /// Exact solids (docs/csg.md, "In the raster frame"): writes the ray pass's resolved pixels into this
  /// frame's visibility buffer (after render()), one point each: ids and depth, and for hits on a solid the
  /// exact-hits channel (made at the frame's size on first use). The program is compiled on first use. An
  /// error names what the GL refused.
  Result<void> patch(std::span<const ResolvedPixel> pixels);
  /// The exact-hits channel patch() writes (RGBA32F, full res: a solid's outward normal and t along the
  /// pixel's camera ray where ids.y = kExactTriangle; undefined elsewhere), empty before the first patch.
  const Texture& exactHits() const { return exactHits_; }

  const Texture& ids() const { return ids_; }
  const Texture& depth() const { return depth_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Program program_;
  Program maskProgram_;  // TD_ALPHA_MASK: discards texels of MASK materials under their cutoff
  mutable Program peelPrograms_[2];  // TD_PEEL, without and with TD_ALPHA_MASK (made on first use)
  Texture ids_, depth_;
  Framebuffer fbo_;
  // patch(): its program, the records' buffer, and the framebuffer of ids + exact hits + depth.
  Program resolveProgram_;
  Buffer resolved_;
  std::size_t resolvedCapacity_ = 0;
  Texture exactHits_;
  Framebuffer resolveFbo_;
  VertexArray emptyVao_;
  PixelReadback idReadback_;  // the ids' read-back memory (8 bytes a pixel), made by the first read
  void releaseTargets();      // release() but for the read-back memory
  int width_ = 0, height_ = 0;
};

}  // namespace tandem::gl
