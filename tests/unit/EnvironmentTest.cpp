// The environment (core/Environment.h; docs/environment.md): tdEquirectUv's directions, the image's bilinear
// lookup at texel centres and across the seam, the turn about +Y, and the ambient term's nine coefficients
// against the irradiance integrated directly (a uniform environment exactly, the sky and an image with a
// bright patch within the series' own error).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "core/Environment.h"
#include "core/Shading.h"

namespace tandem {
namespace {

constexpr float kPi = 3.14159265f;

Scene withEnvironment(const Environment& e) {
  Scene s;
  s.environment = e;
  return s;
}

std::shared_ptr<EnvironmentMap> uniformMap(glm::vec3 l, int w, int h) {
  return std::make_shared<EnvironmentMap>(w, h, std::vector<glm::vec3>(std::size_t(w * h), l));
}

// Irradiance over π at a surface facing n: ∫ L(d) max(n·d, 0) dω / π over a fine grid of the sphere.
glm::vec3 directAmbient(const EnvironmentLookup& env, glm::vec3 n, int rows = 400) {
  glm::dvec3 sum(0.0);
  const int cols = 2 * rows;
  for (int i = 0; i < rows; ++i) {
    const double theta = (i + 0.5) * M_PI / rows;
    for (int j = 0; j < cols; ++j) {
      const double phi = (j + 0.5) * 2.0 * M_PI / cols;
      const glm::vec3 d(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)), float(std::sin(theta) * std::sin(phi)));
      const double c = std::max(0.0, double(glm::dot(n, d)));
      if (c > 0.0) sum += glm::dvec3(env.radiance(d)) * c * std::sin(theta) * (M_PI / rows) * (2.0 * M_PI / cols);
    }
  }
  return glm::vec3(sum / M_PI);
}

const glm::vec3 kNormals[] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}, glm::normalize(glm::vec3(1, 1, 1)),
                              glm::normalize(glm::vec3(-0.3f, -0.6f, 0.7f)), glm::normalize(glm::vec3(0.9f, 0.1f, -0.2f))};

TEST(Environment, EquirectangularCoordinatesFollowTheDocumentedAxes) {
  auto near = [](glm::vec2 a, glm::vec2 b) { return glm::length(a - b) < 1e-6f; };
  EXPECT_TRUE(near(shading::tdEquirectUv({0, 0, -1}), {0.5f, 0.5f}));
  EXPECT_TRUE(near(shading::tdEquirectUv({1, 0, 0}), {0.75f, 0.5f}));
  EXPECT_TRUE(near(shading::tdEquirectUv({-1, 0, 0}), {0.25f, 0.5f}));
  EXPECT_NEAR(shading::tdEquirectUv({0, 1, 0}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(shading::tdEquirectUv({0, -1, 0}).y, 1.0f, 1e-6f);
  EXPECT_NEAR(shading::tdEquirectUv(glm::normalize(glm::vec3(0, 1, -1))).y, 0.25f, 1e-6f);
}

TEST(Environment, TheImageIsReadBilinearlyWrappingAtTheSeam) {
  const int w = 8, h = 4;
  std::vector<glm::vec3> t;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.emplace_back(float(x), float(y), 1.0f);
  const EnvironmentMap map(w, h, t);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      EXPECT_EQ(sampleEquirect(map, {(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)}), glm::vec3(float(x), float(y), 1.0f));
  // u = 0 lies between the last column and the first: half of each.
  EXPECT_NEAR(sampleEquirect(map, {0.0f, 0.5f / h}).x, 0.5f * (w - 1), 1e-5f);
  // Above the first row's centre: that row (clamped), not the last one's.
  EXPECT_NEAR(sampleEquirect(map, {0.5f / w, 0.0f}).y, 0.0f, 1e-6f);
  EXPECT_NEAR(sampleEquirect(map, {0.5f / w, 1.0f}).y, float(h - 1), 1e-6f);
}

TEST(Environment, ATurnAboutUpMovesTheImageWithIt) {
  const int w = 64, h = 32;
  std::vector<glm::vec3> t;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) t.emplace_back(std::sin(6.2831853f * (float(x) + 0.5f) / float(w)) + 1.5f, (float(y) + 0.5f) / float(h), 0.2f);
  Environment e;
  e.kind = Environment::Kind::Map;
  e.map = std::make_shared<EnvironmentMap>(w, h, t);
  const EnvironmentLookup still(withEnvironment(e));
  e.rotationDeg = 40.0f;
  e.intensity = 2.0f;
  const EnvironmentLookup turned(withEnvironment(e));
  const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), glm::radians(40.0f), glm::vec3(0, 1, 0)));
  for (glm::vec3 d : kNormals) {
    const glm::vec3 a = 2.0f * still.radiance(d), b = turned.radiance(turn * d);
    EXPECT_LT(glm::length(a - b), 1e-4f) << d.x << "," << d.y << "," << d.z;
    // and the ambient term turns and scales with it
    EXPECT_LT(glm::length(2.0f * still.ambient(d) - turned.ambient(turn * d)), 1e-4f);
  }
  // Counter-clockwise seen from above: what was straight ahead (−Z) is now towards −X.
  EXPECT_LT(glm::length(turned.radiance(turn * glm::vec3(0, 0, -1)) - 2.0f * still.radiance({0, 0, -1})), 1e-4f);
  EXPECT_LT((turn * glm::vec3(0, 0, -1)).x, -0.5f);
}

