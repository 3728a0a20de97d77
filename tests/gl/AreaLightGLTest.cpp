// Area lights in the frame (docs/area-lights.md): the hybrid frame draws each pixel's light samples in the
// shade pass from the same seeds as the ray pass, so it equals the reference at those samples in every
// shading model; accumulation converges to the converged reference; a point-sized sphere is the point
// light; the same seed gives the same image on any thread count; the raster fallback softens its shadows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/GlTestUtil.h"
#include "tandem/ImageMetrics.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 90;

// A floor, a box and a ball under a rect, a disk and a sphere light, with physical (1/d²) attenuation.
std::string sceneText(const std::string& lights) {
  return R"({
    "name": "area-lights",
    "meshes": {
      "floor": { "primitive": "plane", "size": [12, 12] },
      "box": { "primitive": "box", "size": 1 },
      "ball": { "primitive": "sphere", "radius": 0.6, "segments": 32, "rings": 16 }
    },
    "materials": {
      "floor": { "ka": 0.1, "kd": [0.7, 0.7, 0.65], "ks": 0.2, "ns": 30, "checker": { "color2": [0.3, 0.35, 0.5], "frequency": 1 } },
      "red": { "ka": 0.1, "kd": [0.7, 0.15, 0.1], "ks": 0.5, "ns": 60 },
      "blue": { "ka": 0.1, "kd": [0.15, 0.3, 0.8], "ks": 0.3, "ns": 20 }
    },
    "lights": [ { "type": "ambient", "intensity": 0.1 }, )" +
         lights + R"( ],
    "instances": [
      { "mesh": "floor", "material": "floor" },
      { "mesh": "box", "material": "red", "transform": { "translate": [-0.9, 0.5, 0], "rotate": [0, 25, 0] } },
      { "mesh": "ball", "material": "blue", "transform": { "translate": [1.0, 0.9, 0.4] } }
    ],
    "camera": { "position": [0, 3.2, 5.5], "target": [0, 0.4, 0], "fov": 45 }
  })";
}

const char* kAreaLights = R"(
      { "type": "rect", "position": [-1.5, 3.5, 1], "direction": [0.3, -1, -0.2], "size": [1.5, 0.8],
        "intensity": 9, "attenuation": [0, 0, 1] },
      { "type": "disk", "position": [2.5, 3, -1], "direction": [-0.5, -1, 0.3], "radius": 0.5,
        "intensity": 6, "color": [1, 0.8, 0.6], "attenuation": [0, 0, 1] },
      { "type": "sphere", "position": [0.5, 2.6, 2.2], "radius": 0.35, "intensity": 4,
        "color": [0.6, 0.8, 1], "attenuation": [0, 0, 1] })";

using Frame = gltest::SceneFrame;

Frame load(GlContext& context, const std::string& lights = kAreaLights, int threads = 0) {
  return gltest::sceneFrame(context, parseSceneJson(sceneText(lights), "area-lights", "."), kW, kH, threads);
}

FrameSettings preset(const Frame& f, const char* name, int lightSamples = 4) {
  FrameSettings s = *presetSettings(name, f.base);
  s.referenceSpp = 1;
  s.lightSamples = lightSamples;
  return s;
}

using gltest::flipMean;

TEST(AreaLight, TheHybridFrameIsTheReferenceAtItsSamples) {
  // The shade pass draws each pixel's samples from the seed the ray pass traced them with, and sums the
  // ones whose shadow rays got through: with full-resolution rays it is the reference's estimate, in every
  // shading model (the area loop of shade.frag against rt::shadeLocal's).
  TD_REQUIRE_GL_CONTEXT();
  Frame f = load(*glContext_);
  // Toon outlines are the raster's alone (the reference draws none): measured against the same scene under
  // point lights at the area lights' centres.
  Frame points = load(*glContext_, R"(
      { "type": "point", "position": [-1.5, 3.5, 1], "intensity": 9, "attenuation": [0, 0, 1] },
      { "type": "point", "position": [2.5, 3, -1], "intensity": 6, "attenuation": [0, 0, 1] },
      { "type": "point", "position": [0.5, 2.6, 2.2], "intensity": 4, "attenuation": [0, 0, 1] })");
  for (std::optional<ShadingModel> model :
       {std::optional<ShadingModel>(), std::optional<ShadingModel>(ShadingModel::Gouraud),
        std::optional<ShadingModel>(ShadingModel::Flat), std::optional<ShadingModel>(ShadingModel::Toon)}) {
    FrameSettings hybrid = preset(f, "hybrid-full");
    FrameSettings reference = preset(f, "reference");
    hybrid.shadingOverride = reference.shadingOverride = model;
    FrameStats st;
    const double e = flipMean(gltest::drawFrame(f, hybrid, &st), gltest::drawFrame(f, reference));
    const double baseline = flipMean(gltest::drawFrame(points, hybrid), gltest::drawFrame(points, reference));
    std::printf("model %d: FLIP hybrid-full vs reference, 4 light samples: %.5f (point lights: %.5f; %llu shadow rays)\n",
                model ? static_cast<int>(*model) : -1, e, baseline, static_cast<unsigned long long>(st.rays.shadow));
    EXPECT_LT(e, baseline + 0.003);
    EXPECT_GT(st.rays.shadow, static_cast<std::uint64_t>(kW * kH)) << "several shadow rays per area light";
  }
  // Other samples (another sample index) are another estimate: the comparison above is not vacuous.
  Camera next = f.camera;
  next.sampleIndex = 1;
  const Image other = [&] {
    FrameStats st = f.renderer->render(next, preset(f, "reference"));
    EXPECT_TRUE(st.error.empty());
    return f.renderer->readImage();
  }();
  EXPECT_GT(flipMean(gltest::drawFrame(f, preset(f, "hybrid-full")), other), 0.006);
}

