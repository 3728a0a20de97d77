#version 450 core
// Visibility buffer (Burns & Hunt 2013): the identity of the visible triangle, nothing else. The shade
// pass and the CPU ray pass rebuild the exact hit from it. See docs/gbuffer.md.
#ifndef TD_ALPHA_MASK
#define TD_ALPHA_MASK 0
#endif
#ifndef TD_PEEL
#define TD_PEEL 0  // depth peeling: only what lies behind a given depth (gl/BehindView.h)
#endif
#include "bindings.glsl"  // the ids' output type, and the kd unit below
#if TD_ALPHA_MASK
// glTF alphaMode MASK: texels under the cutoff are holes, so the raster sees what is behind them. A
// variant, because a shader that may discard loses llvmpipe's early depth test for every scene.
#define TD_OUT(T) out T
#include "shading.glsl"
layout(binding = TD_UNIT_KD) uniform sampler2DArray kdTextures;  // GpuScene::bind's kd unit
in vec2 vUv;
flat in float vAlphaCode;
flat in float vLayer;
#endif
#if TD_PEEL
// The nearest see-through surface's depth (reversed-Z: larger is nearer); 0 where there is none.
layout(binding = TD_UNIT_PEEL_DEPTH) uniform sampler2D peelDepth;
#endif
flat in uint vInstance;
flat in uint vPrimitiveBase;  // a coarse copy's offset (visibility.vert)
layout(location = 0) out TD_OUTPUT_IDS outIds;  // x instance + 1 (0 = background), y triangle within the mesh

void main() {
#if TD_PEEL
  if (gl_FragCoord.z >= texelFetch(peelDepth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif
#if TD_ALPHA_MASK
  if (vAlphaCode > 0.0) {
    GpuMaterial m;  // tdCoverage reads only the alpha code
    m.texAlpha = vec4(0.0, 0.0, 0.0, vAlphaCode);
    float a = vLayer >= 0.0 ? texture(kdTextures, vec3(vUv, vLayer)).a : 1.0;
    if (tdCoverage(m, a) <= 0.0) discard;
  }
#endif
  outIds = uvec2(vInstance + 1u, uint(gl_PrimitiveID) + vPrimitiveBase);
}
