#pragma once
// Exact analytic solids and constructive solid geometry (CSG) along rays, in double precision: the
// mathematics of the exact-solid instances (docs/csg.md), with no GL and no Embree, so that the ray pass's
// user geometry, the tests and a CPU reference share one definition.
//
// A ray meets a solid in a list of crossings (where it passes through a surface, with the outward normal
// there), found over the whole line (t from −∞ to +∞), so that a ray starting inside a solid is classified as
// well as one starting outside: its first crossing past its origin says whether it leaves or enters.
//
// Shapes, each in its own space (a node's transform places it):
//   sphere    |p| <= r
//   box       |x| <= hx, |y| <= hy, |z| <= hz
//   cylinder  x² + z² <= r², |y| <= h
//   cone      x² + z² <= ρ(y)², |y| <= h, ρ linear from r0 at y = −h to r1 at y = +h (r1 = 0: a cone)
//   torus     (√(x² + z²) − R)² + y² <= r² (around the y axis; r < R, a ring)
//   plane     y <= 0 (a half-space, for CSG)
// Operations:
//   union         every surface of every operand (inner ones too: glass shows them; POV-Ray's union)
//   merge         the boundary of the union only (no inner surfaces)
//   intersection  the surfaces of each operand inside all the others
//   difference    the first operand minus the rest: its surfaces outside the rest, and theirs inside it,
//                 turned inside out
// Coincident faces: a surface on another operand's boundary counts as inside it for intersection and merge
// (an intersection keeps it, a merge drops it: two boxes touching face to face merge into one solid with no
// wall between), and the subtracted operand wins in a difference (a cut flush with the first operand's face
// opens that face). The tolerance is relative to the ray's coordinates (kCoincident).
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Solid.h"

namespace tandem::solid {

/// A ray in some space: origin and direction (any length; t is in units of it).
struct Ray {
  glm::dvec3 origin{0.0};
  glm::dvec3 dir{0.0, 0.0, 1.0};
};

/// Where a ray passes through a surface: its parameter, the outward unit normal there (in the space the ray
/// was given in) and which leaf the surface belongs to.
struct Crossing {
  double t = 0.0;
  glm::dvec3 normal{0.0, 1.0, 0.0};
  std::uint32_t leaf = 0;
  /// Whether the ray enters the solid there (it goes against the outward normal).
  bool entering(const glm::dvec3& dir) const { return glm::dot(normal, dir) < 0.0; }
};

/// A span of the line inside a solid: [t0, t1] (t0 may be −∞ for a half-space, t1 +∞).
struct Span {
  double t0 = 0.0, t1 = 0.0;
};

/// One solid's crossings along a ray and its inside spans (sorted by t, the spans disjoint).
struct Hits {
  std::vector<Crossing> crossings;
  std::vector<Span> spans;
};

/// The spans and crossings of a primitive in its own space (every root of its surface along the line).
Hits intersect(const Primitive& primitive, const Ray& ray);
/// Whether a point is inside a primitive (its surface included), in its own space.
bool contains(const Primitive& primitive, const glm::dvec3& p);
/// The outward unit normal of a primitive's surface at (or nearest) p.
glm::dvec3 normalAt(const Primitive& primitive, const glm::dvec3& p);

/// Limits on what a scene may build (the loaders refuse more, naming the JSON path).
inline constexpr int kMaxCsgDepth = 32;
inline constexpr std::size_t kMaxCsgNodes = 4096;

/// Checks a tree: indices in range, no cycles, every operation with at least one child (difference: the first
/// is the one subtracted from), depth and node count within the limits, finite invertible transforms, shape
/// sizes positive and finite (a cone's r0 or r1 may be 0, not both). Empty when fine, else what and where
/// ("node 3: ...").
std::string validate(const Solid& solid);

/// The crossings and inside spans of a whole tree along a ray given in the tree's own space (the root's
/// parent space).
Hits intersect(const Solid& solid, const Ray& ray);
/// Whether a point (in the tree's space) is inside the solid: the set the crossings bound.
bool contains(const Solid& solid, const glm::dvec3& p);

/// The first crossing with tNear < t < tFar, or false. `entering` tells whether the ray enters the solid there.
bool firstHit(const Hits& hits, double tNear, double tFar, Crossing& out);

/// Bounds of a solid in its own space (conservative: operations take their operands' union, an
/// intersection the smallest operand's, a difference its first's); a half-space reaches far.
struct Bounds {
  glm::dvec3 lo{0.0}, hi{0.0};
};
Bounds bounds(const Solid& solid);
/// The bounds of node `index`'s subtree, placed in its parent's space (its own transform applied).
Bounds nodeBounds(const Solid& solid, std::uint32_t index);

/// The relative tolerance of coincidence: two crossings of one ray closer than this times the ray's coordinate
/// scale are at the same point.
inline constexpr double kCoincident = 1e-12;

}  // namespace tandem::solid
