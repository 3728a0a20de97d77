// The glossy lobe (rt/SurfaceShading.h, glossyDirection; docs/glossy.md): the mirror at roughness 0, the Phong
// lobe's moments, directions kept on their side of the facet, and finite unit directions at the extremes; the
// spatiotemporal filter's cone of a lobe (shading.glsl's tdLobeSpread) holds 99 % of the sampler's directions.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/packing.hpp>

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

// The cone the spatiotemporal filter tests moved instances against for a glossy reflection (docs/denoise.md):
// about 1 % of the lobe's samples fall outside it, at every roughness, the narrow lobes' series included; a
// transmitting lobe is every direction (-1); no lobe, no cone (0).
TEST(Glossy, TheFiltersConeHoldsNinetyNinePercentOfTheLobe) {
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  float last = 0.0f;
  for (float roughness : {0.02f, 0.05f, 0.15f, 0.25f, 0.35f, 0.5f, 0.7f}) {
    const float spread = shading::tdLobeSpread(shading::tdLobeOf(roughness, 0.5f, 0.0f, 1.0f));
    ASSERT_GT(spread, last) << "a rougher lobe, a wider cone";
    last = spread;
    const int count = 16384;
    int outside = 0;
    for (int i = 0; i < count; ++i) {
      // (tan θ from the direction's parts: its z rounds to 1 in a narrow lobe)
      const glm::vec3 d = glossyDirection(n, roughness, sampleU(static_cast<std::uint32_t>(i)), n);
      outside += std::hypot(d.x, d.y) > spread * d.z ? 1 : 0;
    }
    EXPECT_NEAR(static_cast<double>(outside) / count, 0.01, 0.002) << "roughness " << roughness;
  }
  EXPECT_EQ(shading::tdLobeOf(0.0f, 0.5f, 0.0f, 1.0f), 0.0f);
  EXPECT_EQ(shading::tdLobeOf(0.3f, 0.0f, 0.0f, 1.0f), 0.0f) << "a highlight alone gathers nothing";
  EXPECT_EQ(shading::tdLobeOf(0.3f, 0.1f, 0.9f, 1.0f), -1.0f);
  EXPECT_EQ(shading::tdLobeOf(0.3f, 0.0f, 0.9f, 1.0f), -1.0f);
  EXPECT_EQ(shading::tdLobeOf(0.3f, 0.5f, 0.0f, 0.5f), -1.0f) << "a BLEND surface's uncovered part sees through";
  EXPECT_GT(glm::unpackHalf2x16(glm::packHalf2x16(glm::vec2(shading::tdLobeOf(1e-6f, 0.5f, 0.0f, 1.0f)))).x, 0.0f)
      << "a lobe however narrow stays a lobe in the guide's half float";
  EXPECT_EQ(shading::tdLobeSpread(0.0f), 0.0f);
  EXPECT_EQ(shading::tdLobeSpread(-1.0f), -1.0f);
}

}  // namespace
}  // namespace tandem::rt
