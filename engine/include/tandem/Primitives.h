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

}  // namespace tandem
