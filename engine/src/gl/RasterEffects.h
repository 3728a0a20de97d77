#pragma once
// The raster stand-ins for the ray pass's effects (EffectMode::Raster): shadow maps for the lights that
// cast shadows, and a cube-map reflection probe around every reflective or transparent object. Both are
// caches of the scene: the Renderer re-renders them only when something they depend on changed, and
// allocates them only when the scene and the settings use them. Formats and limits: docs/gbuffer.md.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "gl/Bindings.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/Placeholders.h"
#include "gl/VisibilityPass.h"
#include "tandem/Scene.h"

namespace tandem::gl {


struct Bounds {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  bool empty() const { return lo.x > hi.x; }
  void add(glm::vec3 p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void add(const Bounds& b) {
    if (!b.empty()) add(b.lo), add(b.hi);
  }
  glm::vec3 centre() const { return 0.5f * (lo + hi); }
};

/// Object-space bounds of every mesh (computed once per scene).
std::vector<Bounds> meshBounds(const Scene& scene);
/// Bounds of each instance in render space (world − anchor, core/RenderSpace.h): the space of the GL copy.
/// `shutter`, `u`: a moving instance where time u of the shutter puts it (core/Motion.h).
std::vector<Bounds> instanceBounds(const Scene& scene, const std::vector<Bounds>& meshes, glm::vec3 anchor,
                                   float shutter = 0.0f, float u = 0.5f);
/// Each instance's transform in render space as the GL copy draws it (instanceBounds' matrices).
std::vector<glm::mat4> instanceTransforms(const Scene& scene, glm::vec3 anchor, float shutter = 0.0f, float u = 0.5f);
/// Whether any point of the box may be seen through `clipFromWorld` (GL_ZERO_TO_ONE depth): false only when
/// its eight corners all lie beyond one plane of the frustum.
bool mayBeSeen(const glm::mat4& clipFromWorld, const Bounds& b);
/// One flag per instance: whether `clipFromWorld` may see its bounds (mayBeSeen). A face's draw takes only
/// those (VisibilityPass::renderInto's `seen`): a shadow map's or a probe's face sees a sixth of the scene.
void seenBy(const glm::mat4& clipFromWorld, const std::vector<Bounds>& instances, std::vector<std::uint8_t>& seen);

/// The camera of cube-map face `face` (GL's order +X, −X, +Y, −Y, +Z, −Z) seen from `eye`: a face rendered by
/// the ordinary raster and shade passes is then addressed by direction with no flip.
Camera cubeFaceCamera(glm::vec3 eye, int face, float nearZ, float farZ);

/// One record per direct light j, std140 (shade.frag's GpuShadow). Kind 0: no map (lit).
struct GpuShadow {
  glm::mat4 clipFromWorldRelative{0.0f};  // 2D maps: light clip space of (posW − origin)
  glm::vec4 originKind{0.0f};  // xyz origin (light position / orthographic eye), w kind (shade.frag TD_SHADOW_*)
  glm::vec4 params{0.0f};      // x layer (2D array layer or cube index), y near, z far, w texel size:
                               // world units (orthographic) or per unit of distance (perspective, cube)
};
static_assert(sizeof(GpuShadow) == 96, "GpuShadow must match its std140 layout in shade.frag");

/// Depth maps seen from the lights, reversed-Z like the main view (near → 1, cleared far → 0):
/// spot lights (cone up to 60°) a perspective 2D map, directional lights an orthographic 2D map fitted
/// to the scene's bounds, point lights (and wider spots) a cube map. Sampled with hardware depth compare.
class ShadowMaps {
 public:
  static constexpr int kMapSize = 1024;   // 2D maps, texels per side
  static constexpr int kCubeSize = 512;   // cube faces, texels per side

  /// Brings a map up to date for every direct light with castShadows; frees everything when there is none.
  /// `instances`, `transforms`: every instance's render-space bounds and transform as the GL copy draws them;
  /// `generation` changes when the GL copy was made anew (a new scene, other materials).
  /// What it draws again: everything when a static instance or the generation changed, or the scene outgrew
  /// the bounds the lights' cameras were fitted to (with a margin, so a rolling marble does not refit them);
  /// a light's maps whole when that light changed; otherwise only the map faces that see where a dynamic
  /// instance was or now is, each as its static part (kept from the last whole draw) with the dynamic
  /// instances drawn over it. Either way the maps
  /// are what drawing everything would give, bit for bit (tests/gl/RasterEffectsGLTest.cpp). `everything`
  /// forces the full draw.
  void update(const Scene& scene, const GpuScene& gpu, const VisibilityPass& raster, const std::vector<Bounds>& instances,
              const std::vector<glm::mat4>& transforms, std::uint64_t generation, bool everything = false);
  /// Map faces the last update drew (a 2D map is one face, a cube six), and how many there were.
  int facesDrawn() const { return facesDrawn_; }
  int faceCount() const { return layers_ + 6 * cubes_; }
  void release();
  /// Binds the maps (kUnitShadowMaps, kUnitShadowCubes, and the cubes' depths at kUnitShadowCubesDepth) and the
  /// per-light records (kBlockShadows).
  /// Binds the maps to their units; a kind the scene has none of (no spot or directional light, no point
  /// light) gets a placeholder of its type.
  void bind(Placeholders& placeholders) const;
  int mapCount() const { return layers_; }
  int cubeCount() const { return cubes_; }

 private:
  void reserveTargets(int layers, int cubes, bool withStatic);
  Texture maps_, cubeMaps_;
  // What the static instances alone draw into each face (only while the scene has dynamic instances).
  Texture staticMaps_, staticCubeMaps_;
  // What the maps were last drawn from, to tell what the next update must draw again.
  struct Drawn {
    bool valid = false;
    std::uint64_t generation = 0;
    std::vector<Light> lights;           // every direct light, as it was
    std::vector<glm::mat4> transforms;   // per instance
    std::vector<Bounds> bounds;          // per instance
    Bounds fit;                          // what the lights' cameras were fitted to
  } drawn_;
  std::vector<glm::mat4> faceClip_;  // per face (2D maps' layers, then 6 per cube): its clip-from-render-space
  std::vector<Camera> faceCamera_;
  int facesDrawn_ = 0;
  std::vector<std::uint8_t> seen_;  // the face being drawn: which instances it may see (seenBy)
  Sampler cubeDepths_;  // reads cubeMaps_ without depth compare: the blocker search of area lights' soft shadows
  Framebuffer fbo_;
  Buffer records_;
  int layers_ = 0, cubes_ = 0;
};

}  // namespace tandem::gl
