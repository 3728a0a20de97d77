// The hybrid ray pass and the reference tracer on analytic scenes with known answers.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "rt/CpuComposite.h"
#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"
#include "rt/RayTracerBench.h"
#include "rt/RtTestScenes.h"
#include "rt/Wavefront.h"
#include "rt/Whitted.h"
#include "tandem/Log.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

std::size_t at(int x, int y, int w) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); }

// ---- Shadows ----

struct EllipseScene {
  Scene scene;
  glm::vec3 center{0.0f, 2.0f, 0.0f};
  float radius = 1.0f;
  glm::vec3 lightDir = glm::normalize(glm::vec3(0.5f, -1.0f, 0.3f));  // direction the light travels
  std::uint32_t plane = 0, sphere = 0;
  EllipseScene() {
    std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
    plane = addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), mat, glm::mat4(1.0f));
    sphere = addInstance(scene, addMesh(scene, makeSphere(radius, 256, 128)), mat, translate(center), true);
    scene.lights.push_back(directional(lightDir));
    scene.camera.posW = {1.0f, 10.0f, 5.0f};
    scene.camera.targetW = {1.0f, 0.0f, 0.6f};
    scene.camera.yFovDeg = 30.0f;
  }
  // Analytic: the plane point p is in shadow when the ray from p towards the light passes within r of c.
  bool inShadow(glm::vec2 pixel, int w, int h) const {
    Ray r = scene.camera.rayThroughPixel(pixel, {w, h});
    double t = -double(r.origin.y) / double(r.dir.y);
    glm::dvec3 p = glm::dvec3(r.origin) + t * glm::dvec3(r.dir);
    glm::dvec3 toLight = -glm::dvec3(lightDir);
    glm::dvec3 c = glm::dvec3(center);
    double s = glm::dot(c - p, toLight);
    double d2 = glm::dot(c - p, c - p) - s * s;
    return s > 0.0 && d2 < double(radius) * radius;
  }
};

TEST(RayPassShadows, SphereShadowOnPlaneMatchesTheAnalyticEllipse) {
  EllipseScene e;
  auto rt = makeTracer(e.scene);
  ASSERT_TRUE(rt);
  const int w = 256, h = 256;
  VisibilityBuffer vis;
  RayOutputs out;
  castAndTrace(*rt, e.scene, settingsFor(w, h), vis, out);
  ASSERT_EQ(out.lightMask.size(), static_cast<std::size_t>(w * h));
  int shadowed = 0, checked = 0, mismatches = 0, farMismatches = 0;
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      if (vis.ids[at(x, y, w)].x != e.plane + 1) continue;
      ++checked;
      bool analytic = e.inShadow(glm::vec2(x, y) + 0.5f, w, h);
      bool traced = (out.lightMask[at(x, y, w)] & 1u) == 0;
      shadowed += traced;
      if (analytic == traced) continue;
      ++mismatches;
      // Allowed only where the analytic boundary passes within one pixel.
      bool nearBoundary = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          nearBoundary = nearBoundary || e.inShadow(glm::vec2(x + dx, y + dy) + 0.5f, w, h) != analytic;
      if (!nearBoundary) ++farMismatches;
    }
  EXPECT_GT(checked, w * h / 2);
  EXPECT_GT(shadowed, 1500);  // the ellipse covers thousands of pixels at this size
  EXPECT_EQ(farMismatches, 0) << mismatches << " boundary pixels differ";
  // Every plane pixel faces the light (one ray each); of the sphere, only the lit half sends one.
  EXPECT_GE(out.counts.shadow, static_cast<std::uint64_t>(checked));
  EXPECT_LT(out.counts.shadow, out.counts.primary);
}

TEST(RayPassShadows, MovingADynamicInstanceMovesTheShadowWithoutSetScene) {
  EllipseScene e;
  auto rt = makeTracer(e.scene);
  ASSERT_TRUE(rt);
  const int w = 128, h = 128;
  FrameSettings s = settingsFor(w, h);
  auto shadowPixels = [&](std::vector<bool>& shadow) {
    VisibilityBuffer vis;
    RayOutputs out;
    castAndTrace(*rt, e.scene, s, vis, out);
    shadow.assign(static_cast<std::size_t>(w * h), false);
    for (std::size_t i = 0; i < shadow.size(); ++i)
      shadow[i] = vis.ids[i].x == e.plane + 1 && !(out.lightMask[i] & 1u);
  };
  std::vector<bool> before, after;
  shadowPixels(before);
  e.center += glm::vec3(-3.0f, 0.0f, -2.0f);
  e.scene.instances[e.sphere].worldFromObject = translate(e.center);
  rt->updateTransforms(e.scene);
  shadowPixels(after);
  int lit = 0, darkened = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::size_t i = at(x, y, w);
      lit += before[i] && !after[i];
      darkened += !before[i] && after[i];
      // The new shadow is where the analytic ellipse of the moved sphere says (boundary pixels aside).
      if (after[i] && !e.inShadow(glm::vec2(x, y) + 0.5f, w, h)) {
        bool nearBoundary = false;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) nearBoundary = nearBoundary || e.inShadow(glm::vec2(x + dx, y + dy) + 0.5f, w, h);
        EXPECT_TRUE(nearBoundary) << x << "," << y;
      }
    }
  EXPECT_GT(lit, 200);
  EXPECT_GT(darkened, 200);
}

// A static instance moves the way a dynamic one does, through the top level only (no BVH of a mesh is
// rebuilt): the frame after updateTransforms is the frame of a tracer built from scratch on the moved
// scene, to the bit.
TEST(RayPassWhitted, MovingAStaticInstanceEqualsBuildingTheMovedScene) {
  Scene scene = makeWhittedScene();
  std::uint32_t moved = 0;
  while (moved < scene.instances.size() && scene.materials[scene.instances[moved].material].kt <= 0.0f) ++moved;
  ASSERT_LT(moved, scene.instances.size()) << "the Whitted scene has a glass sphere";
  ASSERT_FALSE(scene.instances[moved].dynamic);
  const int w = 96, h = 72;
  FrameSettings s = settingsFor(w, h);
  auto tracer = makeTracer(scene, 2);
  ASSERT_TRUE(tracer);
  VisibilityBuffer vis;
  RayOutputs before;
  castAndTrace(*tracer, scene, s, vis, before);

  scene.instances[moved].worldFromObject = translate({0.6f, 0.1f, -0.4f}) * scene.instances[moved].worldFromObject;
  tracer->updateTransforms(scene);
  RayOutputs updated, rebuilt;
  castAndTrace(*tracer, scene, s, vis, updated);
  auto fresh = makeTracer(scene, 2);
  ASSERT_TRUE(fresh);
  VisibilityBuffer freshVis;
  castAndTrace(*fresh, scene, s, freshVis, rebuilt);

  EXPECT_EQ(vis.ids, freshVis.ids);
  EXPECT_NE(updated.transmitted, before.transmitted) << "the glass sphere did not move";
  EXPECT_EQ(updated.lightMask, rebuilt.lightMask);
  EXPECT_EQ(updated.reflected, rebuilt.reflected);
  EXPECT_EQ(updated.transmitted, rebuilt.transmitted);
  EXPECT_EQ(updated.counts.total(), rebuilt.counts.total());
}

