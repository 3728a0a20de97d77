#include "SceneBuilder.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "tandem/Log.h"
#include "tandem/Primitives.h"

namespace marble {

namespace {

using tandem::Material;

Material mirrorMaterial() {
  Material m;
  m.name = "mirror";
  m.ka = glm::vec3(0.02f);
  m.kd = glm::vec3(0.04f, 0.05f, 0.06f);
  m.ks = glm::vec3(0.6f);
  m.ns = 200.0f;
  m.kr = 0.85f;
  return m;
}

Material glassMaterial(const char* name, glm::vec3 tint) {
  Material m;
  m.name = name;
  m.ka = glm::vec3(0.0f);
  m.kd = tint;
  m.ks = glm::vec3(0.9f);
  m.ns = 300.0f;
  m.kr = 0.05f;
  m.kt = 0.9f;
  m.ior = 1.5f;
  return m;
}

std::uint32_t addMesh(tandem::Scene& s, tandem::Mesh mesh) {
  s.meshes.push_back(std::move(mesh));
  return static_cast<std::uint32_t>(s.meshes.size() - 1);
}
std::uint32_t addMaterial(tandem::Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}
std::uint32_t addInstance(tandem::Scene& s, const std::string& name, std::uint32_t mesh, std::uint32_t material,
                          const glm::mat4& m, bool dynamic) {
  tandem::Instance i;
  i.name = name;
  i.mesh = mesh;
  i.material = material;
  i.worldFromObject = m;
  i.dynamic = dynamic;
  s.instances.push_back(i);
  return static_cast<std::uint32_t>(s.instances.size() - 1);
}

// Boxes that stand on the floor reach this far below it: a base exactly in the floor's plane fights the
// floor for depth, which shows through glass as a flickering speckle (tandem::coplanarOverlaps finds it).
constexpr float kSink = 0.01f;

// A box of `size` centred on its origin, extended by kSink below its base (its top stays at size.y / 2).
tandem::Mesh standingBox(glm::vec3 size) {
  tandem::Mesh m = tandem::makeBox({size.x, size.y + kSink, size.z});
  for (glm::vec3& p : m.positions) p.y -= 0.5f * kSink;
  return m;
}

constexpr float kOrbitRadius = 5.5f;
constexpr float kOrbitHeight = 3.0f;
constexpr float kOrbitRate = 0.45f;  // rad/s

}  // namespace

tandem::Light orbitLight(const tandem::Light& base, double t, float phase) {
  tandem::Light l = base;
  const float a = kOrbitRate * static_cast<float>(t) + phase;
  l.posW = {kOrbitRadius * std::cos(a), kOrbitHeight + 0.5f * std::sin(2.0f * a), kOrbitRadius * std::sin(a)};
  return l;
}

tandem::Light followSpot(const tandem::Light& base, glm::vec3 marble) {
  tandem::Light l = base;
  l.posW = marble + glm::vec3(0.0f, 4.0f, 0.0f);
  l.dirW = {0.0f, -1.0f, 0.0f};
  return l;
}

BuiltScene buildScene(const Game& game) {
  const Level& level = game.level();
  BuiltScene out;
  tandem::Scene& s = out.scene;
  s.name = level.name;
  s.background = {0.015f, 0.02f, 0.045f};

  // Floor: a glossy checkerboard, so gems and lights show up in it once reflections are ray traced.
  Material floor;
  floor.name = "floor";
  floor.ka = glm::vec3(0.6f);
  floor.kd = {0.7f, 0.7f, 0.68f};
  floor.kd2 = {0.08f, 0.09f, 0.12f};
  floor.checkerFrequency = 0.5f;
  floor.ks = glm::vec3(0.3f);
  floor.ns = 48.0f;
  floor.kr = 0.12f;
  const auto floorMat = addMaterial(s, floor);
  const glm::vec2 floorSize = 2.0f * level.halfSize + glm::vec2(0.6f);
  addInstance(s, "floor", addMesh(s, tandem::makePlane(floorSize, 16)), floorMat, glm::mat4(1.0f), false);

  const auto mirrorMat = addMaterial(s, mirrorMaterial());
  const auto glassMat = addMaterial(s, glassMaterial("glass", {0.02f, 0.05f, 0.05f}));
  Material stone;
  stone.name = "stone";
  stone.ka = {0.55f, 0.32f, 0.22f};
  stone.kd = {0.55f, 0.32f, 0.22f};
  stone.ks = glm::vec3(0.1f);
  stone.ns = 16.0f;
  const auto stoneMat = addMaterial(s, stone);
  auto materialOf = [&](Surface surface) {
    return surface == Surface::Mirror ? mirrorMat : surface == Surface::Glass ? glassMat : stoneMat;
  };

  for (const Obstacle& o : level.obstacles) {
    const auto mesh = addMesh(s, standingBox({2.0f * o.halfXZ.x, o.height, 2.0f * o.halfXZ.y}));
    glm::mat4 m = glm::translate(glm::mat4(1.0f), {o.centerXZ.x, 0.5f * o.height, o.centerXZ.y});
    m = glm::rotate(m, o.yaw, glm::vec3(0, 1, 0));
    addInstance(s, o.name, mesh, materialOf(o.surface), m, false);
  }

  Material brass = mirrorMaterial();
  brass.name = "brass-mirror";
  brass.kd = {0.35f, 0.25f, 0.05f};
  brass.ka = brass.kd * 0.3f;
  brass.ks = {0.9f, 0.75f, 0.4f};
  brass.kr = 0.6f;
  const auto brassMat = addMaterial(s, brass);
  for (std::size_t i = 0; i < level.spinners.size(); ++i) {
    const Obstacle& b = level.spinners[i].box;
    const auto mesh = addMesh(s, standingBox({2.0f * b.halfXZ.x, b.height, 2.0f * b.halfXZ.y}));
    out.handles.spinners.push_back(addInstance(s, b.name, mesh, brassMat, game.spinnerTransform(i), true));
  }

  // Gems glow in their own colour (emission) so they read even in shadow and in a mirror's depths.
  const auto gemMesh = addMesh(s, tandem::makeBox(glm::vec3(0.46f)));
  for (std::size_t i = 0; i < level.gems.size(); ++i) {
    Material g;
    g.name = "gem-" + std::to_string(i);
    g.ka = level.gems[i].color * 0.3f;
    g.kd = level.gems[i].color * 0.6f;
    g.ks = glm::vec3(0.9f);
    g.ns = 96.0f;
    g.kr = 0.15f;
    g.emission = level.gems[i].color * 0.5f;
    out.handles.gems.push_back(
        addInstance(s, g.name, gemMesh, addMaterial(s, g), game.gemTransform(i), true));
  }

  // The player: a glass marble with a faint blue tint and a strong highlight.
  const auto marbleMat = addMaterial(s, glassMaterial("marble-glass", {0.05f, 0.1f, 0.16f}));
  out.handles.marble = addInstance(s, "marble", addMesh(s, tandem::makeSphere(level.marbleRadius, 48, 24)),
                                   marbleMat, game.marbleTransform(), true);

  // Lights: a fixed key light, two coloured lights circling the hall and a spot that follows the marble
  // (4 direct lights of the engine's 8), then the ambient term last. The key light is a sphere lamp (an area
  // light, docs/area-lights.md): its shadows are soft, and at its radius it lights as the point it was.
  tandem::Light key;
  key.name = "key";
  key.type = tandem::LightType::Sphere;
  key.radius = 0.6f;
  key.posW = {2.0f, 7.5f, 3.0f};
  key.color = {1.0f, 0.97f, 0.9f};
  key.intensity = 0.9f;
  key.attenuation = {1.0f, 0.0f, 0.004f};
  s.lights.push_back(key);

  tandem::Light warm;
  warm.name = "orbit-warm";
  warm.type = tandem::LightType::Point;
  warm.color = {1.0f, 0.55f, 0.25f};
  warm.intensity = 0.8f;
  warm.attenuation = {1.0f, 0.05f, 0.03f};
  out.handles.orbitLightA = static_cast<std::uint32_t>(s.lights.size());
  s.lights.push_back(orbitLight(warm, 0.0, 0.0f));
  tandem::Light cool = warm;
  cool.name = "orbit-cool";
  cool.color = {0.3f, 0.55f, 1.0f};
  out.handles.orbitLightB = static_cast<std::uint32_t>(s.lights.size());
  s.lights.push_back(orbitLight(cool, 0.0, 3.14159265f));

  tandem::Light spot;
  spot.name = "marble-spot";
  spot.type = tandem::LightType::Spot;
  spot.color = {0.9f, 0.95f, 1.0f};
  spot.intensity = 0.7f;
  spot.innerConeDeg = 14.0f;
  spot.outerConeDeg = 24.0f;
  out.handles.followSpot = static_cast<std::uint32_t>(s.lights.size());
  s.lights.push_back(followSpot(spot, game.marblePos()));

  tandem::Light ambient;
  ambient.name = "ambient";
  ambient.type = tandem::LightType::Ambient;
  ambient.color = {0.6f, 0.65f, 0.8f};
  ambient.intensity = 0.12f;
  s.lights.push_back(ambient);

  s.camera.yFovDeg = 60.0f;
  s.camera.nearZ = 0.05f;
  for (const std::string& w : tandem::coplanarOverlaps(s)) tandem::logWarning("Marble Mirrors scene: " + w);
  return out;
}

void syncScene(tandem::Renderer& renderer, const Game& game, const SceneHandles& h) {
  renderer.setInstanceTransform(h.marble, game.marbleTransform());
  for (std::size_t i = 0; i < h.gems.size(); ++i) renderer.setInstanceTransform(h.gems[i], game.gemTransform(i));
  for (std::size_t i = 0; i < h.spinners.size(); ++i)
    renderer.setInstanceTransform(h.spinners[i], game.spinnerTransform(i));
  const auto& lights = renderer.scene().lights;
  renderer.setLight(h.orbitLightA, orbitLight(lights[h.orbitLightA], game.time(), 0.0f));
  renderer.setLight(h.orbitLightB, orbitLight(lights[h.orbitLightB], game.time(), 3.14159265f));
  renderer.setLight(h.followSpot, followSpot(lights[h.followSpot], game.marblePos()));
}

}  // namespace marble
