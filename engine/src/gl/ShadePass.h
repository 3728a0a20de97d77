#pragma once
// The shade pass (shade.frag): the visibility buffer → linear radiance, local shading per docs/shading.md
// with the raster effects and the ray results added; its compiled variants, and the textures the ray
// results are uploaded into. It draws into a target it is given (the output pass's linear radiance, or a
// probe's face). Channel table: docs/gbuffer.md; binding points: gl/Bindings.h.
#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "gl/Bindings.h"
#include "gl/MovedInstances.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/Placeholders.h"
#include "gl/Program.h"
#include "gl/RasterEffects.h"
#include "gl/RayChannels.h"
#include "gl/ShadeVariant.h"
#include "gl/VisibilityPass.h"
#include "tandem/Camera.h"
#include "tandem/Result.h"
#include "tandem/Settings.h"

namespace tandem::gl {

struct ShadeInputs {
  glm::vec3 background{0.0f};
  glm::vec3 ambient{0.0f};  // Ia
  /// The radiosity solution replaces the ambient term where it covers a surface (GpuScene::uploadRadiosity
  /// holds it): C·H per pixel, H interpolated over the patch grid, plus the unshot light's estimate.
  bool radiosity = false;
  glm::vec3 radiosityAmbient{0.0f};
  int radiosityInstances = 0;  // RadiosityField::instanceCount
  /// RayInput bits the frame's plan can produce: the variant is compiled for these, so a frame whose
  /// rays leave a channel empty (nothing reflective in view) does not switch variants mid-game.
  int rayChannels = 0;
  int rayInputs = 0;        // RayInput bits uploaded this frame (a subset of rayChannels): a uniform
  int rayScale = 1;
  int rayWidth = 0, rayHeight = 0;
  DebugView debugView = DebugView::Final;
  const ShadowMaps* shadowMaps = nullptr;  // raster shadows: per-light visibility from these maps
  /// Raster shadows of area lights soft (percentage-closer soft shadows over the light's extent: 16 map
  /// reads a pixel) or hard (as a point light at the light's centre: 4). The probes take them hard: a probe
  /// face is 16 384 pixels shaded for a small reflection, which the penumbrae do not reach.
  bool softShadows = true;
  const Texture* probeCubes = nullptr;     // raster reflection/refraction: the probes' cube array
  int probeEffects = 0;                    // ProbeEffect bits (with probeCubes)
  /// With kProbeBehind: the view behind the see-through surfaces at the frame's size (gl/BehindView.h), which
  /// IOR-1 transmission reads at its own pixel.
  const Texture* behindView = nullptr;
  /// The layers of that view: alpha holds each pixel's distance from the camera (TD_DISTANCE_FAR for the sky),
  /// which sets how far a rough see-through surface in front of it blurs it.
  bool distanceInAlpha = false;
  FresnelMode fresnel = FresnelMode::Exact;
  bool fresnelWeighted = true;             // wR = kr + kt·F, wT = kt·(1 − F); else wR = kr, wT = kt
  /// Area lights: samples per pixel at the accumulation's sample `sampleIndex` (Camera::sampleIndex); the
  /// pass draws sequence points sampleIndex · lightSamples + k, rt::FrameShading's primaryLight, so the samples
  /// the ray pass traced.
  int lightSamples = 1;
  std::uint32_t sampleIndex = 0;
  /// The frame's pass (not the probes'): the target has the display at colour attachment 1 too, which
  /// the shader fills with tdDisplay(exposure, toneMap) of what it writes (OutputPass::fusedFramebuffer).
  bool fusedOutput = false;
  /// Exact solids: the visibility buffer's exact-hits channel (VisibilityPass::exactHits) where the frame's
  /// ids name hits on solids; set by shade() from the visibility pass (probe faces have none).
  const Texture* exactHits = nullptr;
  float exposure = 1.0f;
  ToneMap toneMap = ToneMap::Aces;
  /// The motion view (DebugView::Motion, docs/motion.md): per instance its previous-from-current transform in
  /// render space (a buffer texture, 4 RGBA32F texels an instance, the matrix's columns), the last frame's
  /// ids and visibility depth, its camera's projection (unjittered, times the view rotation) and position in
  /// render space. Without motionHistory there is no last frame: every pixel counts as newly seen.
  const Texture* motionInstances = nullptr;
  const Texture* previousIds = nullptr;
  const Texture* previousDepth = nullptr;
  glm::mat4 previousClipFromViewRotation{1.0f};
  glm::vec3 previousCameraPos{0.0f};
  glm::vec3 previousCameraForward{0.0f, 0.0f, -1.0f};  // its axis (unit): the filter's depths are along it
  bool motionHistory = false;
  /// The spatiotemporal filter (DenoisePass, docs/denoise.md): the target has its inputs at colour
  /// attachments 2-4 (the guide: depth, normal, instance and modulation; the motion; the radiance that goes
  /// past the filter), which the shader fills from the motion inputs above (motionHistory false: none known).
  bool denoiseGuides = false;
  /// With motionHistory: the filter may keep its history (no area light and no setting that shapes the light
  /// changed since the last frame).
  bool denoiseHistory = false;
  /// For the filter, not the shade pass: what moved since the last frame (DenoisePass::filter).
  MovedInstances moved;
};

/// The visibility pass's projection without the anti-aliasing jitter, times the camera's view rotation: a
/// render-space point p lands at clipFromViewRotation · (p − camera.posW, 1) (the motion view's projection).
inline glm::mat4 clipFromViewRotation(const Camera& camera, int width, int height) {
  return camera.clipFromView(float(width) / float(height)) * glm::mat4(glm::mat3(camera.viewFromWorld()));
}

/// What a ray-grid texture may hold, per tile of `size` texels (uploadReflected with GridTiles): 1 where
/// the tile may be non-zero, 0 where it is zero.
struct GridResidency {
  std::vector<std::uint8_t> mayBeNonZero;
  int size = 0;
};

/// What cameraRay builds a pixel's ray from: the origin, the forward axis (with the sub-pixel jitter folded
/// in: perspective), and the right and up axes scaled to the image plane's half extents (render space).
struct CameraVectors {
  glm::vec3 origin, forward, right, up;
};
CameraVectors cameraVectors(int width, int height, const Camera& camera);

/// The camera uniforms of shade_hit.glsl's cameraRay (TD_LOC_CAMERA_*, TD_LOC_ORTHOGRAPHIC, TD_LOC_FRAME_SIZE)
/// for a width × height frame; `camera` in render space. The shade pass's, and the shadow-proof pass's.
void setCameraUniforms(GLuint program, int width, int height, const Camera& camera);

class ShadePass {
 public:
  static Result<ShadePass> create();

