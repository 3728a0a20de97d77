// Exact solids in the hybrid frame (docs/csg.md, "In the raster frame"): the raster draws each solid's proxy,
// the resolve step traces those pixels' camera rays, and the GL shades what they found — the solid's exact
// point, or what lies behind where the ray passes the solid by. Every preset then shows the solids as the
// reference does, the holes of a CSG solid show the floor exactly as a frame without the solid, still frames
// reuse the resolved pixels, and exact spheres remove the tessellation's error.
#include <gtest/gtest.h>

#include <cstring>

#include "gl/GlTestUtil.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 240, kH = 136;

// A floor, a glass sphere, a die (a box less a sphere: a hole through each face), a mirror ring and a lens.
std::string sceneText(bool withSolids) {
  const std::string e = "true";
  std::string meshes = R"("floor": { "primitive": "plane", "size": [10, 10], "divisions": 4 })";
  std::string instances = R"({ "name": "floor", "mesh": "floor", "material": "floor" })";
  if (withSolids) {
    meshes += R"(, "ball": { "primitive": "sphere", "radius": 0.6, "exact": )" + e + R"( },
      "die": { "csg": "difference", "of": [ { "primitive": "box", "size": 1 }, { "primitive": "sphere", "radius": 0.62 } ] },
      "ring": { "primitive": "torus", "radius": 0.6, "tube": 0.18 },
      "lens": { "csg": "intersection", "of": [
        { "primitive": "sphere", "radius": 1, "translate": [0, 0, -0.7] },
        { "primitive": "sphere", "radius": 1, "translate": [0, 0, 0.7] } ] })";
    instances += R"(,
      { "name": "ball", "mesh": "ball", "material": "glass", "transform": { "translate": [-0.2, 0.6, 0.6] } },
      { "name": "die", "mesh": "die", "material": "matte", "transform": { "translate": [1.5, 0.5, -0.3], "rotate": [0, 25, 0] } },
      { "name": "ring", "mesh": "ring", "material": "mirror", "transform": { "translate": [-1.7, 0.8, -0.5], "rotate": [75, 20, 0] } },
      { "name": "lens", "mesh": "lens", "material": "glass", "transform": { "translate": [0.6, 0.45, 1.6], "scale": 0.4 } })";
  }
  return R"({ "name": "exact", "meshes": { )" + meshes + R"( },
    "materials": {
      "floor": { "ka": [0.8, 0.1, 0.1], "kd": [0.8, 0.1, 0.1], "checker": { "color2": [0.9, 0.8, 0.1], "frequency": 1 } },
      "matte": { "ka": [0.2, 0.3, 0.8], "kd": [0.2, 0.3, 0.8], "ks": 0.3, "ns": 20 },
      "mirror": { "ka": 0.02, "kd": 0.05, "ks": 0.8, "ns": 200, "kr": 0.85 },
      "glass": { "ka": 0.02, "kd": 0.02, "ks": 0.9, "ns": 300, "kr": 0.1, "kt": 0.9, "ior": 1.5 } },
    "lights": [ { "type": "ambient", "intensity": 0.2 },
                { "type": "point", "position": [-3, 6, 4], "intensity": 0.9 },
                { "type": "directional", "direction": [0.3, -1, -0.4], "intensity": 0.4 } ],
    "instances": [ )" + instances + R"( ],
    "camera": { "position": [0, 2.0, 5.0], "target": [0, 0.5, 0], "fov": 40 },
    "background": [0.24, 0.62, 0.83] })";
}

gltest::SceneFrame frame(GlContext& context, const std::string& text, int threads = 0) {
  return gltest::sceneFrame(context, parseSceneJson(text, "exact", "."), kW, kH, threads);
}

FrameSettings preset(const gltest::SceneFrame& f, const char* name) { return gltest::presetFor(f, name); }

// Local shading only: no shadows, no secondary rays (the GL's shade pass against its CPU twin).
FrameSettings localOnly(FrameSettings s, ShadingModel model) {
  s.shadows = s.reflections = s.refraction = EffectMode::Off;
  s.maxDepth = 0;
  s.shadingOverride = model;
  return s;
}