// Shadow rays to a point light run from the hit to just short of the light: a sphere between them
// shadows the floor where the analytic cone says, and the ceiling the light is mounted on (geometry at
// the light itself) shadows nothing.
TEST(RayPassShadows, PointLightRaysStopShortOfTheLight) {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  const std::uint32_t floor = addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), mat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), mat, translate({0.0f, 3.0f, 0.0f}));
  const glm::vec3 center(1.5f, 1.5f, 0.0f);
  const float radius = 0.3f;
  addInstance(scene, addMesh(scene, makeSphere(radius, 128, 64)), mat, translate(center));
  const glm::vec3 light(0.0f, 3.0f, 0.0f);  // on the ceiling
  scene.lights.push_back(pointLight(light, 10.0f));
  scene.camera.posW = {0.0f, 2.5f, 8.0f};
  scene.camera.targetW = {1.0f, 0.0f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  const int w = 192, h = 128;
  VisibilityBuffer vis;
  RayOutputs out;
  castAndTrace(*rt, scene, settingsFor(w, h), vis, out);
  ASSERT_EQ(out.lightMask.size(), static_cast<std::size_t>(w * h));
  int lit = 0, shadowed = 0, wrong = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (vis.ids[at(x, y, w)].x != floor + 1) continue;
      Ray r = scene.camera.rayThroughPixel(glm::vec2(x, y) + 0.5f, {w, h});
      glm::dvec3 p = glm::dvec3(r.origin) + (-double(r.origin.y) / double(r.dir.y)) * glm::dvec3(r.dir);
      // Distance from the sphere centre to the segment p → light.
      glm::dvec3 seg = glm::dvec3(light) - p;
      double s = glm::clamp(glm::dot(glm::dvec3(center) - p, seg) / glm::dot(seg, seg), 0.0, 1.0);
      double d = glm::length(glm::dvec3(center) - (p + s * seg));
      if (std::abs(d - radius) < 0.02) continue;  // the boundary: either answer is right
      bool expectLit = d > radius;
      bool isLit = (out.lightMask[at(x, y, w)] & 1u) != 0;
      lit += isLit;
      shadowed += !isLit;
      wrong += isLit != expectLit;
    }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(lit, w * h / 4);  // the ceiling the light sits on does not occlude it
  EXPECT_GT(shadowed, 50);    // the sphere's shadow
}

// Zero acne: a large plane lit at grazing angles, nothing else in the scene: every pixel is lit.
TEST(RayPassShadows, NoAcneOnALargePlaneAtGrazingLight) {
  for (glm::vec3 offset : {glm::vec3(0.0f), glm::vec3(300.0f, 20.0f, -200.0f), glm::vec3(-2000.0f, -150.0f, 1000.0f)}) {
    Scene scene;
    std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
    // Tilted a little so no coordinate is exactly zero, and subdivided into long thin triangles.
    glm::mat4 m = translate(offset) * glm::rotate(glm::mat4(1.0f), 0.05f, glm::vec3(1, 0, 0.3f));
    addInstance(scene, addMesh(scene, makePlane({2000.0f, 2000.0f}, 7)), mat, m);
    glm::vec3 up = glm::normalize(glm::vec3(m * glm::vec4(0, 1, 0, 0)));
    for (float elevationDeg : {0.1f, 0.5f, 2.0f, 10.0f}) {
      float e = glm::radians(elevationDeg);
      // Directions at this elevation above the tilted plane, from several azimuths.
      glm::vec3 t1 = glm::normalize(glm::cross(up, glm::vec3(0.3f, 0.1f, 1.0f)));
      glm::vec3 t2 = glm::cross(up, t1);
      for (float az : {0.0f, 2.0f, 4.0f})
        scene.lights.push_back(directional(-(std::sin(e) * up + std::cos(e) * (std::cos(az) * t1 + std::sin(az) * t2))));
      // A point light just above the surface, far from most of what it lights.
      glm::vec3 onPlane = glm::vec3(m * glm::vec4(40.0f, 0.0f, -60.0f, 1.0f));
      scene.lights.push_back(pointLight(onPlane + up * (0.02f + elevationDeg), 1.0f));
      ASSERT_LE(scene.lights.size(), static_cast<std::size_t>(kMaxLights));
      if (scene.lights.size() + 4 > static_cast<std::size_t>(kMaxLights)) {
        scene.camera.posW = glm::vec3(m * glm::vec4(0.0f, 4.0f, 30.0f, 1.0f));
        scene.camera.targetW = glm::vec3(m * glm::vec4(0.0f, 0.0f, -60.0f, 1.0f));
        scene.camera.upW = up;
        auto rt = makeTracer(scene);
        ASSERT_TRUE(rt);
        const int w = 160, h = 120;
        VisibilityBuffer vis;
        RayOutputs out;
        castAndTrace(*rt, scene, settingsFor(w, h), vis, out);
        ASSERT_FALSE(out.lightMask.empty());
        std::uint32_t all = (1u << scene.lights.size()) - 1u;
        int planePixels = 0, acne = 0;
        for (std::size_t i = 0; i < vis.ids.size(); ++i) {
          if (vis.ids[i].x == 0) continue;
          ++planePixels;
          acne += out.lightMask[i] != all;
        }
        EXPECT_GT(planePixels, w * h / 3);
        EXPECT_EQ(acne, 0) << "offset " << offset.x << " elevation up to " << elevationDeg;
        EXPECT_EQ(out.counts.shadow, static_cast<std::uint64_t>(planePixels) * scene.lights.size());
        scene.lights.clear();
      }
    }
  }
}

// ---- Ray counts ----