TEST(AreaLight, AccumulatedFramesConvergeToTheReference) {
  TD_REQUIRE_GL_CONTEXT();
  Frame f = load(*glContext_);
  FrameSettings truthSettings = preset(f, "reference", 16);
  truthSettings.referenceSpp = 2;
  const Image truth = gltest::accumulateFrames(f, truthSettings, 8);  // 4 × 16 × 8 = 512 samples per light and pixel
  const double one = flipMean(gltest::drawFrame(f, preset(f, "hybrid-full")), truth);
  const double sixteen = flipMean(gltest::accumulateFrames(f, preset(f, "hybrid-full"), 16), truth);
  const double oneSampleSixteenFrames = flipMean(gltest::accumulateFrames(f, preset(f, "hybrid-full", 1), 16), truth);
  const double referenceSixteen = flipMean(gltest::accumulateFrames(f, preset(f, "reference"), 16), truth);
  std::printf("FLIP vs converged reference: 1 frame x 4 samples %.5f, 16 frames x 4 %.5f, 16 frames x 1 %.5f, "
              "reference 16 frames x 4 %.5f\n",
              one, sixteen, oneSampleSixteenFrames, referenceSixteen);
  EXPECT_LT(sixteen, 0.5 * one) << "new light samples every frame: the noise must go";
  EXPECT_LT(sixteen, 0.03);
  EXPECT_LT(oneSampleSixteenFrames, one);
  // The hybrid accumulation and the reference's are the same estimator (up to raster vs ray primary hits).
  EXPECT_NEAR(sixteen, referenceSixteen, 0.005);
}

TEST(AreaLight, APointSizedSphereIsThePointLight) {
  TD_REQUIRE_GL_CONTEXT();
  const char* tinySphere = R"({ "type": "sphere", "position": [-1, 3.5, 1.5], "radius": 1e-5, "intensity": 9,
                                "attenuation": [0, 0, 1] })";
  const char* point = R"({ "type": "point", "position": [-1, 3.5, 1.5], "intensity": 9, "attenuation": [0, 0, 1] })";
  Frame sphere = load(*glContext_, tinySphere), pointLit = load(*glContext_, point);
  for (const char* name : {"hybrid-full", "reference", "raster"}) {
    const double e = flipMean(gltest::drawFrame(sphere, preset(sphere, name)), gltest::drawFrame(pointLit, preset(pointLit, name)));
    std::printf("%s: FLIP sphere radius 1e-5 vs point light %.6f\n", name, e);
    EXPECT_LT(e, 0.001) << name;
  }
}

TEST(AreaLight, TheSameSeedGivesTheSameImageOnAnyThreadCount) {
  TD_REQUIRE_GL_CONTEXT();
  Frame one = load(*glContext_, kAreaLights, 1), two = load(*glContext_, kAreaLights, 2);
  for (const char* name : {"hybrid-full", "hybrid-fast", "reference"}) gltest::expectSameFrame(one, two, preset(one, name), name);
}

TEST(AreaLight, EveryPresetStaysNearTheReference) {
  // The coarser ray grid scales each pixel's samples by the visible fraction around it, and raster shadows
  // stand in with soft shadow maps: both approximate, neither far off.
  TD_REQUIRE_GL_CONTEXT();
  Frame f = load(*glContext_);
  FrameSettings truthSettings = preset(f, "reference", 16);
  truthSettings.referenceSpp = 2;
  const Image truth = gltest::accumulateFrames(f, truthSettings, 4);
  for (const char* name : {"hybrid-fast", "raster", "hybrid-full"}) {
    const double e = flipMean(gltest::accumulateFrames(f, preset(f, name), 8), truth);
    std::printf("%s, 8 frames: FLIP vs converged reference %.5f\n", name, e);
    EXPECT_LT(e, 0.035) << name;
  }
}

