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

  /// Renders a map for every direct light with castShadows; frees everything when there is none.
  void update(const Scene& scene, const GpuScene& gpu, const VisibilityPass& raster, const Bounds& world);
  void release();
  /// Binds the maps (kUnitShadowMaps, kUnitShadowCubes, and the cubes' depths at kUnitShadowCubesDepth) and the
  /// per-light records (kBlockShadows).
  /// Binds the maps to their units; a kind the scene has none of (no spot or directional light, no point
  /// light) gets a placeholder of its type.
  void bind(Placeholders& placeholders) const;
  int mapCount() const { return layers_; }
  int cubeCount() const { return cubes_; }

 private:
  void reserveTargets(int layers, int cubes);
  Texture maps_, cubeMaps_;
  Sampler cubeDepths_;  // reads cubeMaps_ without depth compare: the blocker search of area lights' soft shadows
  Framebuffer fbo_;
  Buffer records_;
  int layers_ = 0, cubes_ = 0;
};

}  // namespace tandem::gl
