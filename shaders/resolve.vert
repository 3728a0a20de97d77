#version 450 core
// The resolve step's records (core/ResolvedPixel.h; docs/csg.md) drawn into the visibility buffer: one point
// per pixel the ray pass resolved, at that pixel's centre and the depth of what its camera ray found, so the
// ids, the depth and the exact-hits channel hold the ray's answer where the raster drew a solid's proxy.
#include "bindings.glsl"

struct ResolvedPixel {
  uvec2 pixel;  // row 0 at the top
  uvec2 id;     // instance + 1 and triangle (TD_EXACT_TRIANGLE: on the instance's solid), or 0
  vec4 hit;     // a solid's outward normal (xyz) and t along the camera ray (w)
  float depth;  // reversed-Z window depth; 0 for the background
};
layout(std430, binding = TD_BIND_RESOLVED) readonly buffer Resolved { ResolvedPixel resolved[]; };
layout(location = TD_LOC_RESOLVE_FRAME_SIZE) uniform ivec2 frameSize;

flat out uvec2 vId;
flat out vec4 vHit;

void main() {
  ResolvedPixel r = resolved[gl_VertexID];
  // GL rows run bottom-up; a one-pixel point at the centre covers that pixel's sample and no other.
  vec2 centre = vec2(float(r.pixel.x) + 0.5, float(frameSize.y - 1 - int(r.pixel.y)) + 0.5);
  gl_Position = vec4(centre / vec2(frameSize) * 2.0 - 1.0, r.depth, 1.0);
  gl_PointSize = 1.0;
  vId = r.id;
  vHit = r.hit;
}
