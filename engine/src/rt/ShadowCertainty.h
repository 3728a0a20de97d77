#pragma once
// Hybrid shadows: light-space maps that answer a shadow ray without tracing it where they can prove
// what Embree would answer, and say "unknown" everywhere else (the ray then decides). The argument that a
// decided ray equals the traced one is in docs/shadows.md; in short:
//
// - Seen from a point light, a shadow ray (the segment from the hit to the light) projects to a single
//   direction, within a bound set by its offset origin; seen along a directional light, to a single point
//   of an orthographic map. Whatever can block it lies in the light-space frustum of that texel.
// - The maps are made by exact conservative rasterization on the CPU: each texel lists the kCandidates
//   triangles nearest the light among those whose projection touches its square grown by kMarginTexels,
//   and a lower bound of the depth of any it had to leave out. GL 4.5 core has no conservative
//   rasterization (only vendor extensions), and the ray pass's own hit, offset origin and triangle ids are
//   what the argument needs, so the maps are the CPU's.
// - The ray itself (origin, direction, length: exactly Embree's) is then tested against the listed
//   triangles in float with a margin a hundred times the rounding (Embree's, in object space, and ours): lit when it misses every one
//   but the hit's own and nothing left out lies in front of the hit; shadowed when it crosses the interior
//   of one that lets no ray through (no alpha-mask filter), which Embree's watertight test cannot miss.
// - Everything else (grazing rays, texels with too many triangles, points near the light) is unknown.
//
// The maps depend on geometry and lights only, not on the camera: they are rebuilt when an instance
// moves or a light changes, and serve primary and secondary hits alike.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/Shading.h"
#include "rt/SurfaceShading.h"
#include "tandem/Scene.h"

namespace tandem::rt {

class EmbreeScene;

/// What a map says of one shadow ray.
enum class ShadowAnswer : std::uint8_t { Unknown = 0, Lit = 1, Shadowed = 2 };

class ShadowCertainty {
 public:
  static constexpr int kCubeSize = 512;    // point and spot lights: texels per cube-face side
  static constexpr int kOrthoSize = 1024;  // directional lights: texels per side
  /// How far (in texels) beyond its own square a texel records geometry: the room a query's ray may
  /// stray from the texel's direction (offset origin, rounding) and still be covered by it.
  static constexpr float kMarginTexels = 0.25f;
  /// A query's ray may stray this much less than kMarginTexels from its texel (the rest covers rounding).
  static constexpr float kQueryMargin = kMarginTexels - 0.03f;
  /// Relative depth margin: contacts closer than this fraction of the distance to the light go to rays.
  static constexpr float kDepthRel = 1e-4f;
  /// The exact tests' margin, relative to the magnitudes involved: a hundred times the rounding of Embree's
  /// float test, of the two transforms of the vertices (Embree's and build()'s) and of the tests' own arithmetic.
  static constexpr float kRelativeMargin = 1e-5f;
  /// Texels are stored in kBlock × kBlock blocks (texelIndex in ShadowCertainty.cpp; the GL's proof pass too).
  static constexpr int kBlock = 16;

  /// One map per direct light that casts shadows (frame.lights order), from the Embree scene's
  /// render-space transforms. `threads` as RayTracer's (run inside its arena).
  void build(const Scene& scene, const EmbreeScene& embree, const FrameShading& frame, int threads);
  void clear();
  /// Whether build() saw these lights (position, direction, kind, castShadows): the maps' other input,
  /// the geometry, is tracked by the caller.
  bool builtFor(const FrameShading& frame) const;

  /// The answer for the shadow ray from `hit` towards light `light`: Embree's ray from originW along dirW
  /// over [0, tFar] (Whitted::shadowRay's).
  ShadowAnswer classify(std::size_t light, const ShadowPoint& hit, glm::vec3 originW, glm::vec3 dirW, float tFar) const;

  std::size_t bytes() const;
  bool empty() const { return maps_.empty(); }
  /// Changes with every build() and clear(): what a copy of the maps (the GL's, gl/ShadowProofPass.h) compares
  /// to tell that it is stale.
  std::uint64_t generation() const { return generation_; }

  static constexpr int kCandidates = 6;
  /// One texel: the triangles touching it nearest the light (by a lower bound of their depth over it),
  /// and a lower bound of the depth of every other one. Depths grow away from the light; +inf: none.
  struct Texel {
    std::uint32_t triangles[kCandidates];  // global ids (instance base + triangle); ~0u: none
    float depths[kCandidates];             // their depth bounds, ascending
    float restDepth;                       // bound of those left out (≥ every one kept)
  };
  enum class Kind : std::uint8_t { None, Cube, Ortho };
  struct Map {
    Kind kind = Kind::None;
    int size = 0;
    glm::vec3 origin{0.0f};   // cube: the light; ortho: unused
    glm::vec3 axes[6][3];     // per face: S, T (the map's x, y) and A (depth); ortho: face 0, A towards the light
    float extent = 1.0f;      // cube: tangent half-range of a face (> 1: guard band); ortho: half-width
    glm::vec2 centre{0.0f};   // ortho: S, T of the map's centre
    float top = 0.0f;         // ortho: A of depth 0
    float nearZ = 0.0f;       // cube: faces start here; nothing within 4·nearZ of the light but nearLight
    std::vector<std::uint32_t> nearLight;  // cube: the triangles within 4·nearZ of the light
    float depthEps = 0.0f;    // ortho: absolute depth margin (scene-sized)
    std::vector<Texel> texels;  // faces × size × size
    // What build() was given for this light, to tell when it must be built again.
    shading::GpuLight light{};
  };
  /// A triangle as classify() tests rays against it: its plane and edges (unit normals, into the triangle)
  /// and the largest magnitude of its coordinates (the tests' rounding scale).
  struct TriangleTest {
    glm::vec4 plane{0.0f};   // n, n·a
    glm::vec4 edges[3];      // inward normal, its offset
    float magnitude = 0.0f;
    bool valid = false;      // false: no area (every test is unsure)
  };

 private:
  std::vector<Map> maps_;                  // frame.lights order; Kind::None: no map (unknown everywhere)
  std::vector<std::uint32_t> triangleBase_;  // per instance: its first global triangle id
  std::vector<TriangleTest> tests_;          // per global triangle, in render space
  std::vector<std::uint8_t> blocksAll_;      // per global triangle: no alpha-mask filter on its instance
  std::uint64_t generation_ = 0;

 public:
  // The maps as the GL's proof pass copies them (read-only).
  const std::vector<Map>& maps() const { return maps_; }
  const std::vector<TriangleTest>& tests() const { return tests_; }
  const std::vector<std::uint8_t>& blocksAll() const { return blocksAll_; }
  const std::vector<std::uint32_t>& triangleBase() const { return triangleBase_; }
};

}  // namespace tandem::rt
