// FrameStats' ray counts through the Renderer, exactly, for each preset and effect combination, against counts
// made independently from the frame's own picture: a scene where every visible point faces every light (two
// up-facing planes, lights above) and only the lower plane is a mirror, so a hybrid frame traces one primary
// hit per covered pixel of its ray grid, one shadow ray per light (K per area light's samples) per hit, and one
// reflection ray per mirror pixel whose reflected hits (the plate's underside) face away from every light.
// The pixels are counted from the instance-id view.
#include <gtest/gtest.h>

#include <cstring>

#include "gl/GlTestUtil.h"
#include "rt/RayMath.h"

namespace tandem {
namespace {

constexpr int kW = 120, kH = 80;

Scene countsScene(bool areaLight) {
  Scene s;
  s.meshes.push_back(makePlane(glm::vec2(12.0f), 2));
  s.meshes.push_back(makePlane(glm::vec2(1.5f), 1));
  Material mirror;
  mirror.kd = glm::vec3(0.3f);
  mirror.kr = 0.5f;
  Material matte;
  matte.kd = glm::vec3(0.6f, 0.3f, 0.2f);
  s.materials = {mirror, matte};
  Instance floor;
  Instance plate;
  plate.mesh = 1;
  plate.material = 1;
  plate.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 1.0f, 0.0f));
  s.instances = {floor, plate};
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.intensity = 0.2f;
  Light sun;
  sun.type = LightType::Directional;
  sun.dirW = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  Light top;
  top.type = areaLight ? LightType::Rect : LightType::Point;
  top.posW = {0.0f, 6.0f, 0.0f};
  top.dirW = {0.0f, -1.0f, 0.0f};
  top.size = {1.0f, 1.0f};
  top.intensity = 10.0f;
  s.lights = {ambient, sun, top};
  s.camera.posW = {0.0f, 2.5f, 4.0f};
  s.camera.targetW = {0.0f, 0.3f, 0.0f};
  s.camera.yFovDeg = 60.0f;
  s.background = {0.2f, 0.3f, 0.5f};
  return s;
}

struct Pixels {
  std::vector<std::uint32_t> id;  // per pixel: 0 sky, 1 floor, 2 plate
};

// The instance under each pixel, from the instance-id view: black is the sky, the floor's colour is the one at
// the bottom row's middle, the plate's at its centre.
Pixels classify(gltest::SceneFrame& f, const Scene& scene) {
  FrameSettings s = gltest::rasterOnly(kW, kH);
  s.debugView = DebugView::InstanceId;
  const Image ids = gltest::drawFrame(f, s);
  auto colour = [&](int x, int y) {
    std::uint32_t c;
    std::memcpy(&c, &ids.rgba[4 * (static_cast<std::size_t>(y) * kW + x)], 4);
    return c;
  };
  const std::uint32_t floor = colour(kW / 2, kH - 1);
  const glm::mat4 clip = scene.camera.clipFromView(glm::ivec2(kW, kH)) * scene.camera.viewFromWorld();
  const glm::vec4 c = clip * glm::vec4(0.3f, 1.0f, 0.0f, 1.0f);
  const std::uint32_t plate = colour(static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kW), static_cast<int>((0.5f - c.y / c.w * 0.5f) * kH));
  std::uint32_t sky = 0;
  std::memcpy(&sky, &ids.rgba[0], 4);  // the top-left corner sees the sky
  EXPECT_NE(floor, plate);
  EXPECT_NE(floor, sky);
  Pixels p;
  p.id.resize(static_cast<std::size_t>(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::uint32_t v = colour(x, y);
      std::uint32_t& out = p.id[static_cast<std::size_t>(y) * kW + x];
      out = v == floor ? 1 : v == plate ? 2 : 0;
      EXPECT_TRUE(v == floor || v == plate || v == sky) << "pixel " << x << "," << y;
    }
  return p;
}

struct Expected {
  std::uint64_t hits = 0, mirror = 0;
};

// Hits and mirror hits among the grid pixels of a ray grid of `scale` (each stands for one full-res pixel).
Expected onGrid(const Pixels& p, int scale) {
  Expected e;
  for (int gy = 0; gy < rt::gridSize(kH, scale); ++gy)
    for (int gx = 0; gx < rt::gridSize(kW, scale); ++gx) {
      const glm::ivec2 q = rt::fullPixelOfGridPixel(gx, gy, scale, kW, kH);
      const std::uint32_t id = p.id[static_cast<std::size_t>(q.y) * kW + static_cast<std::size_t>(q.x)];
      e.hits += id != 0 ? 1 : 0;
      e.mirror += id == 1 ? 1 : 0;
    }
  return e;
}

