#pragma once
// Built-in meshes, in object space, with normals and texture coordinates.
#include "tandem/Scene.h"

namespace tandem {

/// UV sphere of the given radius centred on the origin: `segments` around, `rings` from pole to pole.
Mesh makeSphere(float radius, int segments, int rings);
/// Axis-aligned box centred on the origin with flat faces (24 vertices).
Mesh makeBox(glm::vec3 size);
/// Plane in XZ facing +Y, centred on the origin, subdivided `divisions` times per side;
/// uv spans [0, size.x] x [0, size.y] so a checker frequency of 1 gives unit squares.
Mesh makePlane(glm::vec2 size, int divisions);

/// An exact solid (docs/csg.md) as a Mesh: `solid` as Mesh::exact and, as its triangles, a proxy the raster
/// draws that encloses the solid (every camera ray that meets the solid meets the proxy first): each shape
/// tessellated to circumscribe it (`segments` around its curves), a union's operands together, an
/// intersection's smallest operand or the box of their common bounds, a difference's first operand, whichever of
/// those and the solid's bounding box encloses the least volume. Empty (no exact, no triangles) for an unbounded solid.
Mesh makeSolidProxy(const solid::Solid& solid, int segments = 48);

}  // namespace tandem
