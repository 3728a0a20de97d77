#include "render/FrameHistory.h"

#include <algorithm>

#include "core/Motion.h"

namespace tandem {

bool FrameHistory::reusesRays(const FramePlan& p, const Camera& c, bool lastDrawn, bool partial) const {
  return p.settings.reuseRays && lastDrawn && !sceneChanged && camera == c && sameRayInputs(plan, p) && !partial;
}

bool FrameHistory::keepsSome(const FramePlan& p, const Camera& c, const Scene& scene, bool lastDrawn, bool haveAnswers,
                             Changes& changes) const {
  // Only primary shadow answers are kept, and only from a frame that looked at the same scene from the
  // same camera with the same ray settings.
  if (!p.settings.reuseRays || !lastDrawn || !sceneChanged || sceneReplaced || !p.rayPass || !p.rays.primaryShadows ||
      !haveAnswers || !(camera == c) || !sameRayInputs(plan, p))
    return false;
  // Motion blur: the reuse gate bounds instances at their transforms, and with a shutter open a moving one is
  // where its time puts it (and its motion may have changed with the transform unchanged): nothing kept while
  // anything moves, nor just after (the last frame's rays saw the instances where their time put them).
  if (moving) return false;
  for (const Instance& inst : scene.instances)
    if (isMoving(inst, c.shutter)) return false;
  const std::vector<const Light*> lights = scene.directLights();
  if (transforms.size() != scene.instances.size() || directLights.size() != lights.size()) return false;
  changes.moved.clear();
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (!(scene.instances[i].worldFromObject == transforms[i]))
      changes.moved.emplace_back(static_cast<std::uint32_t>(i), transforms[i]);
  changes.changedLights = 0;
  for (std::size_t j = 0; j < lights.size(); ++j)
    if (!(*lights[j] == directLights[j])) changes.changedLights |= 1u << j;
  return true;
}

void FrameHistory::remember(const FramePlan& p, const Camera& c, const Scene& scene, bool usedShadowMaps,
                            int usedProbeEffects) {
  drawn = true;
  sceneChanged = false;
  sceneReplaced = false;
  camera = c;
  plan = p;
  transforms.clear();
  directLights.clear();
  if (p.settings.reuseRays) {
    for (const Instance& inst : scene.instances) transforms.push_back(inst.worldFromObject);
    for (const Light* l : scene.directLights()) directLights.push_back(*l);
  }
  shadowMaps = usedShadowMaps;
  probeEffects = usedProbeEffects;
  moving = std::any_of(scene.instances.begin(), scene.instances.end(),
                       [&](const Instance& inst) { return isMoving(inst, c.shutter); });
}

}  // namespace tandem