TEST(RayPassCounts, CostFollowsTheScene) {
  Scene scene;
  Material m = diffuse(glm::vec3(0.7f));
  std::uint32_t mat = addMaterial(scene, m);
  addInstance(scene, addMesh(scene, makePlane({10.0f, 10.0f}, 2)), mat, glm::mat4(1.0f));
  scene.lights.push_back(directional({0.2f, -1.0f, 0.1f}));  // above: one ray per pixel
  scene.lights.push_back(pointLight({0.0f, -3.0f, 0.0f}));   // below the plane: never a ray
  Light noShadow = directional({0.0f, -1.0f, 0.0f});
  noShadow.castShadows = false;                              // visible without a ray
  scene.lights.push_back(noShadow);
  scene.lights.push_back(ambientLight(0.2f));
  scene.camera.posW = {0.0f, 6.0f, 2.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  const int w = 64, h = 48;
  VisibilityBuffer vis;
  rt->castVisibility(scene.camera, w, h, vis);
  auto visible = static_cast<std::uint64_t>(std::count_if(vis.ids.begin(), vis.ids.end(), [](glm::uvec2 id) { return id.x != 0; }));
  ASSERT_GT(visible, 1000u);

  FrameSettings s = settingsFor(w, h);
  RayOutputs out;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.primary, visible);
  EXPECT_EQ(out.counts.shadow, visible);
  EXPECT_EQ(out.counts.reflection, 0u);
  EXPECT_EQ(out.counts.refraction, 0u);
  EXPECT_TRUE(out.reflected.empty());
  EXPECT_TRUE(out.transmitted.empty());
  ASSERT_EQ(out.lightMask.size(), static_cast<std::size_t>(w * h));
  for (std::size_t i = 0; i < vis.ids.size(); ++i)
    if (vis.ids[i].x != 0) {
      ASSERT_EQ(out.lightMask[i], 0b111u) << "unoccluded, unreachable and shadowless lights";
    }

  s.shadows = EffectMode::Off;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.shadow, 0u);
  EXPECT_TRUE(out.lightMask.empty());

  // A mirror: one reflection ray per pixel (escaping: no further rays); no refraction.
  scene.materials[mat].kr = 0.5f;
  s.shadows = EffectMode::Ray;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.reflection, visible);
  EXPECT_EQ(out.counts.refraction, 0u);
  EXPECT_TRUE(out.transmitted.empty());
  ASSERT_EQ(out.reflected.size(), static_cast<std::size_t>(w * h));
  // Below the contribution threshold, or no bounce allowed, or reflections by raster: none.
  s.minContribution = 0.6f;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.reflection, 0u);
  EXPECT_TRUE(out.reflected.empty());
  s.minContribution = 0.01f;
  s.maxDepth = 0;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.reflection, 0u);
  s.maxDepth = 5;
  s.reflections = EffectMode::Raster;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.reflection, 0u);

  // Half-resolution grid: one primary hit per grid pixel on the plane.
  s = settingsFor(w, h);
  s.rayScale = 2;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.width, 32);
  EXPECT_EQ(out.height, 24);
  std::uint64_t gridVisible = 0;
  for (int gy = 0; gy < 24; ++gy)
    for (int gx = 0; gx < 32; ++gx) {
      glm::ivec2 p = fullPixelOfGridPixel(gx, gy, 2, w, h);
      gridVisible += vis.ids[at(p.x, p.y, w)].x != 0;
    }
  EXPECT_EQ(out.counts.primary, gridVisible);
  EXPECT_EQ(out.counts.reflection, gridVisible);
}

TEST(RayPassCounts, RefractionRaysOnlyWhereSomethingTransmits) {
  Scene scene;
  Material glass = diffuse(glm::vec3(0.0f));
  glass.kt = 0.9f;
  std::uint32_t glassMat = addMaterial(scene, glass);
  std::uint32_t wallMat = addMaterial(scene, diffuse(glm::vec3(0.5f)));
  addInstance(scene, addMesh(scene, makeBox({2.0f, 2.0f, 0.2f})), glassMat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeBox({20.0f, 20.0f, 0.1f})), wallMat, translate({0, 0, -3}));
  scene.lights.push_back(directional({0.0f, 0.0f, -1.0f}));
  scene.camera.posW = {0.0f, 0.0f, 6.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  const int w = 64, h = 64;
  VisibilityBuffer vis;
  rt->castVisibility(scene.camera, w, h, vis);
  auto glassPixels = static_cast<std::uint64_t>(std::count_if(vis.ids.begin(), vis.ids.end(), [](glm::uvec2 id) { return id.x == 1; }));
  ASSERT_GT(glassPixels, 100u);
  FrameSettings s = settingsFor(w, h);
  s.reflections = EffectMode::Off;
  s.maxDepth = 2;
  RayOutputs out;
  rt->trace(scene, scene.camera, s, vis, out);
  // Into the slab at every glass pixel, and out of its back face (no TIR near normal incidence).
  EXPECT_EQ(out.counts.refraction, 2 * glassPixels);
  EXPECT_EQ(out.counts.reflection, 0u);
  EXPECT_FALSE(out.transmitted.empty());
  s.refraction = EffectMode::Off;
  rt->trace(scene, scene.camera, s, vis, out);
  EXPECT_EQ(out.counts.refraction, 0u);
  EXPECT_TRUE(out.transmitted.empty());
}

// ---- Reflection and refraction ----

// A mirror facing the camera returns what is behind the camera: a wall whose colour is an affine
// function of position, so the expected radiance at each pixel follows from the reflected ray alone.
TEST(RayPassWhitted, MirrorFacingTheCameraShowsWhatIsBehindIt) {
  Scene scene;
  Material mirror = diffuse(glm::vec3(0.0f));
  mirror.ka = glm::vec3(0.0f);
  mirror.kr = 1.0f;
  Material wall = diffuse(glm::vec3(1.0f));
  wall.unlit = true;
  std::uint32_t mirrorMat = addMaterial(scene, mirror), wallMat = addMaterial(scene, wall);
  glm::mat4 facingZ = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));  // +Y → +Z
  addInstance(scene, addMesh(scene, makePlane({40.0f, 40.0f}, 1)), mirrorMat, facingZ);
  Mesh wallMesh = makePlane({200.0f, 200.0f}, 1);
  auto colorAt = [](glm::vec3 pW) { return glm::vec3(0.5f + 0.004f * pW.x, 0.5f + 0.002f * pW.y, 0.3f); };
  glm::mat4 wallFromObject = translate({0, 0, 10}) * glm::rotate(glm::mat4(1.0f), glm::radians(-90.0f), glm::vec3(1, 0, 0));
  for (const glm::vec3& p : wallMesh.positions) wallMesh.colors.emplace_back(colorAt(glm::vec3(wallFromObject * glm::vec4(p, 1))), 1.0f);
  addInstance(scene, addMesh(scene, wallMesh), wallMat, wallFromObject);
  scene.lights.push_back(ambientLight(1.0f));
  scene.camera.posW = {0.3f, 0.2f, 5.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  const int w = 96, h = 64;
  VisibilityBuffer vis;
  RayOutputs out;
  castAndTrace(*rt, scene, settingsFor(w, h), vis, out);
  ASSERT_FALSE(out.reflected.empty());
  int checked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ASSERT_EQ(vis.ids[at(x, y, w)].x, 1u) << "the mirror fills the view";
      Ray r = scene.camera.rayThroughPixel(glm::vec2(x, y) + 0.5f, {w, h});
      glm::vec3 m = r.origin + r.dir * (-r.origin.z / r.dir.z);
      glm::vec3 d(r.dir.x, r.dir.y, -r.dir.z);
      glm::vec3 onWall = m + d * ((10.0f - m.z) / d.z);
      glm::vec3 expected = colorAt(onWall);
      glm::vec3 got(out.reflected[at(x, y, w)]);
      ASSERT_NEAR(got.x, expected.x, 1e-4f) << x << "," << y;
      ASSERT_NEAR(got.y, expected.y, 1e-4f) << x << "," << y;
      ASSERT_NEAR(got.z, expected.z, 1e-4f) << x << "," << y;
      ++checked;
    }
  EXPECT_EQ(checked, w * h);
}

