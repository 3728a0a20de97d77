#pragma once
// Small analytic scenes for the ray-pass tests (no GL: visibility comes from castVisibility or by hand).
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "rt/EmbreeScene.h"
#include "rt/RayTracer.h"
#include "support/TestSupport.h"
#include "tandem/Image.h"
#include "tandem/Primitives.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem::rt::test {

inline std::uint32_t addMesh(Scene& s, Mesh m) {
  s.meshes.push_back(std::move(m));
  return static_cast<std::uint32_t>(s.meshes.size() - 1);
}
inline std::uint32_t addMaterial(Scene& s, Material m) {
  s.materials.push_back(std::move(m));
  return static_cast<std::uint32_t>(s.materials.size() - 1);
}
inline std::uint32_t addInstance(Scene& s, std::uint32_t mesh, std::uint32_t material, glm::mat4 worldFromObject,
                                 bool dynamic = false) {
  Instance i;
  i.mesh = mesh;
  i.material = material;
  i.worldFromObject = worldFromObject;
  i.dynamic = dynamic;
  s.instances.push_back(i);
  return static_cast<std::uint32_t>(s.instances.size() - 1);
}
inline Material diffuse(glm::vec3 kd) {
  Material m;
  m.kd = kd;
  m.ka = glm::vec3(0.1f);
  return m;
}
inline Light directional(glm::vec3 dirW, float intensity = 1.0f) {
  Light l;
  l.type = LightType::Directional;
  l.dirW = glm::normalize(dirW);
  l.intensity = intensity;
  return l;
}
inline Light pointLight(glm::vec3 posW, float intensity = 1.0f) {
  Light l;
  l.type = LightType::Point;
  l.posW = posW;
  l.intensity = intensity;
  return l;
}
inline Light ambientLight(float intensity) {
  Light l;
  l.type = LightType::Ambient;
  l.intensity = intensity;
  return l;
}
inline glm::mat4 translate(glm::vec3 t) { return glm::translate(glm::mat4(1.0f), t); }

inline FrameSettings settingsFor(int w, int h) {
  FrameSettings s;
  s.width = w;
  s.height = h;
  return s;
}

inline std::unique_ptr<RayTracer> makeTracer(const Scene& scene, int threads = 2) {
  auto rt = RayTracer::create(threads);
  EXPECT_TRUE(rt.ok());
  if (!rt) return nullptr;
  auto r = (*rt)->setScene(scene);
  EXPECT_TRUE(r.ok()) << (r ? std::string() : r.error().message);
  return std::move(*rt);
}

/// One Embree device for the whole test process, made the first time a test asks (before Embree's build
/// threads exist): a second device made later is handed to those threads through TBB, whose
/// synchronisation ThreadSanitizer cannot see.
inline EmbreeDevice& sharedTestDevice() {
  static const std::unique_ptr<EmbreeDevice> device = [] {
    auto made = EmbreeDevice::create();
    EXPECT_TRUE(made.ok());
    return made.ok() ? std::move(*made) : nullptr;
  }();
  return *device;
}

/// One hybrid frame without GL: visibility by Embree camera rays at the settings' size, then the ray pass.
inline void castAndTrace(RayTracer& rt, const Scene& scene, const FrameSettings& s, VisibilityBuffer& vis,
                         RayOutputs& out) {
  rt.castVisibility(scene.camera, s.width, s.height, vis);
  rt.trace(scene, scene.camera, s, vis, out);
}

/// The Whitted scene in miniature: checkerboard floor, a mirror sphere, a glass sphere, a diffuse box,
/// two lights (one point, one directional), Phong/Gouraud/toon materials, a textured quad.
Scene makeWhittedScene();

/// Linear radiance → 8-bit PNG under <build>/test-output for looking at (Reinhard, sRGB).
void writeDebugPng(const ImageF& image, const std::string& name);

}  // namespace tandem::rt::test
