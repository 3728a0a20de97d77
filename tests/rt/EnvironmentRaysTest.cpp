// The environment in the ray passes (docs/environment.md): rays that leave the scene see it and the ambient term
// takes its light, in the Whitted reference, the hybrid frame's ray pass and the path tracer alike. Closed forms:
// under a uniform environment L a diffuse convex ball of albedo ρ is ρL however its light is gathered (the
// ambient term's nine coefficients, or the path tracer's paths), and a perfect mirror shows the sky along
// each reflected ray.
#include <cmath>

#include <gtest/gtest.h>

#include "core/Environment.h"
#include "rt/CpuComposite.h"
#include "rt/RtTestScenes.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

Scene ballUnder(const Environment& environment, float albedo) {
  Scene s;
  Material m;
  m.kd = m.ka = glm::vec3(albedo);
  m.ks = glm::vec3(0.0f);
  addInstance(s, addMesh(s, makeSphere(1.0f, 64, 32)), addMaterial(s, m), glm::mat4(1.0f));
  s.environment = environment;
  s.camera.posW = {0.0f, 0.5f, 4.0f};
  s.camera.targetW = glm::vec3(0.0f);
  s.camera.yFovDeg = 45.0f;
  return s;
}

Environment uniform(glm::vec3 l) {
  Environment e;
  e.kind = Environment::Kind::Map;
  e.map = std::make_shared<EnvironmentMap>(64, 32, std::vector<glm::vec3>(64 * 32, l));
  return e;
}

ImageF reference(const Scene& scene, const FrameSettings& s) {
  auto tracer = makeTracer(scene);
  ImageF out;
  RayCounts counts;
  if (tracer) tracer->renderReference(scene, scene.camera, s, out, counts);
  return out;
}

ImageF hybrid(const Scene& scene, const FrameSettings& s) {
  auto tracer = makeTracer(scene);
  VisibilityBuffer vis;
  RayOutputs rays;
  ImageF out;
  if (!tracer) return out;
  castAndTrace(*tracer, scene, s, vis, rays);
  compositeOnCpu(scene, scene.camera, s, vis, rays, out);
  return out;
}

// The ball's pixels and the background's: those whose whole footprint (its corners and centre) is on the
// unit ball at the origin or off it; pixels on its outline are left out.
template <class Fn>
void eachPixel(const Scene& scene, int w, int h, Fn fn) {
  auto onBall = [&](glm::vec2 p) {
    const Ray r = scene.camera.rayThroughPixel(p, {w, h});
    const float b = glm::dot(r.origin, r.dir), c = glm::dot(r.origin, r.origin) - 1.0f;
    return b * b - c > 0.0f;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool centre = onBall({float(x) + 0.5f, float(y) + 0.5f});
      bool whole = true;
      for (glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(1, 1)})
        whole = whole && onBall(glm::vec2(float(x), float(y)) + corner) == centre;
      if (whole) fn(x, y, centre);
    }
}

TEST(EnvironmentRays, ADiffuseBallUnderAUniformEnvironmentIsItsAlbedoTimesItsRadiance) {
  const glm::vec3 l(0.5f, 0.8f, 1.0f);
  const float albedo = 0.6f;
  const Scene scene = ballUnder(uniform(l), albedo);
  const int n = 48;
  const FrameSettings whitted = *presetSettings("reference", settingsFor(n, n));
  FrameSettings path = whitted;
  path.gi = GlobalIllumination::Path;
  path.referenceSpp = 4;
  const FrameSettings hybridFull = *presetSettings("hybrid-full", settingsFor(n, n));
  const ImageF ref = reference(scene, whitted), paths = reference(scene, path), frame = hybrid(scene, hybridFull);
  ASSERT_EQ(ref.rgb.size(), std::size_t(n * n));
  ASSERT_EQ(paths.rgb.size(), std::size_t(n * n));
  ASSERT_EQ(frame.rgb.size(), std::size_t(n * n));
  glm::dvec3 pathSum(0.0);
  int ball = 0, sky = 0;
  eachPixel(scene, n, n, [&](int x, int y, bool onBall) {
    const glm::vec3 want = onBall ? albedo * l : l;
    (onBall ? ball : sky)++;
    // The ambient term's coefficients hold a uniform environment to the grid's sub-percent error.
    EXPECT_LT(glm::length(ref.at(x, y) - want), 4e-3f * glm::length(want)) << x << "," << y;
    EXPECT_LT(glm::length(frame.at(x, y) - want), 4e-3f * glm::length(want)) << x << "," << y;
    if (onBall) pathSum += glm::dvec3(paths.at(x, y));
    else EXPECT_LT(glm::length(paths.at(x, y) - l), 1e-6f);
  });
  ASSERT_GT(ball, n * n / 8);
  ASSERT_GT(sky, n * n / 4);
  // The paths gather the environment by escaping from the ball (convex: every bounce escapes); their mean over
  // the ball is ρL to the samples' noise (4 spp x ~500 pixels: well under 2 %).
  const glm::vec3 pathMean(pathSum / double(ball));
  EXPECT_LT(glm::length(pathMean - albedo * l), 0.02f * glm::length(albedo * l))
      << pathMean.x << "," << pathMean.y << "," << pathMean.z;
}

TEST(EnvironmentRays, AMirrorShowsTheSkyAlongEachReflectedRay) {
  Environment sky;
  sky.kind = Environment::Kind::Sky;
  sky.rotationDeg = 25.0f;
  Scene scene;
  Material mirror;
  mirror.kd = mirror.ka = mirror.ks = glm::vec3(0.0f);
  mirror.kr = 1.0f;
  addInstance(scene, addMesh(scene, makePlane(glm::vec2(200.0f), 1)), addMaterial(scene, mirror), glm::mat4(1.0f));
  scene.environment = sky;
  scene.camera.posW = {0.0f, 1.0f, 3.0f};
  scene.camera.targetW = {0.0f, 0.0f, -2.0f};
  const int w = 64, h = 36;
  const EnvironmentLookup env(scene);
  const ImageF ref = reference(scene, *presetSettings("reference", settingsFor(w, h)));
  const ImageF frame = hybrid(scene, *presetSettings("hybrid-full", settingsFor(w, h)));
  ASSERT_EQ(ref.rgb.size(), std::size_t(w * h));
  ASSERT_EQ(frame.rgb.size(), std::size_t(w * h));
  int mirrored = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Ray r = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {w, h});
      // Above the horizon the sky itself; below it the mirror, showing the sky along the reflected ray.
      const glm::vec3 want = r.dir.y < -1e-3f ? env.radiance(glm::reflect(r.dir, glm::vec3(0, 1, 0)))
                                              : env.radiance(r.dir);
      if (std::abs(r.dir.y) < 1e-2f) continue;  // the horizon: the plane's far edge
      mirrored += r.dir.y < 0.0f;
      EXPECT_LT(glm::length(ref.at(x, y) - want), 1e-4f) << x << "," << y;
      EXPECT_LT(glm::length(frame.at(x, y) - want), 1e-4f) << x << "," << y;
    }
  EXPECT_GT(mirrored, w * h / 3);
}

}  // namespace
}  // namespace tandem::rt