// A glass slab of IOR 1 is no slab: its transmitted radiance is what the camera sees without it.
TEST(RayPassWhitted, GlassSlabOfIorOneEqualsNoSlab) {
  Scene without;
  Material wall = diffuse({0.8f, 0.6f, 0.3f});
  wall.kd2 = {0.2f, 0.3f, 0.9f};
  wall.checkerFrequency = 0.5f;
  wall.ks = glm::vec3(0.3f);
  std::uint32_t wallMat = addMaterial(without, wall);
  glm::mat4 wallFromObject = translate({0, 0, -4}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
  addInstance(without, addMesh(without, makePlane({30.0f, 30.0f}, 3)), wallMat, wallFromObject);
  without.lights.push_back(ambientLight(0.2f));
  without.lights.push_back(pointLight({1.0f, 2.0f, -2.0f}, 3.0f));  // between slab and wall: no slab shadow
  without.camera.posW = {0.5f, 0.3f, 6.0f};
  without.camera.targetW = {0.0f, 0.0f, 0.0f};
  Scene with = without;
  Material glass = diffuse(glm::vec3(0.0f));
  glass.ka = glm::vec3(0.0f);
  glass.kt = 1.0f;
  glass.ior = 1.0f;
  std::uint32_t glassMat = addMaterial(with, glass);
  std::uint32_t slab = addInstance(with, addMesh(with, makeBox({3.0f, 3.0f, 0.5f})), glassMat,
                                   translate({0, 0, 1}) * glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0.2f, 1, 0)));

  const int w = 80, h = 60;
  FrameSettings s = settingsFor(w, h);
  auto rtWith = makeTracer(with), rtWithout = makeTracer(without);
  ASSERT_TRUE(rtWith && rtWithout);
  VisibilityBuffer vis;
  rtWith->castVisibility(with.camera, w, h, vis);
  RayOutputs out;
  rtWith->trace(with, with.camera, s, vis, out);
  ImageF reference;
  RayCounts counts;
  rtWithout->renderReference(without, without.camera, s, reference, counts);
  ASSERT_FALSE(out.transmitted.empty());
  EXPECT_TRUE(out.reflected.empty()) << "IOR 1: F = 0, so no reflection ray";
  int slabPixels = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (vis.ids[at(x, y, w)].x != slab + 1) continue;
      ++slabPixels;
      glm::vec3 got(out.transmitted[at(x, y, w)]), expected = reference.at(x, y);
      ASSERT_NEAR(got.x, expected.x, 1e-4f * (1.0f + expected.x)) << x << "," << y;
      ASSERT_NEAR(got.y, expected.y, 1e-4f * (1.0f + expected.y)) << x << "," << y;
      ASSERT_NEAR(got.z, expected.z, 1e-4f * (1.0f + expected.z)) << x << "," << y;
    }
  EXPECT_GT(slabPixels, w * h / 4);
}

// ---- Determinism, reference, composite ----

TEST(RayPassWhitted, ImagesAreIdenticalWithOneAndTwoThreads) {
  Scene scene = makeWhittedScene();
  const int w = 120, h = 90;
  FrameSettings s = settingsFor(w, h);
  auto one = makeTracer(scene, 1), two = makeTracer(scene, 2);
  ASSERT_TRUE(one && two);
  EXPECT_EQ(one->threads(), 1);
  EXPECT_EQ(two->threads(), 2);
  VisibilityBuffer vis1, vis2;
  one->castVisibility(scene.camera, w, h, vis1);
  two->castVisibility(scene.camera, w, h, vis2);
  ASSERT_EQ(vis1.ids, vis2.ids);
  RayOutputs a, b;
  one->trace(scene, scene.camera, s, vis1, a);
  two->trace(scene, scene.camera, s, vis1, b);
  EXPECT_EQ(a.lightMask, b.lightMask);
  EXPECT_EQ(a.reflected, b.reflected);
  EXPECT_EQ(a.transmitted, b.transmitted);
  EXPECT_EQ(a.counts.total(), b.counts.total());
  EXPECT_GT(a.counts.reflection, 0u);
  EXPECT_GT(a.counts.refraction, 0u);
  // One shadow ray per rtcOccluded1 call gives the same masks as the batched rtcOccluded1M.
  RayTracerBench::trace(*two, scene, scene.camera, s, vis1, b, {nullptr, false});
  EXPECT_EQ(a.lightMask, b.lightMask);
  EXPECT_EQ(a.counts.shadow, b.counts.shadow);

  s.referenceSpp = 2;
  ImageF r1, r2;
  RayCounts c1, c2;
  one->renderReference(scene, scene.camera, s, r1, c1);
  two->renderReference(scene, scene.camera, s, r2, c2);
  EXPECT_EQ(r1.rgb, r2.rgb);
  EXPECT_EQ(c1.total(), c2.total());
  EXPECT_EQ(c1.primary, static_cast<std::uint64_t>(w * h * 4));
  writeDebugPng(r1, "rt-whitted-reference-spp2.png");
}

