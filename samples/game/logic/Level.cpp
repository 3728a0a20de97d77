#include "Level.h"

#include <glm/gtc/constants.hpp>

namespace marble {

Level makeHallOfMirrors() {
  Level l;
  l.name = "Hall of Mirrors";
  l.halfSize = glm::vec2(9.0f);
  const float wallT = 0.15f;  // half thickness
  const float wallH = 2.2f;
  const float span = l.halfSize.x + 2.0f * wallT;
  // Four mirrored walls enclose the floor: the endless corridors of reflections are the point. The north and
  // south walls own the corners; the east and west walls stop where they begin, so no two walls share a
  // face's plane and area (their tops and outer faces would fight for depth in the corners).
  l.obstacles.push_back({"wall-north", {0.0f, -l.halfSize.y - wallT}, {span, wallT}, wallH, 0.0f, Surface::Mirror});
  l.obstacles.push_back({"wall-south", {0.0f, l.halfSize.y + wallT}, {span, wallT}, wallH, 0.0f, Surface::Mirror});
  l.obstacles.push_back({"wall-west", {-l.halfSize.x - wallT, 0.0f}, {wallT, l.halfSize.y}, wallH, 0.0f, Surface::Mirror});
  l.obstacles.push_back({"wall-east", {l.halfSize.x + wallT, 0.0f}, {wallT, l.halfSize.y}, wallH, 0.0f, Surface::Mirror});

  const float q = glm::quarter_pi<float>();
  l.obstacles.push_back({"mirror-nw", {-4.5f, -4.5f}, {1.5f, 0.1f}, 2.0f, -q, Surface::Mirror});
  l.obstacles.push_back({"mirror-se", {4.5f, 4.5f}, {1.5f, 0.1f}, 2.0f, -q, Surface::Mirror});
  l.obstacles.push_back({"glass-w", {-4.5f, 3.0f}, {0.6f, 0.6f}, 2.0f, 0.0f, Surface::Glass});
  l.obstacles.push_back({"glass-e", {4.5f, -3.0f}, {0.6f, 0.6f}, 2.0f, 0.0f, Surface::Glass});
  l.obstacles.push_back({"block-n", {-3.0f, -6.5f}, {1.0f, 0.5f}, 1.0f, 0.0f, Surface::Stone});
  l.obstacles.push_back({"block-s", {3.0f, 6.5f}, {1.0f, 0.5f}, 1.0f, 0.0f, Surface::Stone});

  // Low enough (0.8) that the follow camera sees over it, tall enough to bat the marble away.
  l.spinners.push_back({{"spinner", {0.0f, 0.0f}, {2.4f, 0.12f}, 0.8f, 0.0f, Surface::Mirror}, 0.8f});

  const glm::vec3 colors[] = {{1.0f, 0.15f, 0.1f}, {0.1f, 1.0f, 0.2f}, {0.15f, 0.35f, 1.0f}, {1.0f, 0.85f, 0.1f},
                              {1.0f, 0.2f, 0.9f},  {0.1f, 0.9f, 1.0f}, {1.0f, 0.5f, 0.05f}, {0.7f, 0.3f, 1.0f}};
  const glm::vec2 spots[] = {{0.0f, 7.6f},   {7.2f, 7.2f},  {7.6f, 0.0f},   {7.2f, -7.2f},
                             {0.0f, -7.6f},  {-7.2f, -7.2f}, {-7.6f, 0.0f}, {-7.2f, 7.2f}};
  for (int i = 0; i < 8; ++i) l.gems.push_back({spots[i], colors[i]});

  l.startXZ = {0.0f, 4.5f};
  l.startCameraYaw = 0.0f;
  l.timeLimit = 60.0f;
  return l;
}

}  // namespace marble
