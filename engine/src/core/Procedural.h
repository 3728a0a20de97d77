#pragma once
// The C++ twin of shaders/procedural.glsl (docs/procedural.md): the same source text compiled with glm after
// shading.glsl (core/Shading.h), so the ray pass and the shade pass evaluate every pattern alike.
#include "core/Shading.h"

namespace tandem::shading {

using std::cos;
using std::sin;

#define TD_OUT(T) T&
#define TD_FN inline
#include "../../../shaders/procedural.glsl"
#undef TD_FN
#undef TD_OUT

}  // namespace tandem::shading