  /// The ray pass's results on the ray grid (gl/RayChannels.h: one entry per channel, row 0 = top, as
  /// RayOutputs holds them; a channel without texels is left as it is). A channel's texture is made again when
  /// the grid's size (or the area lights' count) changes: an error names it when the GL refuses, and the rest
  /// is not uploaded. Tiled channels send only the tiles that hold something, and zero those that held
  /// something the last time: the texture still equals the texels to the bit. Returns the RayInput bits of
  /// the channels sent.
  Result<int> uploadRays(int width, int height, const RayGrid& grid);
  /// A channel's texture as the last upload left it (for tests: the grid it holds must be what was sent).
  const Texture& rayTexture(RayChannelId id) const { return rayGrid_[static_cast<std::size_t>(id)].texture; }
  /// The last shadow-mask pass's grid (RGBA16 array, 2 layers; empty before the first).
  const Texture& shadowMaskTexture() const { return shadowMask_; }

  /// Whether the shade pass for these scene features and this view reads depth in the shader (the toon
  /// outlines' depth test, the depth view). Such a pass samples a copy of the depth: the depth itself
  /// stays attached for the early depth test, and sampling it there would be a feedback loop.
  static bool samplesDepth(const SceneFeatures& features, DebugView view);
  /// The frame-size depth copy that shade() samples when samplesDepth(): made on first need, kept until
  /// the frame size changes; an error names it when the GL refuses.
  Result<void> reserveSampledDepth(int width, int height);
  /// Drops the frame-size depth copy (the frame's size changed).
  void releaseFrame();