TEST(ExactSolidsGL, EveryPresetShadesTheSolidsAsTheReferenceDoes) {
  TD_REQUIRE_GL_CONTEXT();
  auto f = frame(*glContext_, sceneText(true));
  ASSERT_TRUE(f.renderer);
  // The proxies alone (the solids' exact parts taken away) are far off: the comparisons below can tell.
  auto proxyScene = parseSceneJson(sceneText(true), "exact", ".");
  ASSERT_TRUE(proxyScene.ok());
  for (Mesh& m : proxyScene->meshes) m.exact.reset();
  auto proxies = gltest::sceneFrame(*glContext_, std::move(proxyScene), kW, kH);
  ASSERT_TRUE(proxies.renderer);
  for (ShadingModel model : {ShadingModel::Flat, ShadingModel::Gouraud, ShadingModel::Phong}) {
    const Image truth = gltest::drawFrame(f, localOnly(preset(f, "reference"), model));
    for (const char* name : {"raster", "hybrid-fast", "hybrid-full"}) {
      const double err = gltest::flipMean(gltest::drawFrame(f, localOnly(preset(f, name), model)), truth);
      EXPECT_LT(err, 0.0005) << name << " model " << static_cast<int>(model);
    }
  }
  // The whole frame: hybrid-full against the reference at the same pixel centres (shadows, mirror, glass).
  const Image reference = gltest::drawFrame(f, preset(f, "reference"));
  const Image full = gltest::drawFrame(f, preset(f, "hybrid-full"));
  const double err = gltest::flipMean(full, reference);
  EXPECT_LT(err, 0.003);
  gltest::savePng("exact-hybrid-full.png", full);
  gltest::savePng("exact-reference.png", reference);
  // The CSG solids by their boxes (sphere and ring differ less): well beyond either bound.
  FrameSettings box = localOnly(preset(f, "hybrid-full"), ShadingModel::Phong);
  const double proxyErr = gltest::flipMean(gltest::drawFrame(proxies, box),
                                           gltest::drawFrame(f, localOnly(preset(f, "reference"), ShadingModel::Phong)));
  EXPECT_GT(proxyErr, 0.01) << "a frame that showed the proxies would fail the checks above";
}

TEST(ExactSolidsGL, HolesShowWhatLiesBehindExactlyAsWithoutTheSolid) {
  TD_REQUIRE_GL_CONTEXT();
  auto with = frame(*glContext_, sceneText(true));
  auto without = frame(*glContext_, sceneText(false));
  ASSERT_TRUE(with.renderer && without.renderer);
  // Raster, shadows off: the floor's shading does not depend on the solids.
  FrameSettings s = localOnly(preset(with, "raster"), ShadingModel::Phong);
  s.shadingOverride.reset();
  FrameStats st;
  const Image withImage = gltest::drawFrame(with, s, &st), withoutImage = gltest::drawFrame(without, s);
  ASSERT_GT(st.rays.resolved, 0u);
  FrameSettings ids = s;
  ids.debugView = DebugView::InstanceId;
  const Image withIds = gltest::drawFrame(with, ids), withoutIds = gltest::drawFrame(without, ids);
  FrameSettings depth = s;
  depth.debugView = DebugView::Depth;
  const Image withDepth = gltest::drawFrame(with, depth), withoutDepth = gltest::drawFrame(without, depth);
  // Pixels where the frame with the solids shows the floor, or the sky, as the frame without them does:
  // identical there, colour and depth. Inside the solids' proxies (about st.rays.resolved pixels) many are.
  std::size_t same = 0, floorOrSky = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kW * kH); ++p) {
    if (std::memcmp(&withIds.rgba[4 * p], &withoutIds.rgba[4 * p], 4) != 0) continue;  // a solid there
    ++floorOrSky;
    same += std::memcmp(&withImage.rgba[4 * p], &withoutImage.rgba[4 * p], 4) == 0 &&
                    std::memcmp(&withDepth.rgba[4 * p], &withoutDepth.rgba[4 * p], 4) == 0
                ? 1
                : 0;
  }
  EXPECT_EQ(same, floorOrSky);
  // More floor and sky than the proxies leave: the solids' holes and the space around the ring and sphere.
  std::size_t solidPixels = 0;
  for (std::size_t p = 0; p < static_cast<std::size_t>(kW * kH); ++p)
    solidPixels += std::memcmp(&withIds.rgba[4 * p], &withoutIds.rgba[4 * p], 4) != 0 ? 1 : 0;
  EXPECT_LT(solidPixels + 300, st.rays.resolved) << "resolved pixels that showed what lies behind";
}

