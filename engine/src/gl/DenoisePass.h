#pragma once
// The spatiotemporal filter (shaders/denoise.frag, docs/denoise.md; FrameSettings::denoise): the shade pass
// draws the frame's noisy linear radiance and the filter's guides into shadeFramebuffer(); filter() then
// accumulates the demodulated illumination over frames along the motion vectors (temporal stage), estimates
// its variance and runs the edge-aware a-trous iterations; a compose stage (or on a coarser ray grid the
// upsampling) takes them back to radiance, and the anti-aliasing writes linear radiance and the display into
// the frame's output. It keeps the last frame's guide, filtered illumination and moments: the history.
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

#include "gl/GlObjects.h"
#include "gl/MovedInstances.h"
#include "gl/Program.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::gl {

class DenoisePass {
 public:
  static Result<DenoisePass> create();

  /// Its targets at the frame's size, the temporal and a-trous stages' on the ray grid of 1/`gridScale` of it
  /// (FrameSettings::rayScale: each grid pixel's own sample is what they filter); made again when either
  /// changes, the history then forgotten. An error names what the GL refused, and the pass then holds none.
  Result<void> reserve(int width, int height, int gridScale);
  /// The GL memory reserve(width, height, gridScale) allocates.
  static std::size_t targetBytes(int width, int height, int gridScale);
  bool holds() const { return width_ > 0; }
  /// The shade pass's target for this frame: the sampled radiance divided by its modulation at colour
  /// attachment 0, the guide, the motion and the radiance past the filter at 2, 3 and 4
  /// (ShadeInputs::denoiseGuides).
  GLuint shadeFramebuffer() const { return targets_.shadeFbo.id(); }
  /// Filters the frame the shade pass just drew into the frame's output, `linear` radiance and its `display`
  /// (OutputPass's targets, the frame's size). `camera` in render space, as the shade pass drew with;
  /// `history` false: the last frame is not this frame's past (new scene, size, no motion inputs), nothing of it
  /// is reused. `ids`: the visibility pass's (the instances the guide's tags stand for); `moved`: what moved
  /// since the last frame. `maxHistory`: frames the temporal mean spans at most. The background pixels keep
  /// the shade pass's radiance (its exact target holds the environment there).
  void filter(const Texture& linear, const Texture& display, const Texture& ids, const Camera& camera, bool history,
              const MovedInstances& moved, float exposure, ToneMap toneMap, int maxHistory);
  /// The next frame has no past (a frame was drawn without the filter in between).
  void forget() { historyHeld_ = false; }
  /// Its targets released (and the history with them), its programs kept: reserve() before the next filter().
  void release();
  /// What the last filter() left for the next frame to reproject: the filter texels (denoise.glsl) after the
  /// first a-trous iteration, of the grid's size. For tests and debugging.
  const Texture& history() const { return targets_.history[1 - current_]; }

 private:
  // (temporalStill_: the temporal stage without the moved-instance test, for frames where nothing moved)
  Program temporal_, temporalStill_, atrous_, compose_, upsample_, antiAlias_;
  VertexArray emptyVao_;
  // The targets (reserve): of the frame's size, the shade pass's (noisy illumination, the radiance past the
  // filter, guide, motion), the filtered frame and this frame's and the last frame's anti-aliased one; of the
  // grid's, the a-trous iterations' two scratch texels, the depth that marks where they filter, and this
  // frame's and the last frame's history and moments. The pairs alternate.
  struct Targets {
    Texture noisy, exact, guide, motion, scratchA, scratchB, filtered;
    Texture skip;  // depth: 1 where the a-trous iterations filter, 0 where the temporal stage found it settled
    std::array<Texture, 2> history, moments, antiAliased;
    std::array<Framebuffer, 2> temporalFbo, historyFbo;
    Framebuffer shadeFbo, scratchAFbo, scratchBFbo, filteredFbo;
    // The frame's output with this pass's anti-aliased history beside it (the output's textures attached each
    // frame).
    std::array<Framebuffer, 2> outputFbo;
  };
  Targets targets_;
  int current_ = 0;  // which of the pairs this frame writes
  bool historyHeld_ = false;
  int width_ = 0, height_ = 0;
  int gridScale_ = 1, gridWidth_ = 0, gridHeight_ = 0;
};

}  // namespace tandem::gl
