#pragma once
// The last frame drawn, as much of it as the next frame's decisions need, and those decisions as pure functions
// (no GL, no Embree; tests/unit/FrameHistoryTest.cpp): whether a frame reuses the last one's rays whole, or
// keeps some of its shadow answers because only some instances or lights changed (docs/reuse.md). The Renderer
// records each frame it draws here, and Renderer::tracePixel re-runs the frame described here.
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "render/FramePlan.h"
#include "render/SceneChanges.h"
#include "tandem/Camera.h"
#include "tandem/Scene.h"

namespace tandem {

struct FrameHistory {
  bool drawn = false;
  bool sceneChanged = false;   // the scene (SceneChanges::any) or the radiosity solution since: its ids are stale
  bool sceneReplaced = false;  // setScene (or a move of the render anchor) since: nothing of it can be kept
  Camera camera;
  FramePlan plan;
  bool shadowMaps = false;     // primary hits' lights by the shadow maps
  int probeEffects = 0;        // gl::kProbeReflect / kProbeRefract in use
  bool moving = false;         // some instance moved under its open shutter (motion blur)
  // What the scene was when it was drawn, for keeping answers when something moved since (reuseRays only).
  std::vector<glm::mat4> transforms;  // every instance's worldFromObject
  std::vector<Light> directLights;    // Scene::directLights() order

  /// What changed since the last frame, for a frame that keeps some of its answers.
  struct Changes {
    std::vector<std::pair<std::uint32_t, glm::mat4>> moved;  // instance, and the transform it was drawn with
    std::uint32_t changedLights = 0;                         // bit j: direct light j is not what it was
  };

  /// Whether this frame's rays are the last frame's, whole: nothing they depend on changed (the camera, the
  /// scene, the ray settings), the last frame was drawn, and the frame traces every pixel (`partial`: an
  /// adaptive round traces some only).
  bool reusesRays(const FramePlan& plan, const Camera& camera, bool lastDrawn, bool partial) const;

  /// Whether this frame keeps some of the last frame's primary shadow answers, and what changed since it: the
  /// camera and the ray settings as they were, the scene not replaced, only instances' transforms or direct
  /// lights changed, nothing moving under an open shutter now or then. `haveAnswers`: the last frame left
  /// shadow answers to keep.
  bool keepsSome(const FramePlan& plan, const Camera& camera, const Scene& scene, bool lastDrawn, bool haveAnswers,
                 Changes& changes) const;

  /// The scene's changes since the last frame (the Renderer's record, applied before the next frame).
  void apply(const SceneChanges& changes) {
    sceneChanged = sceneChanged || changes.any();
    sceneReplaced = sceneReplaced || changes.replaced;
  }

  /// Records a frame as drawn: its camera and plan, and with reuseRays the scene's transforms and lights.
  void remember(const FramePlan& plan, const Camera& camera, const Scene& scene, bool usedShadowMaps,
                int usedProbeEffects);
};

}  // namespace tandem
