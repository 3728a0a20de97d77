#pragma once
// The frame's output: its linear radiance target (what the shade pass draws, or a reference frame
// uploaded whole), the tone map into 8-bit sRGB (tonemap.frag), the captures of the final frame and the
// present into a window.
#include <cstddef>

#include "gl/GlObjects.h"
#include "gl/Program.h"
#include "tandem/Image.h"
#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::gl {

class OutputPass {
 public:
  static Result<OutputPass> create();

  /// Reallocates the frame's targets when the size changes, the largest (linear radiance, RGBA32F)
  /// first, so a size the driver cannot hold fails before anything else is allocated. An error names
  /// what the GL refused; the pass then holds no targets (readImage() is empty) until a resize succeeds.
  Result<void> resize(int width, int height);
  /// Drops the frame's targets.
  void release();
  /// The GL memory resize(width, height) allocates.
  static std::size_t targetBytes(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }

  /// The linear radiance target the shade pass draws into.
  GLuint linearFramebuffer() const { return linearFbo_.id(); }
  /// The linear target and the display at colour attachments 0 and 1: a shade pass with
  /// ShadeInputs::fusedOutput fills both, and output() is not needed for that frame.
  GLuint fusedFramebuffer() const { return fusedFbo_.id(); }
  /// The targets themselves (a pass that writes them with targets of its own beside them: DenoisePass).
  const Texture& linearTexture() const { return linear_; }
  const Texture& displayTexture() const { return display_; }
  /// A finished linear frame (reference mode), row 0 = top; replaces the shade pass's output.
  void uploadLinear(const ImageF& image);
  /// Exposure, tone map and sRGB encoding into the RGBA8 target; debug views that are already display
  /// values (depth, ids, normals, light mask) pass through.
  void output(float exposure, ToneMap toneMap, DebugView view);

  Image readImage() const;
  ImageF readLinear() const;
  /// Draws the RGBA8 frame into the default framebuffer, letterboxed to keep its aspect.
  void present(int framebufferWidth, int framebufferHeight) const;

 private:
  Program toneMap_;
  VertexArray emptyVao_;
  Texture linear_, display_;
  Framebuffer linearFbo_, displayFbo_, fusedFbo_;
  int width_ = 0, height_ = 0;
};

}  // namespace tandem::gl
