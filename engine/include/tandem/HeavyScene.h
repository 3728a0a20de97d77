#pragma once
// Scenes of a known triangle count, for measuring how each stage's cost grows with geometry
// (tandem-bench --heavy). Deterministic: the same arguments give the same scene.
//
//   Scene s = makeHeavyScene(500'000);   // s.triangleCount() == 500'000 exactly
//
// Contents, so every effect has work to do: a checkerboard floor, a 4×4 grid of diffuse / Phong / toon
// spheres that carry most of the triangles, a mirror sphere, a glass sphere (IOR 1.5), a mirror panel,
// a point light, a spot light, a directional light and ambient light, and a camera that sees them all.
#include <cstddef>

#include "tandem/Scene.h"

namespace tandem {

struct HeavySceneOptions {
  int gridSide = 4;          // the diffuse spheres form gridSide × gridSide, >= 1
  float sphereShare = 0.75f; // fraction of the triangles in the grid spheres; the floor takes the rest
  bool mirrors = true;       // mirror sphere and mirror panel (kr > 0)
  bool glass = true;         // glass sphere (kt > 0)
};

/// Smallest triangle count makeHeavyScene can hit exactly (fixed objects plus the smallest spheres).
std::size_t heavySceneMinTriangles(const HeavySceneOptions& options = {});

/// A scene with exactly max(targetTriangles, heavySceneMinTriangles(options)) triangles.
Scene makeHeavyScene(std::size_t targetTriangles, const HeavySceneOptions& options = {});

}  // namespace tandem
