#pragma once
// The C++ twin of shaders/procedural.glsl (docs/procedural.md): the same source text compiled with glm after
// shading.glsl (core/Shading.h), so the ray pass and the shade pass evaluate every pattern alike.
#include "core/Shading.h"

namespace tandem::shading {

// What procedural.glsl calls, named here even where Shading.h already does (repeating a using-declaration at
// namespace scope is allowed), so this file does not lean on Shading.h's list. uint and tdHash come from Shading.h.
using glm::clamp;  // int octaves
using glm::dot;
using glm::floor;  // vec3
using glm::vec3;
using glm::vec4;
using std::cos;
using std::sin;
using std::sqrt;  // float

#define TD_OUT(T) T&
#define TD_FN inline
#include "../../../shaders/procedural.glsl"
#undef TD_FN
#undef TD_OUT

}  // namespace tandem::shading
