#pragma once
// What moved since the last frame, as the spatiotemporal filter's temporal stage tests it (DenoisePass,
// shaders/denoise.frag's mayHaveChanged; filled by render/Motion.cpp).
#include <array>
#include <utility>

#include <glm/glm.hpp>

#include "gl/Bindings.h"
#include "tandem/Scene.h"

namespace tandem::gl {

/// What moved since the last frame, for the temporal stage's test of whether an instance that moved may have
/// changed a point's area light or what its glossy lobe sees (its history then starts again; docs/denoise.md).
/// Render space.
struct MovedInstances {
  /// Boxes holding where each instance was and where it is: lo.xyz + its index in lo.w (-1 for a union of
  /// several), hi.xyz.
  std::array<std::pair<glm::vec4, glm::vec4>, TD_MAX_MOVED_BOXES> boxes{};
  int boxCount = 0;
  /// The area lights that cast shadows: centre, and the radius of a sphere holding the light.
  std::array<glm::vec4, kMaxLights> areaLights{};
  int areaLightCount = 0;
  /// The scene has glossy materials: their lobes' cones are tested against the boxes too.
  bool lobes = false;
  /// The farthest corner of a box from the camera: how long a lobe's cone must be to reach every box.
  float reach = 0.0f;
  /// A light the filter does not smooth (point, spot, directional) changed: what a glossy lobe gathers did.
  bool lobesStale = false;
};

}  // namespace tandem::gl
