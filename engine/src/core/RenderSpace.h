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
/// A floating origin: the renderer moves the anchor to the camera's position once the camera is farther from
/// it than anchorReach(camera), 1024 times its near distance. Render space then resolves at the camera to
/// within near / 8192 (the ulp of 1024 · near is at most that), and a ray's origin offset (~64 ULPs of its
/// coordinates) stays under 1 % of it, however far the camera travels. A move re-packs the instance transforms
/// and lights (GL and Embree's top level; no mesh is uploaded or rebuilt) and redraws the raster effects, every
/// probe included: it happens once every 1024 near distances travelled (51.2 units at a near plane of 0.05),
/// not every frame.
double anchorReach(const Camera& camera);
/// Whether a frame from `camera` moves the anchor to it (camera.posW finite and farther than anchorReach).
bool anchorDue(glm::vec3 anchor, const Camera& camera);
glm::vec3 toRenderSpace(glm::vec3 posW, glm::vec3 anchor);
/// The camera in render space. Its view direction is the world-space one to float precision wherever the
/// camera is from the anchor: the target is placed along the double-precision difference, scaled by a power of
/// two (exact) so that it lies at least as far from the camera as the camera lies from the anchor (rounding the
/// two points separately would tilt it by ulp(|posR|) over the target's distance: a degree and more for a target
/// close to a camera far from the anchor). A thin lens keeps its plane in focus (focusDistance).
Camera toRenderSpace(const Camera& camera, glm::vec3 anchor);
/// worldFromObject with its translation rebased: renderFromObject.
glm::mat4 toRenderSpace(const glm::mat4& worldFromObject, glm::vec3 anchor);

}  // namespace tandem
