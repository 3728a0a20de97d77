#pragma once
// An exact solid: a tree of analytic shapes and CSG operations (docs/csg.md), as plain data a Mesh may carry
// (Mesh::exact). The shapes and operations are defined in docs/csg.md; engine/src/core/Solids.h intersects
// them with rays.
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace tandem::solid {

enum class Shape : std::uint8_t { Sphere, Box, Cylinder, Cone, Torus, Plane };
enum class Op : std::uint8_t { Leaf, Union, Merge, Intersection, Difference };

/// Shape parameters: sphere {r}; box {hx, hy, hz}; cylinder {r, h}; cone {r0, r1, h}; torus {R, r}; plane {}.
struct Primitive {
  Shape shape = Shape::Sphere;
  glm::dvec3 size{1.0};
};

/// A node of a CSG tree: a primitive (Leaf) or an operation on its children, placed by parentFromNode.
struct Node {
  Op op = Op::Leaf;
  Primitive primitive;                 // Leaf
  std::vector<std::uint32_t> children; // operations: indices into Solid::nodes, in order
  glm::dmat4 parentFromNode{1.0};
};

/// A CSG tree: nodes[root] is the solid; a leaf numbers its surfaces by its node index.
struct Solid {
  std::vector<Node> nodes;
  std::uint32_t root = 0;
};

}  // namespace tandem::solid
