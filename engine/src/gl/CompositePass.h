#pragma once
// Shade + composite (shade.frag: visibility buffer → linear radiance, ray results added) and the output
// pass (tonemap.frag: linear → 8-bit sRGB), plus the textures the ray results are uploaded into and the
// captures of the final frame. Channel table: docs/gbuffer.md.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gl/Bindings.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/RasterEffects.h"
#include "gl/VisibilityPass.h"
#include "tandem/Camera.h"
#include "tandem/Image.h"
#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::gl {

// RayInput and ProbeEffect bits, texture units: gl/Bindings.h (shaders/bindings.glsl).

struct ShadeInputs {
  glm::vec3 background{0.0f};
  glm::vec3 ambient{0.0f};  // Ia
  int rayInputs = 0;        // RayInput bits uploaded this frame
  int rayScale = 1;
  int rayWidth = 0, rayHeight = 0;
  DebugView debugView = DebugView::Final;
  const ShadowMaps* shadowMaps = nullptr;  // raster shadows: per-light visibility from these maps
  const ReflectionProbes* probes = nullptr;
  int probeEffects = 0;                    // ProbeEffect bits (with `probes`)
  FresnelMode fresnel = FresnelMode::Exact;
  bool fresnelWeighted = true;             // wR = kr + kt·F, wT = kt·(1 − F); else wR = kr, wT = kt
};

class CompositePass {
 public:
  static Result<CompositePass> create();

  /// Reallocates the frame's targets when the size changes, the largest (linear radiance, RGBA32F)
  /// first, so a size the driver cannot hold fails before anything else is allocated. An error names
  /// what the GL refused; the pass then holds no targets (readImage() is empty) until a resize succeeds.
  Result<void> resize(int width, int height);
  /// Drops the frame's targets.
  void release();
  /// The GL memory resize(width, height) allocates.
  static std::size_t targetBytes(int width, int height);
  /// Ray results on the ray grid (row 0 = top, as RayOutputs holds them). The grid's texture is made
  /// again when the grid's size changes: an error names it when the GL refuses, and nothing is uploaded.
  Result<void> uploadLightMask(int width, int height, const std::uint32_t* mask);
  Result<void> uploadReflected(int width, int height, const glm::vec4* rgba);
  Result<void> uploadTransmitted(int width, int height, const glm::vec4* rgba);
  /// A finished linear frame (reference mode), row 0 = top; replaces the shade pass's output.
  void uploadLinear(const ImageF& image);

  /// Whether the shade pass for these scene features and this view reads depth in the shader (the toon
  /// outlines' depth test, the depth view). Such a pass samples a copy of the depth: the depth itself
  /// stays attached for the early depth test, and sampling it there would be a feedback loop.
  static bool samplesDepth(const SceneFeatures& features, DebugView view);
  /// The frame-size depth copy that shade() samples when samplesDepth(): made on first need, kept until
  /// the frame size changes; an error names it when the GL refuses.
  Result<void> reserveSampledDepth();

  /// `camera` in render space (GpuScene::anchor()), as the visibility pass drew with.
  void shade(const GpuScene& scene, const VisibilityPass& visibility, const Camera& camera, const ShadeInputs& in);
  /// The same shade pass into another colour target of width × height (a reflection probe's face) from
  /// that view's ids and depth (which it attaches to `framebuffer` as its read-only depth). When
  /// samplesDepth(), `depth` is copied into `sampledDepth` (GL_DEPTH_COMPONENT32F, at least width ×
  /// height), which the shader reads instead.
  void shadeInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids,
                 const Texture& depth, const Texture* sampledDepth, const Camera& camera, const ShadeInputs& in);
  /// Exposure, tone map and sRGB encoding into the RGBA8 target; debug views that are already display
  /// values (depth, ids, normals, light mask) pass through.
  void output(float exposure, ToneMap toneMap, DebugView view);

  Image readImage() const;
  ImageF readLinear() const;
  /// Draws the RGBA8 frame into the default framebuffer, letterboxed to keep its aspect.
  void present(int framebufferWidth, int framebufferHeight) const;

 private:
  /// The shade program compiled for this frame's features (compiled on first use, then cached).
  const Program& shadeVariant(const SceneFeatures& features, const ShadeInputs& in);

  std::map<std::string, Program> shadeVariants_;
  Program toneMap_;
  VertexArray emptyVao_;  // core profile draws need a VAO even with no attributes
  Texture linear_, display_;
  Framebuffer linearFbo_, displayFbo_;
  Texture lightMask_, reflected_, transmitted_;
  Texture sampledDepth_;  // frame size, with reserveSampledDepth()
  int width_ = 0, height_ = 0;
};

}  // namespace tandem::gl