// An adaptive round's selection (trace's `only`): the pixels left out are traced as the sky is, so the
// results equal a trace of ids with those pixels cleared, to the bit and ray for ray; the ids are not touched.
TEST(RayPassWhitted, ASelectionTracesAsIfTheOtherPixelsWereSky) {
  Scene scene = makeWhittedScene();
  auto tracer = makeTracer(scene, 2);
  ASSERT_TRUE(tracer);
  for (int scale : {1, 2}) {
    SCOPED_TRACE("ray scale " + std::to_string(scale));
    const int w = 120, h = 90;
    FrameSettings s = settingsFor(w, h);
    s.rayScale = scale;
    VisibilityBuffer vis;
    tracer->castVisibility(scene.camera, w, h, vis);
    std::vector<std::uint8_t> only(vis.ids.size(), 0);
    VisibilityBuffer masked = vis;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const bool chosen = ((x / 7) + (y / 5)) % 3 == 0;  // stripes across the spheres and the floor
        only[at(x, y, w)] = chosen ? 1 : 0;
        if (!chosen) masked.ids[at(x, y, w)] = glm::uvec2(0u);
      }
    const std::vector<glm::uvec2> idsBefore = vis.ids;
    RayOutputs selected, expected, all;
    tracer->trace(scene, scene.camera, s, vis, selected, nullptr, only);
    tracer->trace(scene, scene.camera, s, masked, expected);
    tracer->trace(scene, scene.camera, s, vis, all);
    EXPECT_EQ(vis.ids, idsBefore);
    EXPECT_EQ(selected.lightMask, expected.lightMask);
    EXPECT_EQ(selected.reflected, expected.reflected);
    EXPECT_EQ(selected.transmitted, expected.transmitted);
    EXPECT_EQ(selected.reflectedTiles, expected.reflectedTiles);
    EXPECT_EQ(selected.counts.total(), expected.counts.total());
    EXPECT_EQ(selected.counts.primary, expected.counts.primary);
    EXPECT_GT(selected.counts.reflection, 0u);
    EXPECT_LT(selected.counts.total(), all.counts.total()) << "the selection must leave rays out";
  }
}

// The upload sends only the tiles the pass flags (RayOutputs::reflectedTiles): a tile flagged empty must be
// zero to the bit, or the shade pass would miss radiance. Every flag is checked against the texels, at a
// grid size that leaves partial tiles at the edges and at a half-resolution grid.
TEST(RayPassWhitted, TileFlagsSayExactlyWhichTilesHoldRayResults) {
  Scene scene = makeWhittedScene();
  auto tracer = makeTracer(scene, 2);
  ASSERT_TRUE(tracer);
  for (int scale : {1, 2}) {
    SCOPED_TRACE("ray scale " + std::to_string(scale));
    const int w = 150, h = 83;
    FrameSettings s = settingsFor(w, h);
    s.rayScale = scale;
    VisibilityBuffer vis;
    tracer->castVisibility(scene.camera, w, h, vis);
    RayOutputs out;
    tracer->trace(scene, scene.camera, s, vis, out);
    ASSERT_GT(out.counts.reflection, 0u);
    ASSERT_GT(out.counts.refraction, 0u);
    ASSERT_GT(out.tileSize, 0);
    const int tilesX = (out.width + out.tileSize - 1) / out.tileSize, tilesY = (out.height + out.tileSize - 1) / out.tileSize;
    for (const auto& [channel, flags] : {std::pair{&out.reflected, &out.reflectedTiles}, std::pair{&out.transmitted, &out.transmittedTiles}}) {
      ASSERT_EQ(flags->size(), static_cast<std::size_t>(tilesX * tilesY));
      int flagged = 0;
      for (int ty = 0; ty < tilesY; ++ty)
        for (int tx = 0; tx < tilesX; ++tx) {
          bool any = false;
          for (int y = ty * out.tileSize; y < std::min((ty + 1) * out.tileSize, out.height); ++y)
            for (int x = tx * out.tileSize; x < std::min((tx + 1) * out.tileSize, out.width); ++x) {
              const glm::vec4 v = (*channel)[at(x, y, out.width)];
              for (int c = 0; c < 4; ++c) any = any || std::signbit(v[c]) || v[c] != 0.0f;
            }
          EXPECT_EQ((*flags)[static_cast<std::size_t>(ty * tilesX + tx)] != 0, any) << "tile " << tx << "," << ty;
          flagged += any ? 1 : 0;
        }
      EXPECT_GT(flagged, 0);
      EXPECT_LT(flagged, tilesX * tilesY) << "some tiles see nothing reflective: the flags must tell them apart";
    }
  }
}

// The hybrid pass traces secondary rays breadth first (Wavefront) and sums them bottom up; its S and T
// must be the recursion's (Whitted::secondary), bit for bit, with the same ray counts, at the default
// depth and at a deep one with a contribution cut-off.
TEST(RayPassWhitted, WavefrontEqualsTheRecursionBitForBit) {
  Scene scene = makeWhittedScene();
  // glTF extras on the secondary rays' vec3 weights: a tinted glass sphere (tdTransmitWeight with a = 1)
  // and a BLEND quad without kt (its 1 − a passes straight through), both in view.
  Material tinted = diffuse(glm::vec3(0.0f));
  tinted.ka = glm::vec3(0.0f);
  tinted.ks = glm::vec3(0.9f);
  tinted.ns = 128.0f;
  tinted.kt = 0.9f;
  tinted.ior = 1.5f;
  tinted.transmissionTint = {0.9f, 0.5f, 0.3f};
  Material blend = diffuse({0.8f, 0.3f, 0.3f});
  blend.alphaMode = AlphaMode::Blend;
  blend.opacity = 0.4f;
  blend.kr = 0.2f;
  addInstance(scene, addMesh(scene, makeSphere(0.5f, 32, 16)), addMaterial(scene, tinted), translate({-0.4f, 0.5f, 2.0f}));
  addInstance(scene, addMesh(scene, makePlane({1.2f, 1.2f}, 1)), addMaterial(scene, blend),
              translate({-1.8f, 1.0f, 2.2f}) * glm::rotate(glm::mat4(1.0f), 1.4f, glm::vec3(1, 0, 0)));
  const int w = 96, h = 72;
  auto tracer = makeTracer(scene, 2);
  ASSERT_TRUE(tracer);
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  auto embree = EmbreeScene::build(**device, scene);
  ASSERT_TRUE(embree.ok());
  VisibilityBuffer vis;
  tracer->castVisibility(scene.camera, w, h, vis);
  for (int depth : {3, 8}) {
    FrameSettings s = settingsFor(w, h);
    s.maxDepth = depth;
    s.minContribution = depth == 8 ? 0.05f : s.minContribution;
    RayOutputs out;
    tracer->trace(scene, scene.camera, s, vis, out);
    ASSERT_EQ(out.reflected.size(), static_cast<std::size_t>(w * h));
    ASSERT_EQ(out.transmitted.size(), static_cast<std::size_t>(w * h));
    FrameShading frame(scene, s.shadingOverride, (*embree)->anchor());
    Whitted whitted(scene, **embree, frame, TraceModes::hybrid(s));
    const Camera cam = toRenderSpace(scene.camera, (*embree)->anchor());
    RayCounts counts;
    int differing = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        glm::uvec2 id = vis.ids[at(x, y, w)];
        if (id.x == 0) continue;
        Ray ray = cam.rayThroughPixel(glm::vec2(x, y) + 0.5f, {w, h});
        SurfaceHit hit = resolveHit(scene, (*embree)->transform(id.x - 1), id.x - 1, id.y, ray);
        glm::vec3 reflected, transmitted;
        bool tracedR, tracedT;
        whitted.secondary(hit, 0, 1.0f, reflected, transmitted, tracedR, tracedT, counts);
        // Alpha marks a pixel whose ray was traced (RayOutputs); untraced pixels are zero throughout.
        differing += glm::vec4(reflected, tracedR ? 1.0f : 0.0f) != out.reflected[at(x, y, w)] ||
                     glm::vec4(transmitted, tracedT ? 1.0f : 0.0f) != out.transmitted[at(x, y, w)];
      }
    EXPECT_EQ(differing, 0) << "depth " << depth;
    EXPECT_EQ(counts.reflection, out.counts.reflection) << "depth " << depth;
    EXPECT_EQ(counts.refraction, out.counts.refraction) << "depth " << depth;
    EXPECT_GT(counts.reflection, 0u);
    EXPECT_GT(counts.refraction, 0u);
  }
}