TEST(Environment, AUniformEnvironmentLightsTheAmbientTermWithItsRadiance) {
  Environment e;
  e.kind = Environment::Kind::Map;
  e.map = uniformMap({0.3f, 0.6f, 1.2f}, 64, 32);
  e.intensity = 1.5f;
  const EnvironmentLookup env(withEnvironment(e));
  for (glm::vec3 n : kNormals) {
    const glm::vec3 a = env.ambient(n);
    EXPECT_NEAR(a.x, 0.45f, 1.5e-3f);
    EXPECT_NEAR(a.y, 0.9f, 3e-3f);
    EXPECT_NEAR(a.z, 1.8f, 6e-3f);
    EXPECT_LT(glm::length(env.radiance(n) - glm::vec3(0.45f, 0.9f, 1.8f)), 1e-6f);
  }
}

TEST(Environment, TheSkysAmbientTermIsItsIrradianceWithinTheSeriesError) {
  Environment e;
  e.kind = Environment::Kind::Sky;
  const EnvironmentLookup env(withEnvironment(e));
  for (glm::vec3 n : kNormals) {
    const glm::vec3 want = directAmbient(env, n), got = env.ambient(n);
    // Nine coefficients: about 3 % off for a smooth sky (Ramamoorthi and Hanrahan 2001).
    EXPECT_LT(glm::length(got - want), 0.04f * glm::length(want)) << n.x << "," << n.y << "," << n.z;
  }
  // Brighter facing the sky than facing the ground.
  EXPECT_GT(env.ambient({0, 1, 0}).x, 2.0f * env.ambient({0, -1, 0}).x);
}

TEST(Environment, AnImagesAmbientTermFollowsItsBrightSide) {
  // A bright half-sky over a dim world: low-order light the nine coefficients hold well.
  const int w = 64, h = 32;
  std::vector<glm::vec3> t;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float u = (float(x) + 0.5f) / float(w), v = (float(y) + 0.5f) / float(h);
      const float bright = std::max(0.0f, std::cos(6.2831853f * (u - 0.75f))) * std::max(0.0f, std::cos(kPi * v));
      t.emplace_back(0.1f + 2.0f * bright, 0.1f + 1.0f * bright, 0.1f);
    }
  Environment e;
  e.kind = Environment::Kind::Map;
  e.map = std::make_shared<EnvironmentMap>(w, h, t);
  const EnvironmentLookup env(withEnvironment(e));
  for (glm::vec3 n : kNormals) {
    const glm::vec3 want = directAmbient(env, n), got = env.ambient(n);
    EXPECT_LT(glm::length(got - want), 0.05f * glm::length(want) + 0.01f) << n.x << "," << n.y << "," << n.z;
  }
  EXPECT_GT(env.ambient(glm::normalize(glm::vec3(1, 1, 0))).x, 4.0f * env.ambient(glm::normalize(glm::vec3(-1, -1, 0))).x);
}

TEST(Environment, TheBackgroundLightsNothingAndAnAmbientOffEnvironmentNeither) {
  Scene s;
  s.background = {0.1f, 0.2f, 0.3f};
  const EnvironmentLookup plain(s);
  EXPECT_EQ(plain.radiance({0, 1, 0}), s.background);
  EXPECT_EQ(plain.ambient({0, 1, 0}), glm::vec3(0.0f));
  s.environment.kind = Environment::Kind::Sky;
  s.environment.lightsAmbient = false;
  const EnvironmentLookup sky(s);
  EXPECT_EQ(sky.ambient({0, 1, 0}), glm::vec3(0.0f));
  EXPECT_EQ(sky.radiance({0, 1, 0}), s.environment.zenith);
  EXPECT_EQ(sky.radiance({0, -1, 0}), s.environment.ground);
  EXPECT_EQ(sky.radiance({1, 0, 0}), s.environment.horizon);
  // the path tracer's: no ambient term, the same sky
  s.environment.lightsAmbient = true;
  EXPECT_EQ(EnvironmentLookup(s, false).ambient({0, 1, 0}), glm::vec3(0.0f));
  EXPECT_NE(EnvironmentLookup(s).ambient({0, 1, 0}), glm::vec3(0.0f));
}

}  // namespace
}  // namespace tandem
