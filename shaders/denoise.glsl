// What the shade pass (writing the filter's guides) and the filter (denoise.frag) agree on: the packed texels,
// the normal's encoding and the luminance the filter's weights and moments read. Standalone.
//
// A software GL pays for every texel fetch and every pass (llvmpipe: ~2 ms a full-screen pass at 640x360
// before any work), so what a tap needs travels in one RGBA32UI texel:
//   guide (the shade pass's):     x depth (float bits), y normal + instance, z modulation rg (half), w its b
//                                 and the glossy lobe the filtered light was gathered through (half:
//                                 shading.glsl's tdLobeOf)
//   filter texel (the stages'):   x illumination rg (half), y illumination b + variance (half; the sign bit:
//                                 the history was dropped), z depth, w normal + instance
// Depth is view depth (along the camera's unjittered axis); the normal is three signed bytes (an edge-stopping
// weight needs no more, and unpacking it is one instruction); the instance, in the fourth byte, is kept modulo
// 255 (1-255; 0 is the background, never filtered): two instances 255 apart are told apart by the depth and
// normal weights alone.
#ifndef TD_DENOISE_GLSL
#define TD_DENOISE_GLSL

// Normal and instance (ids.x = instance + 1; 0: the background) in one word.
uint tdPackNormalInstance(vec3 n, uint instancePlusOne) {
  uint tag = instancePlusOne == 0u ? 0u : (instancePlusOne - 1u) % 255u + 1u;
  return (packSnorm4x8(vec4(n, 0.0)) & 0x00FFFFFFu) | (tag << 24);
}
vec3 tdUnpackNormal(uint w) { return unpackSnorm4x8(w).xyz; }
uint tdInstanceTag(uint w) { return w >> 24; }

float tdDenoiseLuminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The colour the illumination is divided by before filtering and multiplied by after (texture detail never
// enters the filter); a floor keeps a black surface's reflections finite in between.
vec3 tdDemodulation(vec3 albedo) { return max(albedo, vec3(0.02)); }

#endif