// With the spatiotemporal filter on, the light it does not smooth (a mirror's hits) is drawn with
// lightSamplesPastFilter samples, the primary hits with lightSamples: one filtered sample a pixel leaves the
// mirror as a frame of four raw samples has it, bit for bit, and the primary hits as a frame of one; the
// recursion draws the frame's mirror. Without the filter every point draws lightSamples.
TEST(RayPassWhitted, WithTheFilterTheMirrorsHitsDrawTheLightSamplesPastIt) {
  Scene scene;
  const std::uint32_t matte = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  Material mirror = diffuse(glm::vec3(0.05f));
  mirror.kr = 0.9f;
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 4)), matte, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeBox({1.0f, 1.0f, 1.0f})), matte, translate({0.0f, 0.5f, 0.0f}));
  addInstance(scene, addMesh(scene, makeBox({8.0f, 4.0f, 0.1f})), addMaterial(scene, mirror),
              translate({0.0f, 2.0f, -3.0f}));
  Light lamp = pointLight({0.5f, 4.0f, 1.0f});
  lamp.type = LightType::Sphere;
  lamp.radius = 0.8f;
  scene.lights.push_back(lamp);
  scene.camera.posW = {0.0f, 1.5f, 6.0f};
  scene.camera.targetW = {0.0f, 1.0f, -3.0f};
  const int w = 96, h = 54;
  auto tracer = makeTracer(scene, 2);
  ASSERT_TRUE(tracer);
  VisibilityBuffer vis;
  tracer->castVisibility(scene.camera, w, h, vis);
  auto trace = [&](bool denoise, int samples, int pastFilter, bool batched) {
    FrameSettings s = settingsFor(w, h);
    s.denoise = denoise;
    s.lightSamples = samples;
    s.lightSamplesPastFilter = pastFilter;
    RayOutputs out;
    RayTracerBench::trace(*tracer, scene, scene.camera, s, vis, out, BenchTrace{nullptr, batched});
    return out;
  };
  auto differing = [](const auto& a, const auto& b) {
    EXPECT_EQ(a.size(), b.size());
    int n = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) n += a[i] != b[i] ? 1 : 0;
    return n;
  };
  for (bool batched : {true, false}) {
    const RayOutputs filtered = trace(true, 1, 4, batched), four = trace(false, 4, 4, batched),
                     one = trace(false, 1, 4, batched);
    ASSERT_EQ(filtered.areaLights, 1) << batched;
    EXPECT_EQ(differing(filtered.reflected, four.reflected), 0) << "the mirror as four raw samples show it";
    EXPECT_EQ(differing(filtered.areaSamples, one.areaSamples), 0) << "the primary hits' one sample";
    EXPECT_EQ(differing(filtered.lightMask, one.lightMask), 0);
    // The test can fail: the mirror shows the box's penumbra, where one sample and four differ.
    EXPECT_GT(differing(one.reflected, four.reflected), 20) << batched;
    EXPECT_GT(filtered.counts.shadow, one.counts.shadow);
    EXPECT_LT(filtered.counts.shadow, four.counts.shadow);
    // At least lightSamples: a filtered frame of four samples draws four past the filter too.
    EXPECT_EQ(differing(trace(true, 4, 1, batched).reflected, four.reflected), 0);
  }
  // The recursion (Whitted::secondary: the reference's, PixelTrace's) draws the frame's mirror, bit for bit.
  auto embree = EmbreeScene::build(sharedTestDevice(), scene);
  ASSERT_TRUE(embree.ok());
  FrameSettings s = settingsFor(w, h);
  s.denoise = true;
  s.lightSamples = 1;
  const RayOutputs filtered = trace(true, 1, 4, true);
  const FrameShading frame =
      FrameShading::forFrame(scene, s, scene.camera.sampleIndex, (*embree)->anchor(), nullptr);
  const Whitted whitted(scene, **embree, frame, TraceModes::hybrid(s));
  const Camera cam = toRenderSpace(scene.camera, (*embree)->anchor());
  RayCounts counts;
  int mirrored = 0, recursionDiffers = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::uvec2 id = vis.ids[at(x, y, w)];
      if (id.x == 0) continue;
      const Ray ray = cam.rayThroughPixel(glm::vec2(x, y) + 0.5f, {w, h});
      const SurfaceHit hit = resolveHit(scene, (*embree)->transform(id.x - 1), id.x - 1, id.y, ray);
      glm::vec3 reflected, transmitted;
      bool tracedR, tracedT;
      whitted.secondary(hit, 0, 1.0f, reflected, transmitted, tracedR, tracedT, counts);
      mirrored += tracedR ? 1 : 0;
      recursionDiffers += glm::vec4(reflected, tracedR ? 1.0f : 0.0f) != filtered.reflected[at(x, y, w)] ? 1 : 0;
    }
  EXPECT_GT(mirrored, 500);
  EXPECT_EQ(recursionDiffers, 0);
}

