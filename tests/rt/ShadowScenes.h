#pragma once
// Scenes built to break the hybrid shadows' proofs (docs/shadows.md): the CPU's maps are tested on them
// (tests/rt/HybridShadowsTest.cpp) and so is the GL's copy (tests/gl/ShadowProofsGLTest.cpp).
#include <cmath>

#include "RtTestScenes.h"

namespace tandem::rt::test {

// A sphere and a box over a floor, under a point light, a spot and a directional light; `scale` and
// `offset` move the whole scene (camera and lights included).
inline Scene objectsOnAFloor(float scale = 1.0f, glm::vec3 offset = glm::vec3(0.0f)) {
  Scene scene;
  auto place = [&](glm::vec3 p) { return p * scale + offset; };
  glm::mat4 s = glm::scale(glm::mat4(1.0f), glm::vec3(scale));
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 8)), mat, translate(offset) * s);
  addInstance(scene, addMesh(scene, makeSphere(1.0f, 48, 24)), mat, translate(place({-1.5f, 1.2f, 0.0f})) * s);
  // The box rests on the floor: contact shadows along its base.
  addInstance(scene, addMesh(scene, makeBox({1.5f, 1.0f, 1.5f})), mat, translate(place({1.5f, 0.5f, 0.5f})) * s);
  scene.lights.push_back(pointLight(place({-2.0f, 6.0f, 3.0f})));
  Light spot = pointLight(place({4.0f, 5.0f, 2.0f}));
  spot.type = LightType::Spot;
  spot.dirW = glm::normalize(glm::vec3(-4.0f, -5.0f, -2.0f));
  spot.innerConeDeg = 20.0f;
  spot.outerConeDeg = 35.0f;
  scene.lights.push_back(spot);
  scene.lights.push_back(directional({0.4f, -1.0f, -0.3f}));
  scene.camera.posW = place({0.0f, 4.0f, 9.0f});
  scene.camera.targetW = place({0.0f, 0.5f, 0.0f});
  scene.camera.nearZ = 0.05f * scale;
  return scene;
}

// Slabs a thousandth thick over the floor, one just above it, and a needle thinner than a texel of any map:
// the maps must not confuse a slab's two faces, or a slab with the floor under it.
inline Scene thinSlabsAndContacts() {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), mat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeBox({2.0f, 1e-3f, 2.0f})), mat, translate({-1.5f, 1.0f, 0.0f}));
  addInstance(scene, addMesh(scene, makeBox({2.0f, 1e-3f, 2.0f})), mat, translate({1.5f, 1e-3f, 0.0f}));
  addInstance(scene, addMesh(scene, makeBox({4.0f, 2e-3f, 2e-3f})), mat, translate({0.0f, 2.0f, 1.5f}));
  scene.lights.push_back(pointLight({0.5f, 5.0f, 1.0f}));
  scene.lights.push_back(directional({0.2f, -1.0f, 0.1f}));
  scene.camera.posW = {0.0f, 5.0f, 7.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.5f};
  return scene;
}

// Light nearly parallel to a bumpy floor: long shadows, rays grazing every face.
inline Scene grazingLight() {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  Mesh floor = makePlane({20.0f, 20.0f}, 64);
  for (glm::vec3& p : floor.positions) p.y = 0.02f * std::sin(3.0f * p.x) * std::cos(2.0f * p.z);
  floor.normals.clear();  // flat faces: the normals would no longer match the bumps
  addInstance(scene, addMesh(scene, floor), mat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeBox({1.0f, 0.3f, 1.0f})), mat, translate({0.0f, 0.15f, 0.0f}));
  scene.lights.push_back(directional({1.0f, -0.02f, 0.3f}));
  scene.lights.push_back(pointLight({-8.0f, 0.2f, 0.0f}));
  scene.camera.posW = {0.0f, 3.0f, 8.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  return scene;
}

// A point light a hair above a surface, another inside a box (everything outside is dark), and a small plate
// just under a third, nearer it than its maps begin (only the rays and the maps' near-light list see it).
inline Scene lightsAtSurfaces() {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), mat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeBox({1.0f, 1.0f, 1.0f})), mat, translate({2.0f, 0.5f, 0.0f}));
  addInstance(scene, addMesh(scene, makeSphere(0.5f, 24, 12)), mat, translate({-1.0f, 0.5f, 0.0f}));
  scene.lights.push_back(pointLight({0.0f, 1e-4f, 0.0f}));
  scene.lights.push_back(pointLight({2.0f, 0.5f, 0.0f}));
  scene.lights.push_back(pointLight({0.0f, 3.0f, 0.0f}));
  addInstance(scene, addMesh(scene, makeBox({0.3f, 0.01f, 0.3f})), mat, translate({0.0f, 2.9f, 0.0f}));
  scene.camera.posW = {0.0f, 4.0f, 6.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  return scene;
}

}  // namespace tandem::rt::test
