#version 450 core
// resolve.vert's points: the resolved pixel's ids and exact hit (its depth comes from the point's position).
#include "bindings.glsl"

flat in uvec2 vId;
flat in vec4 vHit;
layout(location = 0) out TD_OUTPUT_IDS outIds;
layout(location = 1) out TD_OUTPUT_EXACT_HITS outHit;

void main() {
  outIds = vId;
  outHit = vHit;
}