// BLEND (docs/gltf.md "Alpha modes"): a quad of coverage a with no kt in front of nothing transmits
// (1 − a) of the background straight through, and reflects a·kr.
TEST(RayPassWhitted, BlendSurfacePassesOneMinusCoverageStraightThrough) {
  Scene scene;
  Material blend = diffuse({0.8f, 0.3f, 0.3f});
  blend.alphaMode = AlphaMode::Blend;
  blend.opacity = 0.25f;
  std::uint32_t mat = addMaterial(scene, blend);
  addInstance(scene, addMesh(scene, makePlane({4.0f, 4.0f}, 1)), mat, glm::rotate(glm::mat4(1.0f), 1.5707964f, glm::vec3(1, 0, 0)));
  scene.background = {0.2f, 0.4f, 0.8f};
  scene.lights.push_back(directional({0.0f, 0.0f, -1.0f}));
  scene.camera.posW = {0.0f, 0.0f, 5.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  const int w = 32, h = 32;
  VisibilityBuffer vis;
  rt->castVisibility(scene.camera, w, h, vis);
  ASSERT_EQ(vis.ids[at(w / 2, h / 2, w)].x, 1u);
  FrameSettings s = settingsFor(w, h);
  s.maxDepth = 2;
  RayOutputs out;
  rt->trace(scene, scene.camera, s, vis, out);
  ASSERT_EQ(out.transmitted.size(), static_cast<std::size_t>(w * h));
  EXPECT_GT(out.counts.refraction, 0u);
  glm::vec4 t = out.transmitted[at(w / 2, h / 2, w)];
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c], 0.75f * scene.background[c], 1e-6f);
}

// MASK cut-outs (docs/gltf.md): Embree's filter lets rays through the holes, so the shadow of a quad whose
// texture is transparent on one half falls only under the other half, and a ray through a hole hits the floor.
TEST(RayPassShadows, ShadowThroughAMaskCutOutReachesTheFloor) {
  Scene scene;
  Texture tex;  // 4×4: columns 0-1 alpha 0 (holes), columns 2-3 alpha 255
  tex.width = tex.height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) tex.rgba8.insert(tex.rgba8.end(), {200, 200, 200, static_cast<std::uint8_t>(x < 2 ? 0 : 255)});
  scene.textures.push_back(tex);
  Material cutout = diffuse(glm::vec3(0.8f));
  cutout.kdTexture = 0;
  cutout.alphaMode = AlphaMode::Mask;
  cutout.alphaCutoff = 0.5f;
  std::uint32_t floorMat = addMaterial(scene, diffuse(glm::vec3(0.7f)));
  std::uint32_t cutMat = addMaterial(scene, cutout);
  std::uint32_t floor = addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 1)), floorMat, glm::mat4(1.0f));
  // A 2×2 quad at height 1: uv = (x + 1) / 2, so x < 0 is the holes' half.
  Mesh quad = makePlane({2.0f, 2.0f}, 1);
  for (glm::vec2& uv : quad.uvs) uv /= 2.0f;
  std::uint32_t cut = addInstance(scene, addMesh(scene, quad), cutMat, translate({0.0f, 1.0f, 0.0f}));
  scene.lights.push_back(directional({0.0f, -1.0f, 0.0f}));
  scene.camera.posW = {0.0f, 6.0f, 6.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  auto embree = EmbreeScene::build(**device, scene);
  ASSERT_TRUE(embree.ok());
  EXPECT_TRUE((*embree)->hasAlphaMaskFilter());
  FrameSettings s = settingsFor(16, 16);
  FrameShading frame(scene, s.shadingOverride, (*embree)->anchor());
  Whitted whitted(scene, **embree, frame, TraceModes::reference(s));
  auto floorHit = [&](float x) {  // on the floor's triangle 0 (x + z < 0)
    Ray ray{toRenderSpace(glm::vec3(x, 5.0f, -0.9f), (*embree)->anchor()), glm::vec3(0.0f, -1.0f, 0.0f)};
    return resolveHit(scene, (*embree)->transform(floor), floor, 0, ray);
  };
  RayCounts counts;
  for (float x : {-0.8f, -0.7f, -0.6f}) {
    EXPECT_EQ(whitted.lightMask(floorHit(x), counts), 1u) << x;  // through the holes
    ShadowBatch batch;  // and batched (rtcOccluded8 packets)
    LightMask mask = 0;
    mask = static_cast<LightMask>(mask | batch.add(whitted, 1, floorHit(x), 0));
    batch.trace((*embree)->top(), &mask, counts);
    EXPECT_EQ(mask, 1u) << x;
  }
  for (float x : {0.3f, 0.5f, 0.7f}) EXPECT_EQ(whitted.lightMask(floorHit(x), counts), 0u) << x;
  std::uint32_t instance = 0, triangle = 0;
  glm::vec3 from = toRenderSpace(glm::vec3(-0.7f, 5.0f, -0.9f), (*embree)->anchor());
  ASSERT_TRUE(whitted.intersect(from, glm::vec3(0, -1, 0), 0.0f, 100.0f, instance, triangle));
  EXPECT_EQ(instance, floor);
  from = toRenderSpace(glm::vec3(0.6f, 5.0f, -0.9f), (*embree)->anchor());
  ASSERT_TRUE(whitted.intersect(from, glm::vec3(0, -1, 0), 0.0f, 100.0f, instance, triangle));
  EXPECT_EQ(instance, cut);
  // Scenes without MASK materials get no filter.
  auto plain = EmbreeScene::build(**device, makeWhittedScene());
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE((*plain)->hasAlphaMaskFilter());
}

// CameraRays does Camera::rayThroughPixel's per-camera work once; the rays must not change by a bit.
TEST(RayPassWhitted, CameraRaysAreCameraRayThroughPixelBitForBit) {
  Scene scene = makeWhittedScene();
  for (bool ortho : {false, true})
   for (glm::vec2 jitter : {glm::vec2(0.0f), glm::vec2(0.375f, -0.125f)}) {  // anti-aliasing's sub-pixel offsets
    Camera cam = scene.camera;
    cam.orthographic = ortho;
    cam.orthoHeight = 7.0f;
    cam.jitterPx = jitter;
    const glm::ivec2 size(173, 91);
    CameraRays rays(cam, size);
    int differing = 0;
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        for (glm::vec2 offset : {glm::vec2(0.5f), glm::vec2(0.125f, 0.875f)}) {
          Ray a = cam.rayThroughPixel(glm::vec2(x, y) + offset, size), b = rays.through(glm::vec2(x, y) + offset);
          differing += a.origin != b.origin || a.dir != b.dir;
        }
    EXPECT_EQ(differing, 0) << (ortho ? "orthographic" : "perspective");
  }
}

