// The path-traced reference (FrameSettings::gi = Path, rt/PathTracer.h; docs/path-tracing.md): a closed
// furnace meets the analytic E / (1 − ρ) at any scale and far from the origin, the error halves as the
// samples quadruple, a scene without diffuse bounces is the Whitted reference, and any thread count gives
// the same image.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "rt/PathTracer.h"
#include "rt/RtTestScenes.h"
#include "tandem/SceneFile.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

FrameSettings pathSettings(int size, int spp) {
  FrameSettings s = *presetSettings("reference", settingsFor(size, size));
  s.gi = GlobalIllumination::Path;
  s.referenceSpp = spp;
  return s;
}

ImageF render(RayTracer& tracer, const Scene& scene, const FrameSettings& s) {
  ImageF out;
  RayCounts counts;
  tracer.renderReference(scene, scene.camera, s, out, counts);
  return out;
}

glm::dvec3 mean(const ImageF& image) {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& c : image.rgb) sum += glm::dvec3(c);
  return sum / static_cast<double>(image.rgb.size());
}

double rmse(const ImageF& a, const ImageF& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(a.rgb[i]) - glm::dvec3(b.rgb[i]);
    sum += glm::dot(d, d);
  }
  return std::sqrt(sum / (3.0 * static_cast<double>(a.rgb.size())));
}

// A closed box of side `side` at `centre`, every face emitting E and reflecting ρ (diffuse only), seen from
// inside: every pixel's radiance is E + ρ·(E + ρ·(...)) = E / (1 − ρ).
Scene furnace(float rho, glm::vec3 emission, float side, glm::vec3 centre) {
  Scene s;
  Material m;
  m.kd = glm::vec3(rho);
  m.ka = glm::vec3(0.0f);
  m.ks = glm::vec3(0.0f);
  m.emission = emission;
  const std::uint32_t mat = addMaterial(s, m);
  addInstance(s, addMesh(s, makeBox(glm::vec3(side))), mat, translate(centre));
  s.camera.posW = centre + side * glm::vec3(0.1f, -0.05f, 0.3f);
  s.camera.targetW = centre + side * glm::vec3(-0.2f, 0.1f, -0.4f);
  s.camera.nearZ = 1e-3f * side;
  s.background = glm::vec3(0.0f);
  return s;
}

TEST(PathTracer, TheFurnaceMeetsTheAnalyticRadiance) {
  const glm::vec3 e(0.2f, 0.1f, 0.05f);
  for (float rho : {0.5f, 0.8f}) {
    for (float side : {1e-3f, 1.0f, 1e3f}) {
      for (glm::vec3 centre : {glm::vec3(0.0f), glm::vec3(1e5f, -3e4f, 2e4f)}) {
        if (centre != glm::vec3(0.0f) && side < 1.0f) continue;  // a millimetre box at 1e5 is below float's grain
        const Scene scene = furnace(rho, e, side, centre);
        auto tracer = makeTracer(scene);
        ASSERT_TRUE(tracer);
        const glm::dvec3 got = mean(render(*tracer, scene, pathSettings(32, 2)));
        const glm::dvec3 expected = glm::dvec3(e) / (1.0 - rho);
        std::printf("furnace rho %.1f side %g at %g: %.5f (expected %.5f)\n", rho, side, centre.x, got.x, expected.x);
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(got[c], expected[c], 0.03 * expected[c]) << "rho " << rho << " side " << side << " channel " << c;
      }
    }
  }
}

TEST(PathTracer, TheErrorHalvesAsTheSamplesQuadruple) {
  auto scene = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/cornell-box.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto tracer = makeTracer(*scene);
  ASSERT_TRUE(tracer);
  const ImageF truth = render(*tracer, *scene, pathSettings(32, 24));  // 576 samples a pixel
  double e[3];
  const int spps[3] = {1, 2, 4};  // 1, 4 and 16 samples a pixel
  for (int i = 0; i < 3; ++i) e[i] = rmse(render(*tracer, *scene, pathSettings(32, spps[i])), truth);
  std::printf("RMSE against 576 samples: 1 %.5f, 4 %.5f, 16 %.5f (ratios %.2f, %.2f)\n", e[0], e[1], e[2],
              e[0] / e[1], e[1] / e[2]);
  EXPECT_NEAR(e[0] / e[1], 2.0, 0.45);
  EXPECT_NEAR(e[1] / e[2], 2.0, 0.45);
}

TEST(PathTracer, WithoutDiffuseBouncesItIsTheWhittedReference) {
  // Black diffuse colours and no ambient term: the only continuations are the mirror's, shorter than the
  // roulette's first bounce, so each path is exactly Whitted's recursion.
  Scene scene;
  Material floor, mirror;
  floor.kd = floor.ka = glm::vec3(0.0f);
  floor.ks = glm::vec3(0.6f);
  floor.ns = 20.0f;
  mirror.kd = mirror.ka = glm::vec3(0.0f);
  mirror.ks = glm::vec3(0.8f);
  mirror.kr = 0.85f;
  const std::uint32_t floorMat = addMaterial(scene, floor), mirrorMat = addMaterial(scene, mirror);
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 1)), floorMat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makeSphere(1.0f, 48, 24)), mirrorMat, translate({0.0f, 1.0f, 0.0f}));
  scene.lights.push_back(pointLight({2.0f, 4.0f, 3.0f}, 2.0f));
  scene.camera.posW = {0.0f, 2.0f, 6.0f};
  scene.camera.targetW = {0.0f, 0.8f, 0.0f};
  scene.background = glm::vec3(0.1f, 0.2f, 0.3f);
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  FrameSettings whitted = pathSettings(48, 1);
  whitted.gi = GlobalIllumination::None;
  const ImageF a = render(*tracer, scene, pathSettings(48, 1)), b = render(*tracer, scene, whitted);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) worst = std::max(worst, double(glm::length(a.rgb[i] - b.rgb[i])));
  EXPECT_LT(worst, 1e-5);
}

TEST(PathTracer, TheSameSamplesGiveTheSameImageOnAnyThreadCount) {
  auto scene = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/cornell-box.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto one = makeTracer(*scene, 1), two = makeTracer(*scene, 2);
  ASSERT_TRUE(one && two);
  const ImageF a = render(*one, *scene, pathSettings(24, 2)), b = render(*two, *scene, pathSettings(24, 2));
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0);
  for (const glm::vec3& c : a.rgb) ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
}

TEST(PathTracer, CosineDirectionsFollowTheCosineLobe) {
  // The mean of cos θ under the pdf cos θ / π is 2/3; every direction on the normal's side.
  for (glm::vec3 n : {glm::vec3(0.0f, 0.0f, 1.0f), glm::normalize(glm::vec3(0.9f, -0.3f, 0.1f))}) {
    double sum = 0.0;
    const int count = 64 * 64;
    for (int i = 0; i < 64; ++i)
      for (int j = 0; j < 64; ++j) {
        const glm::vec3 d = cosineDirection(n, (glm::vec2(i, j) + 0.5f) / 64.0f);
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        ASSERT_GE(glm::dot(d, n), 0.0f);
        sum += glm::dot(d, n);
      }
    EXPECT_NEAR(sum / count, 2.0 / 3.0, 2e-3);
  }
}

}  // namespace
}  // namespace tandem::rt
