#version 450 core
// Visibility buffer (Burns & Hunt 2013): the identity of the visible triangle, nothing else. The shade
// pass and the CPU ray pass rebuild the exact hit from it. See docs/gbuffer.md.
flat in uint vInstance;
layout(location = 0) out uvec2 outIds;  // x instance + 1 (0 = background), y triangle within the mesh

void main() { outIds = uvec2(vInstance + 1u, uint(gl_PrimitiveID)); }
