#pragma once
// Turns the game's Level into a tandem::Scene and keeps the animated parts of that scene in step with
// the Game: dynamic instances (marble, gems, spinner) move through Renderer::setInstanceTransform and
// the moving lights through Renderer::setLight, so the static geometry is built once.
#include <cstdint>
#include <vector>

#include "Game.h"
#include "tandem/Renderer.h"
#include "tandem/Scene.h"

namespace marble {

struct SceneHandles {
  std::uint32_t marble = 0;
  std::vector<std::uint32_t> gems;
  std::vector<std::uint32_t> spinners;
  // Direct lights come first in Scene::lights (ambient last), so these indices are the same whether a
  // renderer counts all lights or direct lights only.
  std::uint32_t orbitLightA = 0;
  std::uint32_t orbitLightB = 0;
  std::uint32_t followSpot = 0;
};

struct BuiltScene {
  tandem::Scene scene;
  SceneHandles handles;
};

BuiltScene buildScene(const Game& game);

/// The scene's moving lights at game time `t` with the marble at `marble`.
tandem::Light orbitLight(const tandem::Light& base, double t, float phase);
tandem::Light followSpot(const tandem::Light& base, glm::vec3 marble);

/// Pushes every animated transform and light of the current game state to the renderer.
void syncScene(tandem::Renderer& renderer, const Game& game, const SceneHandles& h);

}  // namespace marble