  /// Shades the frame's visibility buffer into `framebuffer` (the frame's size). `camera` in render space
  /// (GpuScene::anchor()), as the visibility pass drew with. Raster shadows with rayScale > 1 are looked up
  /// on the ray grid first (the shadow-mask pass: one lookup per grid pixel, at the pixel it stands for) and
  /// gathered edge-aware as the rays' light mask is; an error names the mask's texture when the GL refuses
  /// it, and the frame is then shaded with a lookup per pixel.
  void shade(GLuint framebuffer, const GpuScene& scene, const VisibilityPass& visibility, const Camera& camera,
             const ShadeInputs& in);
  /// The same shade pass into another colour target of width × height (a reflection probe's face) from
  /// that view's ids and depth (which it attaches to `framebuffer` as its read-only depth). When
  /// samplesDepth(), `depth` is copied into `sampledDepth` (GL_DEPTH_COMPONENT32F, at least width ×
  /// height), which the shader reads instead.
  void shadeInto(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids,
                 const Texture& depth, const Texture* sampledDepth, const Camera& camera, const ShadeInputs& in);

 private:
  /// What a variant draws: the frame or a probe's face (with maps of its own, or the mask's grid), or the
  /// shadow-mask pass.
  enum class Role { Shade, ShadeWithMask, ShadowMask };
  /// The shade program compiled for this frame's features (compiled on first use, then cached).
  const Program& variant(const SceneFeatures& features, const ShadeInputs& in, Role role = Role::Shade);
  /// The uniforms and the inputs every role reads (camera, frame, lights, scene, ids, exact hits).
  void setUp(GLuint program, int width, int height, const GpuScene& scene, const Texture& ids, const Camera& camera,
             const ShadeInputs& in);
  /// shadeInto's draw, as `role` (Shade or ShadeWithMask).
  void draw(GLuint framebuffer, int width, int height, const GpuScene& scene, const Texture& ids, const Texture& depth,
            const Texture* sampledDepth, const Camera& camera, const ShadeInputs& in, Role role);
  /// The shadow-mask pass into shadowMask_ (gridWidth × gridHeight); false when its texture was refused.
  bool drawShadowMask(const GpuScene& scene, const VisibilityPass& visibility, const Camera& camera, const ShadeInputs& in,
                      int gridWidth, int gridHeight);

  /// The environment's uniforms and image (environment.glsl) on program p, the shade variant's or the sky's.
  void setEnvironment(GLuint p, const GpuScene& scene, const ShadeInputs& in);

  std::map<ShadeVariant, Program> variants_;
  Program sky_;  // sky.frag: the background pixels a software GL's depth test leaves (draw)
  bool depthSkipsSky_ = true;  // the early depth test keeps the shader off background pixels (a software GL)
  VertexArray emptyVao_;  // core profile draws need a VAO even with no attributes
  // The ray grid's channels, kRayChannels order.
  struct GridTexture {
    Texture texture;
    int width = 0, height = 0, layers = 0;
    GridResidency resident;  // tiled channels: the tiles that may hold a non-zero value
  };
  std::array<GridTexture, kRayChannelCount> rayGrid_;
  Texture sampledDepth_;  // frame size, with reserveSampledDepth()
  Texture shadowMask_;    // the ray grid, 2 layers (kChannelShadowMask)
  Framebuffer shadowMaskFbo_;
  int maskWidth_ = 0, maskHeight_ = 0;

  Placeholders placeholders_;  // for the samplers a variant declares and a frame gives nothing to
};

}  // namespace tandem::gl
