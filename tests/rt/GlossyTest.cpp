// The glossy lobe (rt/SurfaceShading.h, glossyDirection; docs/glossy.md): the mirror at roughness 0, the Phong
// lobe's moments, directions kept on their side of the facet, and finite unit directions at the extremes.
#include <gtest/gtest.h>

#include <cmath>

#include "core/Shading.h"
#include "rt/SurfaceShading.h"

namespace tandem::rt {
namespace {

glm::vec2 sampleU(std::uint32_t i) { return shading::tdLightSampleU(12345u, kGlossReflectStream, i); }

TEST(Glossy, RoughnessZeroIsTheMirrorDirection) {
  const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, 0.8f, -0.2f)), side(0.0f, 1.0f, 0.0f);
  for (std::uint32_t i = 0; i < 64; ++i) EXPECT_EQ(glossyDirection(axis, 0.0f, sampleU(i), side), axis);
  EXPECT_TRUE(std::isinf(glossExponent(0.0f)));
  EXPECT_EQ(glossExponent(1.0f), 0.0f);
  // Nearly smooth: within a few 1e-7 of the mirror (the lobe's width is α = roughness² radians).
  for (std::uint32_t i = 0; i < 64; ++i)
    EXPECT_LT(glm::length(glossyDirection(axis, 1e-4f, sampleU(i), side) - axis), 1e-6f);
}

TEST(Glossy, SamplesFollowThePhongLobe) {
  // Around the normal no sample crosses the facet, so the mean of cos θ is the lobe's, (e + 1)/(e + 2),
  // and the mean direction is the axis.
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  for (float roughness : {0.2f, 0.5f, 0.8f, 1.0f}) {
    const double e = glossExponent(roughness);
    double meanCos = 0.0;
    glm::dvec3 meanDir(0.0);
    const int count = 4096;
    for (int i = 0; i < count; ++i) {
      const glm::vec3 d = glossyDirection(n, roughness, sampleU(static_cast<std::uint32_t>(i)), n);
      meanCos += static_cast<double>(d.z);
      meanDir += glm::dvec3(d);
    }
    meanCos /= count;
    meanDir /= count;
    EXPECT_NEAR(meanCos, (e + 1.0) / (e + 2.0), 2e-3) << roughness;
    EXPECT_LT(std::hypot(meanDir.x, meanDir.y), 0.02) << roughness;
  }
}

TEST(Glossy, DirectionsStayOnTheirSideAndFinite) {
  // Grazing mirror directions, axes along ±z (the frame's branch), every roughness: unit, finite, and in
  // front of the facet (a sample below it is mirrored back).
  const glm::vec3 side = glm::normalize(glm::vec3(0.1f, 1.0f, 0.05f));
  const glm::vec3 axes[] = {glm::normalize(glm::vec3(1.0f, 1e-3f, 0.0f)), glm::vec3(0.0f, 0.0f, 1.0f),
                            glm::vec3(0.0f, 0.0f, -1.0f), glm::normalize(glm::vec3(0.0f, 1e-6f, -1.0f)), side};
  for (const glm::vec3& axis : axes)
    for (float roughness : {1e-6f, 0.05f, 0.5f, 1.0f})
      for (std::uint32_t i = 0; i < 256; ++i) {
        const glm::vec3 d = glossyDirection(axis, roughness, sampleU(i), side);
        ASSERT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z));
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        if (glm::dot(axis, side) > 0.0f) {
          ASSERT_GE(glm::dot(d, side), 0.0f) << roughness;
        }
      }
  // u = 0 (the sequence's first point under a zero shift) is the lobe's rim, still finite.
  const glm::vec3 d = glossyDirection(glm::vec3(0.0f, 1.0f, 0.0f), 0.3f, glm::vec2(0.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  EXPECT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z));
}

}  // namespace
}  // namespace tandem::rt
