#pragma once
// The level as game data: what collides, what can be picked up, where the marble starts. GL-free;
// the game's scene builder turns it into tandem meshes, materials and instances.
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace marble {

/// Surface of an obstacle; the scene builder maps each to a material.
enum class Surface { Mirror, Glass, Stone };

/// A box standing on the floor, rotated about +Y by `yaw` radians (the convention of glm::rotate about
/// +Y). Collision is 2-D in the floor plane, since the marble never leaves the floor.
struct Obstacle {
  std::string name;
  glm::vec2 centerXZ{0.0f};
  glm::vec2 halfXZ{0.5f};
  float height = 1.0f;
  float yaw = 0.0f;
  Surface surface = Surface::Stone;
};

/// An obstacle that turns about its centre at a constant rate: the animated, dynamic instance.
struct Spinner {
  Obstacle box;
  float angularSpeed = 1.0f;  // rad/s about +Y
};

struct GemSpec {
  glm::vec2 posXZ{0.0f};
  glm::vec3 color{1.0f};
};

struct Level {
  std::string name;
  glm::vec2 halfSize{9.0f};     // the floor inside the walls spans [-halfSize, halfSize] in x and z
  std::vector<Obstacle> obstacles;  // walls included
  std::vector<Spinner> spinners;
  std::vector<GemSpec> gems;
  glm::vec2 startXZ{0.0f};
  float startCameraYaw = 0.0f;  // radians; 0 puts the camera on +z looking toward -z
  float marbleRadius = 0.4f;
  float gemRadius = 0.35f;      // pickup radius of a gem (its drawn size is a bit smaller)
  float gemHeight = 0.6f;       // centre height of a gem above the floor
  float timeLimit = 60.0f;      // seconds to collect every gem
};

/// "Hall of Mirrors": mirrored walls, angled mirror panels, glass pillars, a spinning mirror blade in
/// the middle and eight gems around the edge.
Level makeHallOfMirrors();

}  // namespace marble