TEST(ExactSolidsGL, StillFramesReuseTheResolvedPixels) {
  TD_REQUIRE_GL_CONTEXT();
  auto f = frame(*glContext_, sceneText(true));
  ASSERT_TRUE(f.renderer);
  for (const char* name : {"raster", "hybrid-full"}) {
    FrameSettings s = preset(f, name);
    s.reuseRays = true;
    FrameStats first, second;
    const Image a = gltest::drawFrame(f, s, &first);
    const Image b = gltest::drawFrame(f, s, &second);
    EXPECT_FALSE(first.raysReused) << name;
    EXPECT_GT(first.rays.resolved, 0u) << name;
    EXPECT_TRUE(second.raysReused) << name;
    EXPECT_EQ(second.rays.resolved, 0u) << name << ": nothing traced again";
    EXPECT_TRUE(gltest::sameImage(a, b)) << name << ": the raster's proxies drawn again, the resolved pixels with them";
  }
}

TEST(ExactSolidsGL, StatsCountOneRayPerProxyPixelInEveryHybridPreset) {
  TD_REQUIRE_GL_CONTEXT();
  auto f = frame(*glContext_, sceneText(true));
  auto none = frame(*glContext_, sceneText(false));
  ASSERT_TRUE(f.renderer && none.renderer);
  FrameStats raster, fast, full, reference, without;
  gltest::drawFrame(f, preset(f, "raster"), &raster);
  gltest::drawFrame(f, preset(f, "hybrid-fast"), &fast);
  gltest::drawFrame(f, preset(f, "hybrid-full"), &full);
  gltest::drawFrame(f, preset(f, "reference"), &reference);
  gltest::drawFrame(none, preset(none, "hybrid-full"), &without);
  EXPECT_GT(raster.rays.resolved, 1000u);
  EXPECT_EQ(fast.rays.resolved, raster.rays.resolved) << "the same proxies from the same camera";
  EXPECT_EQ(full.rays.resolved, raster.rays.resolved);
  EXPECT_EQ(raster.rays.primary, 0u) << "the raster preset traces the resolve step's rays and nothing else";
  EXPECT_EQ(raster.rays.total(), raster.rays.resolved);
  EXPECT_EQ(reference.rays.resolved, 0u) << "the reference's camera rays see the solids themselves";
  EXPECT_EQ(without.rays.resolved, 0u);
}

TEST(ExactSolidsGL, SameFrameOnAnyThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  auto one = frame(*glContext_, sceneText(true), 1);
  auto two = frame(*glContext_, sceneText(true), 2);
  ASSERT_TRUE(one.renderer && two.renderer);
  for (const char* name : {"raster", "hybrid-full"}) gltest::expectSameFrame(one, two, preset(one, name), name);
}

TEST(ExactSolidsGL, ExactSpheresRemoveTheTessellationError) {
  TD_REQUIRE_GL_CONTEXT();
  // The Whitted scene with its spheres exact: the truth is the reference of that scene, at the same pixel
  // centres (1 spp). The hybrid frame of the exact scene meets it as closely as any hybrid frame meets its
  // reference; the tessellated scene's frame carries the 64 × 32 facets' error on top.
  auto text = std::string(defaultSceneText());
  auto exactText = text;
  const std::string sphere = R"("primitive": "sphere", "radius": 1, "segments": 64, "rings": 32)";
  const std::size_t at = exactText.find(sphere);
  ASSERT_NE(at, std::string::npos) << "the embedded scene's sphere mesh";
  exactText.replace(at, sphere.size(), sphere + R"(, "exact": true)");
  auto exact = gltest::sceneFrame(*glContext_, parseSceneJson(exactText, "whitted-exact", "."), 320, 180);
  auto tessellated = gltest::sceneFrame(*glContext_, parseSceneJson(text, "whitted", "."), 320, 180);
  ASSERT_TRUE(exact.renderer && tessellated.renderer);
  const Image truth = gltest::drawFrame(exact, preset(exact, "reference"));
  const double exactErr = gltest::flipMean(gltest::drawFrame(exact, preset(exact, "hybrid-full")), truth);
  const double tessErr = gltest::flipMean(gltest::drawFrame(tessellated, preset(tessellated, "hybrid-full")), truth);
  std::printf("whitted 320x180 hybrid-full vs the exact reference: exact spheres %.5f, tessellated %.5f\n", exactErr,
              tessErr);
  EXPECT_LT(exactErr, 0.6 * tessErr);
  EXPECT_LT(exactErr, 0.0025);
}

}  // namespace
}  // namespace tandem