TEST(RayPassWhitted, HybridPointEqualsTheReferenceAtOneSample) {
  Scene scene = makeWhittedScene();
  const int w = 160, h = 120;
  for (std::optional<ShadingModel> model :
       {std::optional<ShadingModel>{}, std::optional<ShadingModel>{ShadingModel::Flat}, std::optional<ShadingModel>{ShadingModel::Gouraud},
        std::optional<ShadingModel>{ShadingModel::Toon}}) {
    FrameSettings s = settingsFor(w, h);
    s.shadingOverride = model;
    s.fresnel = model ? FresnelMode::Schlick : FresnelMode::Exact;
    auto rt = makeTracer(scene);
    ASSERT_TRUE(rt);
    VisibilityBuffer vis;
    RayOutputs out;
    castAndTrace(*rt, scene, s, vis, out);
    ImageF hybrid, reference;
    compositeOnCpu(scene, scene.camera, s, vis, out, hybrid);
    RayCounts counts;
    rt->renderReference(scene, scene.camera, s, reference, counts);
    // Same points, same rays: the same colour, up to float reassociation.
    int differ = 0;
    for (std::size_t i = 0; i < hybrid.rgb.size(); ++i) {
      glm::vec3 d = glm::abs(hybrid.rgb[i] - reference.rgb[i]);
      if (glm::max(d.x, glm::max(d.y, d.z)) > 1e-5f * (1.0f + glm::max(reference.rgb[i].x, reference.rgb[i].y))) ++differ;
    }
    EXPECT_EQ(differ, 0) << "model override " << (model ? int(*model) : -1);
    // The reference counts the same rays as the hybrid plus the local-shading shadow rays it does itself.
    EXPECT_EQ(counts.reflection, out.counts.reflection);
    EXPECT_EQ(counts.refraction, out.counts.refraction);
    EXPECT_EQ(counts.shadow, out.counts.shadow);
    EXPECT_EQ(counts.primary, static_cast<std::uint64_t>(w * h));
    if (!model) {
      writeDebugPng(hybrid, "rt-whitted-hybrid-composite.png");
      writeDebugPng(reference, "rt-whitted-reference-spp1.png");
    }
  }
}

// ---- Robustness ----

TEST(RayPassRobustness, DegenerateTrianglesAndStaleIdsNeverBreakTheFrame) {
  Scene scene;
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 2, 0}, {1e-9f, 0, 0}, {3, 3, 3}};
  m.indices = {0, 1, 2, 3, 4, 3, 0, 5, 1, 0, 6, 6};  // a good triangle, a point, a needle, a zero-length edge
  Material mat = diffuse(glm::vec3(0.5f));
  mat.kr = 0.5f;
  mat.kt = 0.5f;
  addInstance(scene, addMesh(scene, m), addMaterial(scene, mat), glm::mat4(1.0f));
  scene.lights.push_back(pointLight({0.2f, 0.2f, 3.0f}));
  scene.camera.posW = {0.3f, 0.3f, 4.0f};
  scene.camera.targetW = {0.3f, 0.3f, 0.0f};
  auto rt = makeTracer(scene);
  ASSERT_TRUE(rt);
  VisibilityBuffer vis;
  vis.width = 4;
  vis.height = 1;
  vis.ids = {{1, 0}, {1, 1}, {1, 2}, {1, 3}};  // the ids a rasterizer could write for each triangle
  RayOutputs out;
  rt->trace(scene, scene.camera, settingsFor(4, 1), vis, out);
  EXPECT_EQ(out.counts.primary, 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    if (!out.reflected.empty()) {
      EXPECT_TRUE(isFinite(glm::vec3(out.reflected[i]))) << i;
    }
    if (!out.transmitted.empty()) {
      EXPECT_TRUE(isFinite(glm::vec3(out.transmitted[i]))) << i;
    }
  }
  ImageF image;
  RayCounts counts;
  FrameSettings s = settingsFor(32, 32);
  rt->renderReference(scene, scene.camera, s, image, counts);
  for (const glm::vec3& c : image.rgb) ASSERT_TRUE(isFinite(c));
}

TEST(RayPassRobustness, SetSceneRefusesBadInputAndKeepsThePreviousScene) {
  EllipseScene e;
  auto rt = makeTracer(e.scene);
  ASSERT_TRUE(rt);
  VisibilityBuffer before, after;
  rt->castVisibility(e.scene.camera, 64, 64, before);

  Scene bad = e.scene;
  bad.meshes[0].positions[0].x = std::nanf("");
  auto r = rt->setScene(bad);
  EXPECT_FALSE(r.ok());
  rt->castVisibility(e.scene.camera, 64, 64, after);
  EXPECT_EQ(before.ids, after.ids);

  // Embree out of memory (a tight budget through the memory monitor): an error value, old scene kept.
  std::vector<std::string> logged;
  LogSink old = setLogSink([&](LogLevel, std::string_view m) { logged.emplace_back(m); });
  rt->setEmbreeMemoryLimit(4096);
  r = rt->setScene(e.scene);
  setLogSink(old);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("out of memory"), std::string::npos) << r.error().message;
  EXPECT_FALSE(logged.empty());
  rt->castVisibility(e.scene.camera, 64, 64, after);
  EXPECT_EQ(before.ids, after.ids);
  rt->setEmbreeMemoryLimit(0);
  EXPECT_TRUE(rt->setScene(e.scene).ok());
}

// ---- Throughput (run explicitly: --gtest_also_run_disabled_tests --gtest_filter=*Throughput*) ----

TEST(RayPassPerf, DISABLED_ShadowRayThroughput) {
  Scene scene = makeWhittedScene();
  for (int i = 0; i < 4; ++i) scene.lights.push_back(pointLight({-4.0f + 2.5f * float(i), 5.0f, 3.0f}, 0.3f));
  const int w = 640, h = 480;
  FrameSettings s = settingsFor(w, h);
  s.reflections = s.refraction = EffectMode::Off;
  for (int threads : {1, 2})
    for (bool batched : {false, true}) {
      auto rt = makeTracer(scene, threads);
      ASSERT_TRUE(rt);
      VisibilityBuffer vis;
      rt->castVisibility(scene.camera, w, h, vis);
      RayOutputs out;
      const BenchTrace how{nullptr, batched};
      RayTracerBench::trace(*rt, scene, scene.camera, s, vis, out, how);  // warm-up
      double best = 1e30;
      for (int rep = 0; rep < 5; ++rep) {
        auto t0 = std::chrono::steady_clock::now();
        RayTracerBench::trace(*rt, scene, scene.camera, s, vis, out, how);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      ASSERT_GT(out.counts.shadow, 0u);
      std::printf("threads %d %-10s shadow rays %llu  best %.2f ms  %.2f Mrays/s (shadow)  %.2f Mrays/s (all)\n", threads,
                  batched ? "occluded1M" : "occluded1", static_cast<unsigned long long>(out.counts.shadow), best * 1e3,
                  double(out.counts.shadow) / best * 1e-6, double(out.counts.total()) / best * 1e-6);
    }
}

}  // namespace
}  // namespace tandem::rt
