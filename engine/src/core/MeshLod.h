#pragma once
// A coarse copy of a mesh's triangles for views where the mesh covers a few texels (the reflection probes'
// faces): vertex clustering (Rossignac & Borrel 1993). Core: no GL, no Embree.
#include <cstdint>
#include <vector>

#include "tandem/Scene.h"

namespace tandem {

/// The mesh's triangles with every vertex moved to the representative of its cell in a grid of
/// `cellsAcross` cells along the bounds' longest side: the vertex nearest the mean of the cell's vertices,
/// so the copy indexes the mesh's own vertices (and their normals, uvs, colours) and needs no new ones.
/// Triangles whose corners fall in fewer than three cells are dropped, as are those the move turns over
/// (against the original's normal) and repeats (the same three corners in the same turning order); the
/// survivors keep their winding, in the mesh's order. Indices are
/// the mesh's (Mesh::indices' numbering). A mesh with no extent or no triangles comes back as it is.
std::vector<std::uint32_t> clusteredTriangles(const Mesh& mesh, int cellsAcross);

}  // namespace tandem