void expectCounts(gltest::SceneFrame& f, const FrameSettings& s, RayCounts want, const std::string& what) {
  FrameStats st;
  gltest::drawFrame(f, s, &st);
  EXPECT_EQ(st.rays.primary, want.primary) << what;
  EXPECT_EQ(st.rays.shadow, want.shadow) << what;
  EXPECT_EQ(st.rays.reflection, want.reflection) << what;
  EXPECT_EQ(st.rays.refraction, want.refraction) << what;
  EXPECT_EQ(st.rays.resolved, 0u) << what;
}

TEST(FrameCountsGL, EveryPresetAndEffectCountsExactly) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = countsScene(false);
  auto f = gltest::sceneFrame(*glContext_, Result<Scene>(scene), kW, kH);
  ASSERT_TRUE(f.renderer);
  const Pixels p = classify(f, scene);
  const Expected full = onGrid(p, 1), half = onGrid(p, 2);
  ASSERT_GT(full.mirror, 3000u);
  ASSERT_GT(full.hits - full.mirror, 200u) << "the plate is in view";
  ASSERT_LT(full.hits, static_cast<std::uint64_t>(kW * kH)) << "and the sky";
  auto preset = [&](const char* name) {
    FrameSettings s = *presetSettings(name, f.base);
    s.reuseRays = false;
    s.referenceSpp = 1;
    return s;
  };
  // Two shadow-casting lights, both above every visible point.
  expectCounts(f, preset("raster"), {}, "raster");
  expectCounts(f, preset("hybrid-full"), {full.hits, 2 * full.hits, full.mirror, 0}, "hybrid-full");
  expectCounts(f, preset("hybrid-fast"), {half.hits, 2 * half.hits, half.mirror, 0}, "hybrid-fast (1/2 grid)");
  // The reference: a camera ray per pixel, sky included.
  expectCounts(f, preset("reference"), {static_cast<std::uint64_t>(kW * kH), 2 * full.hits, full.mirror, 0},
               "reference");
  FrameSettings s = preset("hybrid-full");
  s.shadows = EffectMode::Off;
  expectCounts(f, s, {full.hits, 0, full.mirror, 0}, "hybrid-full, shadows off");
  s = preset("hybrid-full");
  s.shadows = EffectMode::Raster;
  expectCounts(f, s, {full.hits, 0, full.mirror, 0}, "hybrid-full, raster shadows (no secondary hit faces a light)");
  s = preset("hybrid-full");
  s.maxDepth = 0;
  expectCounts(f, s, {full.hits, 2 * full.hits, 0, 0}, "hybrid-full, depth 0");
  s = preset("hybrid-full");
  s.reflections = EffectMode::Raster;
  expectCounts(f, s, {full.hits, 2 * full.hits, 0, 0}, "hybrid-full, raster reflections");
  s = preset("hybrid-full");
  s.rayScale = 4;
  const Expected quarter = onGrid(p, 4);
  expectCounts(f, s, {quarter.hits, 2 * quarter.hits, quarter.mirror, 0}, "hybrid-full, 1/4 grid");
  s = preset("hybrid-full");
  s.hybridShadows = true;
  s.shadowProofs = ShadowProofs::Cpu;
  FrameStats st;
  gltest::drawFrame(f, s, &st);
  EXPECT_EQ(st.rays.shadow + st.rays.shadowByMap, 2 * full.hits) << "hybrid shadows: every answer a ray or a map's";
  // With the tile shafts first (auto), a shaft also answers points that would need no ray (a secondary hit
  // facing away from the light): at least every ray is answered, and fewer are traced or mapped.
  s.shadowProofs = ShadowProofs::Auto;
  gltest::drawFrame(f, s, &st);
  EXPECT_GT(st.rays.shadowByShaft, 0u);
  EXPECT_LT(st.rays.shadow + st.rays.shadowByMap, 2 * full.hits);
  EXPECT_GE(st.rays.shadow + st.rays.shadowByMap + st.rays.shadowByShaft, 2 * full.hits);
}

TEST(FrameCountsGL, AreaLightsTraceOneRayPerSample) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = countsScene(true);
  auto f = gltest::sceneFrame(*glContext_, Result<Scene>(scene), kW, kH);
  ASSERT_TRUE(f.renderer);
  const Expected full = onGrid(classify(f, scene), 1);
  for (int samples : {1, 4, 9}) {
    FrameSettings s = *presetSettings("hybrid-full", f.base);
    s.reuseRays = false;
    s.lightSamples = samples;
    expectCounts(f, s, {full.hits, full.hits * static_cast<std::uint64_t>(1 + samples), full.mirror, 0},
                 std::to_string(samples) + " samples");
  }
}

}  // namespace
}  // namespace tandem
