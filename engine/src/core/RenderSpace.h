#pragma once
// Camera-relative rendering (docs/numerics.md, "Position"): the ray pass and the GL passes work in
// "render space", world space translated by −anchor, as Unity HDRP does. Far from the world origin a float
// world position carries an error of ulp(|p|) (1/16 at 1e6): vertices transformed there lose silhouettes,
// shadow maps fit to such bounds get acne, and offsets sized for it would be metres. Relative to the
// camera the coordinates stay small and precise. Every position either side handles (instance transforms,
// lights, cameras, bounds, hits) is in render space; directions, distances and images are as in world space.
// The subtraction is done in double, so the only rounding is that of the (small) result.
#include <glm/glm.hpp>

#include "tandem/Camera.h"
#include "tandem/Scene.h"

namespace tandem {

/// The anchor for a scene: its camera's position when finite (where precision matters most), else the origin.
glm::vec3 renderAnchor(const Scene& scene);
glm::vec3 toRenderSpace(glm::vec3 posW, glm::vec3 anchor);
Camera toRenderSpace(const Camera& camera, glm::vec3 anchor);
/// worldFromObject with its translation rebased: renderFromObject.
glm::mat4 toRenderSpace(const glm::mat4& worldFromObject, glm::vec3 anchor);

}  // namespace tandem
