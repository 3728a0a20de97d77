#pragma once
// Motion blur's transforms (docs/motion-blur.md): an instance's rigid motion over the shutter, sampled at
// time steps that the ray scene (Embree's motion-blur instances), the GL copy and the exact hits all share,
// and interpolated between them as Embree does, linearly, so every part of the frame sees one motion.
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Scene.h"

namespace tandem {

/// Whether the instance moves while a shutter of `shutter` seconds is open.
bool isMoving(const Instance& inst, float shutter);

/// The instance's transform at time u ∈ [0, 1] of the shutter (0.5: worldFromObject itself): translated
/// by velocity·τ and turned by angularVelocity·τ about its origin, τ = (u − 0.5)·shutter seconds. Exact, in
/// double; world space.
glm::dmat4 rigidMotionAt(const Instance& inst, float shutter, double u);

/// The time steps of a moving instance in render space around `anchor` (core/RenderSpace.h): the exact
/// motion at u = k / (n − 1), an even number of segments (so u = 0.5 is a step: worldFromObject exactly),
/// at least 2 and enough that no segment turns by more than 2 degrees (at most kMaxMotionSteps steps).
/// Linear interpolation between steps then strays from the exact arc by under 1.6e-4 of the radius. Empty
/// for an instance at rest.
std::vector<glm::mat4> motionSteps(const Instance& inst, float shutter, glm::vec3 anchor);
inline constexpr int kMaxMotionSteps = 129;

/// The steps' transform at time u ∈ [0, 1]: the two neighbouring steps blended linearly (Embree's
/// motion-blur interpolation of instance transforms).
glm::mat4 motionAt(const std::vector<glm::mat4>& steps, float u);

}  // namespace tandem
