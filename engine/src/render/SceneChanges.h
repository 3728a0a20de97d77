#pragma once
// What changed in the scene since the last frame, recorded once by the Renderer's mutators (setScene,
// setInstanceTransform, setInstanceMotion, setLight) and read, at the start of the next frame or trace, by
// everything derived from the scene: the caches (render/SceneCaches), the radiosity job, the frame history
// and the budget, each deciding what the change means for it (their apply). No mutator tells any of them
// directly, so a new consumer reads the record and no mutator changes. Plain data (tests/unit/SceneChangesTest).
namespace tandem {

struct SceneChanges {
  bool replaced = false;      // setScene: a new scene, nothing derived from the old one holds
  bool staticMoved = false;   // a static instance's transform: the radiosity solution's geometry too
  bool dynamicMoved = false;  // a dynamic instance's transform, or any instance's motion (velocities)
  bool lights = false;        // a light's value

  bool instancesMoved() const { return staticMoved || dynamicMoved; }
  /// Anything the frame shows: the last frame's ids and rays may be stale.
  bool any() const { return replaced || instancesMoved() || lights; }
  SceneChanges& operator|=(const SceneChanges& o) {
    replaced = replaced || o.replaced;
    staticMoved = staticMoved || o.staticMoved;
    dynamicMoved = dynamicMoved || o.dynamicMoved;
    lights = lights || o.lights;
    return *this;
  }
  bool operator==(const SceneChanges&) const = default;
};

}  // namespace tandem