TEST(AreaLight, AFrameKeepingLastFramesRaysIsTheFrameWithout) {
  // With the camera still and the box moved, the frame keeps the shadow answers that cannot have changed
  // (rt/RayReuse.h), an area light's per sample (the same point draws the same samples): the frame still
  // equals one drawn from scratch.
  TD_REQUIRE_GL_CONTEXT();
  Frame kept = load(*glContext_), fresh = load(*glContext_);
  FrameSettings keeping = preset(kept, "hybrid-full");
  keeping.reuseRays = true;
  FrameSettings scratch = keeping;
  scratch.reuseRays = false;
  gltest::drawFrame(kept, keeping);
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(-0.6f, 0.5f, 0.3f));
  kept.renderer->setInstanceTransform(1, moved);
  fresh.renderer->setInstanceTransform(1, moved);
  FrameStats st;
  const Image a = gltest::drawFrame(kept, keeping, &st), b = gltest::drawFrame(fresh, scratch);
  EXPECT_GT(st.rays.shadowKept, static_cast<std::uint64_t>(kW * kH)) << "the samples clear of the box keep their answers";
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  EXPECT_TRUE(a.rgba == b.rgba);
}

TEST(AreaLight, LightsChangingTypeKeepNoOtherLightsSamples) {
  // An area light's samples sit in the plane of its rank among the area lights: when two lights change type
  // at once, the count stays and the rank of an unchanged area light moves, so the kept frame's planes would
  // belong to other lights. Reuse then keeps no area answers, and the frame equals one drawn from scratch.
  TD_REQUIRE_GL_CONTEXT();
  const char* lights = R"(
      { "type": "rect", "position": [-1.5, 3.5, 1], "direction": [0.3, -1, -0.2], "size": [1.5, 0.8],
        "intensity": 9, "attenuation": [0, 0, 1] },
      { "type": "point", "position": [2.5, 3, -1], "intensity": 3, "attenuation": [0, 0, 1] },
      { "type": "sphere", "position": [0.5, 2.6, 2.2], "radius": 0.35, "intensity": 4, "attenuation": [0, 0, 1] },
      { "type": "point", "position": [-2, 2, 2], "intensity": 2, "attenuation": [0, 0, 1] })";
  Frame kept = load(*glContext_, lights), fresh = load(*glContext_, lights);
  FrameSettings keeping = preset(kept, "hybrid-full");
  keeping.reuseRays = true;
  FrameSettings scratch = keeping;
  scratch.reuseRays = false;
  gltest::drawFrame(kept, keeping);
  // Scene lights: 0 ambient, 1 rect, 2 point, 3 sphere, 4 point. The rect becomes a point light and the last
  // point a disk: still two area lights, the sphere's rank 1 → 0.
  for (Frame* f : {&kept, &fresh}) {
    Light a = f->renderer->scene().lights[1], d = f->renderer->scene().lights[4];
    a.type = LightType::Point;
    d.type = LightType::Disk;
    d.dirW = glm::vec3(0.5f, -1.0f, -0.5f);
    d.radius = 0.4f;
    f->renderer->setLight(1, a);
    f->renderer->setLight(4, d);
  }
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(-0.6f, 0.5f, 0.3f));
  kept.renderer->setInstanceTransform(1, moved);
  fresh.renderer->setInstanceTransform(1, moved);
  const Image a = gltest::drawFrame(kept, keeping), b = gltest::drawFrame(fresh, scratch);
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  EXPECT_TRUE(a.rgba == b.rgba);
}

TEST(AreaLight, SetLightRefusesABadShape) {
  TD_REQUIRE_GL_CONTEXT();
  Frame f = load(*glContext_);
  const Image before = gltest::drawFrame(f, preset(f, "hybrid-full"));
  for (float radius : {std::nanf(""), -1.0f, std::numeric_limits<float>::infinity()}) {
    Light l = f.renderer->scene().lights[3];  // the sphere
    l.radius = radius;
    f.renderer->setLight(3, l);
    EXPECT_EQ(f.renderer->scene().lights[3].radius, 0.35f) << radius;
  }
  Light rect = f.renderer->scene().lights[1];
  rect.dirW = glm::vec3(0.0f);
  f.renderer->setLight(1, rect);
  EXPECT_NE(f.renderer->scene().lights[1].dirW, glm::vec3(0.0f));
  EXPECT_TRUE(gltest::drawFrame(f, preset(f, "hybrid-full")).rgba == before.rgba);
}

}  // namespace
}  // namespace tandem
