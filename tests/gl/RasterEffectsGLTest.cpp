// EffectMode::Raster: shadow maps against the ray-traced light mask, reflection probes against ray-traced
// reflections, environment-mapped refraction against ray-traced refraction where a single interface is
// exact (IOR 1), and each against Off.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "core/Shading.h"
#include "gl/GpuScene.h"
#include "gl/RasterEffects.h"
#include "gl/VisibilityPass.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

// A sphere of radius 0.5 floating over a plane, one direct light of the given type, a camera above. A spot
// cone wider than kMaxSpotMapDeg gets a cube map instead of a 2D one.
Scene sphereOverPlane(LightType type, float spotOuterDeg = 40.0f) {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(8.0f), 8), makeSphere(0.5f, 48, 24)};
  s.materials = {gltest::plainMaterial({0.8f, 0.8f, 0.8f}), gltest::plainMaterial({0.7f, 0.3f, 0.2f})};
  Instance plane, ball;
  ball.mesh = 1;
  ball.material = 1;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  s.instances = {plane, ball};
  Light& l = s.lights[1];
  l.type = type;
  l.intensity = 1.0f;
  if (type == LightType::Spot) {
    l.posW = {1.0f, 4.0f, 1.5f};
    l.dirW = glm::normalize(glm::vec3(0.0f) - l.posW);
    l.innerConeDeg = spotOuterDeg - 10.0f;
    l.outerConeDeg = spotOuterDeg;
  } else if (type == LightType::Directional) {
    l.dirW = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
  } else {
    l.posW = {0.8f, 3.0f, 0.6f};
  }
  s.camera.posW = {0.0f, 4.0f, 4.5f};
  s.camera.targetW = {0.0f, 0.0f, -0.3f};
  return s;
}

int luma(const Image& image, int x, int y) { return image.at(x, y).g; }

struct MaskComparison {
  int compared = 0, shadowed = 0, disagree = 0, disagreeAwayFromEdge = 0;
};

// Plane pixels the light reaches (no mask bit is defined elsewhere): the LightMask views of Raster and
// Ray, thresholded at one half, and whether each disagreement sits within 2 pixels of the ray-traced
// shadow's boundary.
MaskComparison compareMasks(const Scene& scene, const Image& raster, const Image& ray,
                            const std::vector<glm::uvec2>& ids, int w, int h) {
  shading::GpuLight light = shading::packLight(scene.lights[1]);
  MaskComparison c;
  auto rayLit = [&](int x, int y) { return luma(ray, x, y) > 127; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (ids[static_cast<std::size_t>(y) * w + x].x != 1) continue;  // the plane only
      Ray r = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {w, h});
      if (r.dir.y >= 0.0f) continue;
      glm::vec3 p = r.origin + r.dir * (-r.origin.y / r.dir.y);
      if (!shading::tdLightCanReach(light, p, glm::vec3(0.0f, 1.0f, 0.0f))) continue;
      ++c.compared;
      bool lit = rayLit(x, y);
      c.shadowed += lit ? 0 : 1;
      if (lit == (luma(raster, x, y) > 127)) continue;
      ++c.disagree;
      bool nearEdge = false;
      for (int dy = -2; dy <= 2 && !nearEdge; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
          if (rayLit(xx, yy) != lit) {
            nearEdge = true;
            break;
          }
        }
      c.disagreeAwayFromEdge += nearEdge ? 0 : 1;
    }
  return c;
}

void checkShadowMaps(LightType type, const char* name, float spotOuterDeg = 40.0f) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = sphereOverPlane(type, spotOuterDeg);
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(scene).ok());
  const int w = 240, h = 180;
  FrameSettings s = gltest::rasterOnly(w, h);
  s.debugView = DebugView::LightMask;
  s.shadows = EffectMode::Raster;
  FrameStats stats = renderer->render(scene.camera, s);
  EXPECT_EQ(stats.rays.total(), 0u);  // raster shadows trace nothing
  Image raster = renderer->readImage();
  s.shadows = EffectMode::Ray;
  renderer->render(scene.camera, s);
  Image ray = renderer->readImage();
  gltest::savePng(std::string("shadowmap-") + name + "-raster.png", raster);
  gltest::savePng(std::string("shadowmap-") + name + "-ray.png", ray);

  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok());
  EXPECT_TRUE(pass->resize(w, h).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));  // the GL copy is in render space
  std::vector<glm::uvec2> ids;
  pass->readIds(ids);

  MaskComparison c = compareMasks(scene, raster, ray, ids, w, h);
  EXPECT_GT(c.compared, w * h / 4) << name;
  EXPECT_GT(c.shadowed, c.compared / 100) << name << ": the sphere must shadow part of the plane";
  EXPECT_LE(c.disagree, c.compared / 50) << name << ": shadow map vs ray mask on " << c.compared << " plane pixels";
  EXPECT_EQ(c.disagreeAwayFromEdge, 0) << name << ": disagreement away from the shadow's boundary";
  ::testing::Test::RecordProperty("disagree", c.disagree);

  // The final frame: raster shadows darken the shadow, brighten nothing.
  s.debugView = DebugView::Final;
  s.shadows = EffectMode::Off;
  renderer->render(scene.camera, s);
  Image off = renderer->readImage();
  s.shadows = EffectMode::Raster;
  renderer->render(scene.camera, s);
  Image on = renderer->readImage();
  gltest::savePng(std::string("shadowmap-") + name + "-final.png", on);
  int darker = 0, brighter = 0;
  for (std::size_t i = 0; i < off.rgba.size(); i += 4) {
    darker += on.rgba[i + 1] + 2 < off.rgba[i + 1];
    brighter += on.rgba[i + 1] > off.rgba[i + 1] + 1;
  }
  EXPECT_GT(darker, c.shadowed / 2) << name;
  EXPECT_EQ(brighter, 0) << name;
}

TEST(RasterEffectsGLTest, SpotShadowMapMatchesRayMask) { checkShadowMaps(LightType::Spot, "spot"); }
TEST(RasterEffectsGLTest, WideSpotShadowCubeMatchesRayMask) {
  ASSERT_EQ(gl::shadowMapKind(sphereOverPlane(LightType::Spot, 70.0f).lights[1]), gl::ShadowMapKind::Cube);
  checkShadowMaps(LightType::Spot, "wide-spot", 70.0f);
}
TEST(RasterEffectsGLTest, DirectionalShadowMapMatchesRayMask) {
  checkShadowMaps(LightType::Directional, "directional");
}
TEST(RasterEffectsGLTest, PointShadowCubeMatchesRayMask) { checkShadowMaps(LightType::Point, "point"); }

// Every kind of shadow map in one frame: the shade pass is compiled for the scene's light types and map
// kinds (GpuScene's lightKinds, shade.frag's TD_LIGHT_KINDS), light by light. Each light's share of the
// frame must be what a frame with that light alone gets: a type or map kind given to the wrong light, or
// a map slot read for the wrong light, changes the light's share far beyond the sums' rounding.
TEST(RasterEffectsGLTest, MixedLightKindsAddUpLightByLight) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = sphereOverPlane(LightType::Point);
  Light point = scene.lights[1];
  point.intensity = 0.5f;
  Light narrowSpot = sphereOverPlane(LightType::Spot).lights[1];  // 40°: a perspective map
  narrowSpot.intensity = 0.6f;
  Light wideSpot = narrowSpot;  // 70°: a cube map, the second cube of the frame
  wideSpot.posW = {-1.5f, 3.5f, 1.0f};
  wideSpot.dirW = glm::normalize(glm::vec3(0.2f, 1.0f, -0.2f) - wideSpot.posW);
  wideSpot.innerConeDeg = 55.0f;
  wideSpot.outerConeDeg = 70.0f;
  wideSpot.color = {0.4f, 0.6f, 1.0f};
  Light sun = sphereOverPlane(LightType::Directional).lights[1];  // an orthographic map
  sun.intensity = 0.3f;
  const std::vector<Light> lights = {point, narrowSpot, wideSpot, sun};
  const Light ambient = scene.lights[0];

  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  const int w = 240, h = 180;
  FrameSettings s = gltest::rasterOnly(w, h);
  s.shadows = EffectMode::Raster;
  auto frameWith = [&](std::vector<Light> direct) {
    Scene one = scene;
    one.lights = {ambient};
    one.lights.insert(one.lights.end(), direct.begin(), direct.end());
    EXPECT_TRUE(renderer->setScene(one).ok());
    renderer->render(one.camera, s);
    return renderer->readLinear();
  };
  const ImageF all = frameWith(lights);
  gltest::savePng("shadowmap-mixed-kinds.png", renderer->readImage());
  const ImageF none = frameWith({});
  std::vector<ImageF> alone;
  for (const Light& l : lights) alone.push_back(frameWith({l}));

  int mismatched = 0;
  float worst = 0.0f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 sum = none.at(x, y);
      for (const ImageF& one : alone) sum += one.at(x, y) - none.at(x, y);
      const float err = glm::length(all.at(x, y) - sum);
      worst = std::max(worst, err);
      if (err > 1e-4f + 1e-5f * glm::length(sum) && ++mismatched < 8)
        ADD_FAILURE() << "pixel " << x << "," << y << ": all lights " << all.at(x, y).x << " vs the sum of each alone "
                      << sum.x;
    }
  EXPECT_EQ(mismatched, 0) << "worst " << worst;

  // Each light shadows part of the frame (its map is read), so the sum above tests every kind.
  s.shadows = EffectMode::Off;
  for (std::size_t j = 0; j < lights.size(); ++j) {
    const ImageF unshadowed = frameWith({lights[j]});
    int darker = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) darker += alone[j].at(x, y).y + 1e-3f < unshadowed.at(x, y).y;
    EXPECT_GT(darker, w * h / 100) << "light " << j << " casts no visible shadow";
  }
}

// A small object over a checkerboard far larger than it: a probe at its centre sees what the object's
// surface points see, up to a parallax of its radius.
Scene smallObjectOverCheckers(const Material& surface) {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(40.0f), 8), makeSphere(0.2f, 64, 32), makeBox(glm::vec3(0.6f))};
  Material floor = gltest::plainMaterial({0.8f, 0.1f, 0.1f});
  floor.kd2 = {0.9f, 0.8f, 0.1f};
  floor.checkerFrequency = 0.25f;
  Material block = gltest::plainMaterial({0.1f, 0.3f, 0.9f});
  s.materials = {floor, surface, block};
  Instance plane, ball, box;
  ball.mesh = 1;
  ball.material = 1;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.5f, 0.0f));
  box.mesh = 2;
  box.material = 2;
  box.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.5f, -6.0f)) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(4.0f));
  s.instances = {plane, ball, box};
  s.lights[1].posW = {3.0f, 8.0f, 5.0f};
  s.lights[1].castShadows = false;
  s.camera.posW = {0.0f, 1.7f, 1.07f};
  s.camera.targetW = {0.0f, 1.5f, 0.0f};
  s.camera.yFovDeg = 30.0f;
  s.background = {0.3f, 0.5f, 0.8f};
  return s;
}

struct ViewDiff {
  int compared = 0, close = 0, changedFromOff = 0;
};

// Pixels of instance 1 (the small object): `view` of Raster against Ray (within 24/255 per channel),
// and the Final frame of Raster against Off.
ViewDiff compareEffect(const Scene& scene, DebugView view, EffectMode FrameSettings::*effect, const char* name) {
  ViewDiff d;
  std::string contextError_;
  GlContext* context = gltest::sharedContext(contextError_);
  if (!context) return d;
  auto renderer = gltest::makeRenderer(*context);
  if (!renderer || !renderer->setScene(scene).ok()) return d;
  const int w = 160, h = 160;
  FrameSettings s = gltest::rasterOnly(w, h);
  s.maxDepth = 2;  // rays need a second bounce to leave a closed glass object; probes use one either way
  s.debugView = view;
  s.*effect = EffectMode::Raster;
  renderer->render(scene.camera, s);
  Image raster = renderer->readImage();
  s.*effect = EffectMode::Ray;
  FrameStats rayStats = renderer->render(scene.camera, s);
  EXPECT_GT(rayStats.rays.reflection + rayStats.rays.refraction, 0u) << name;
  Image ray = renderer->readImage();
  s.debugView = DebugView::Final;
  s.*effect = EffectMode::Raster;
  renderer->render(scene.camera, s);
  Image finalRaster = renderer->readImage();
  s.*effect = EffectMode::Off;
  renderer->render(scene.camera, s);
  Image off = renderer->readImage();
  gltest::savePng(std::string("probe-") + name + "-raster.png", raster);
  gltest::savePng(std::string("probe-") + name + "-ray.png", ray);
  gltest::savePng(std::string("probe-") + name + "-final.png", finalRaster);

  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  if (!pass) return d;
  EXPECT_TRUE(pass->resize(w, h).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));  // the GL copy is in render space
  std::vector<glm::uvec2> ids;
  pass->readIds(ids);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (ids[static_cast<std::size_t>(y) * w + x].x != 2) continue;
      ++d.compared;
      int worst = 0, changed = 0;
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(int(raster.at(x, y)[c]) - int(ray.at(x, y)[c])));
        changed = std::max(changed, std::abs(int(finalRaster.at(x, y)[c]) - int(off.at(x, y)[c])));
      }
      d.close += worst <= 24 ? 1 : 0;
      d.changedFromOff += changed > 8 ? 1 : 0;
    }
  return d;
}

TEST(RasterEffectsGLTest, ProbeReflectionMatchesRayTracedMirror) {
  TD_REQUIRE_GL_CONTEXT();
  Material mirror = gltest::plainMaterial({0.02f, 0.02f, 0.02f});
  mirror.ka = glm::vec3(0.0f);
  mirror.kr = 0.9f;
  ViewDiff d = compareEffect(smallObjectOverCheckers(mirror), DebugView::Reflection, &FrameSettings::reflections,
                             "mirror");
  ASSERT_GT(d.compared, 3000);
  // Floor, horizon, blue block and sky all appear in the mirror; the probe gets them right except within
  // a parallax of the sphere's radius of their edges, and where a 128² face's texels are magnified.
  EXPECT_GE(d.close, d.compared * 85 / 100) << d.close << " of " << d.compared;
  EXPECT_GE(d.changedFromOff, d.compared * 9 / 10);
}

// With the spatiotemporal filter on, a probe's area lights are drawn with lightSamplesPastFilter samples (at
// least lightSamples): what a probe shows goes past the filter. A filtered frame of one sample draws the
// probes of a filtered frame of four, to the bit, and not those of one sample past the filter. The reflection
// view (the filter still asked for) shows the probes as the filtered frame drew them: the probes follow the
// settings, so nothing changed and none is redrawn. Switching the filter off draws them again with
// lightSamples, as a renderer that never filtered draws them.
TEST(RasterEffectsGLTest, WithTheFilterTheProbesDrawTheLightSamplesPastIt) {
  TD_REQUIRE_GL_CONTEXT();
  Material mirror = gltest::plainMaterial({0.02f, 0.02f, 0.02f});
  mirror.ka = glm::vec3(0.0f);
  mirror.kr = 0.9f;
  Scene scene = smallObjectOverCheckers(mirror);
  scene.lights[1].type = LightType::Sphere;  // its samples' points on the sphere light the floor differently
  scene.lights[1].radius = 2.0f;
  scene.lights[1].posW = {1.0f, 3.0f, 1.0f};
  // The reflection view after a frame with the filter `denoise`, then (`off`) after one more without it.
  auto probes = [&](bool denoise, int samples, int pastFilter, bool off = false) {
    auto renderer = gltest::makeRenderer(*glContext_);
    EXPECT_TRUE(renderer && renderer->setScene(scene).ok());
    if (!renderer) return Image{};
    FrameSettings s = gltest::rasterOnly(160, 160);
    s.reflections = EffectMode::Raster;
    s.maxDepth = 1;
    s.denoise = denoise;
    s.lightSamples = samples;
    s.lightSamplesPastFilter = pastFilter;
    EXPECT_EQ(renderer->render(scene.camera, s).denoised, denoise);
    s.debugView = DebugView::Reflection;
    s.denoise = denoise && !off;
    renderer->render(scene.camera, s);
    return renderer->readImage();
  };
  const Image one = probes(true, 1, 4), four = probes(true, 4, 4), onePast = probes(true, 1, 1);
  gltest::savePng("probe-past-filter-one.png", one);
  gltest::savePng("probe-past-filter-one-past-one.png", onePast);
  auto differing = [](const Image& a, const Image& b) {
    int n = 0;
    for (std::size_t i = 0; i + 3 < std::min(a.rgba.size(), b.rgba.size()); i += 4)
      n += a.rgba[i] != b.rgba[i] || a.rgba[i + 1] != b.rgba[i + 1] || a.rgba[i + 2] != b.rgba[i + 2] ? 1 : 0;
    return n;
  };
  ASSERT_EQ(one.rgba.size(), four.rgba.size());
  EXPECT_EQ(differing(one, four), 0) << "the probes of four samples";
  EXPECT_GT(differing(one, onePast), 500) << "one sample past the filter draws other probes";
  const Image switchedOff = probes(true, 1, 4, true), neverFiltered = probes(false, 1, 4);
  EXPECT_EQ(differing(switchedOff, neverFiltered), 0) << "drawn again with lightSamples";
  EXPECT_GT(differing(switchedOff, one), 500);
}

TEST(RasterEffectsGLTest, ProbeRefractionWithIorNearOneSeesStraightThrough) {
  TD_REQUIRE_GL_CONTEXT();
  // IOR ≈ 1: the refracted ray goes (nearly) straight on and F ≈ 0 but at the very rim, so one interface
  // is as good as two and the ray-traced transmission (through both sides of the sphere) is the probe's
  // lookup along −V, up to parallax.
  Material glass = gltest::plainMaterial({0.0f, 0.0f, 0.0f});
  glass.ka = glm::vec3(0.0f);
  glass.kt = 0.9f;
  glass.ior = 1.001f;
  ViewDiff d = compareEffect(smallObjectOverCheckers(glass), DebugView::Transmission, &FrameSettings::refraction,
                             "ior1");
  ASSERT_GT(d.compared, 3000);
  EXPECT_GE(d.close, d.compared * 85 / 100) << d.close << " of " << d.compared;
  EXPECT_GE(d.changedFromOff, d.compared * 9 / 10);
}

// A see-through sheet (IOR 1, one layer) with a small box close behind its left half: its raster transmission
// is the view behind at each pixel (gl/BehindView.h), so it shows the box where the ray-traced transmission
// does. The probe drawn from the sheet's centre, which it read before, has the box a few centimetres away,
// filling most of the directions behind the sheet.
// smallObjectOverCheckers with a see-through sheet (IOR 1, black, transmitting 0.9) facing the camera as the
// small object.
Scene seeThroughSheetOverCheckers(float roughness, glm::vec3 tint) {
  Material sheet = gltest::plainMaterial({0.0f, 0.0f, 0.0f});
  sheet.ka = glm::vec3(0.0f);
  sheet.kt = 0.9f;
  sheet.ior = 1.0f;
  sheet.roughness = roughness;
  sheet.transmissionTint = tint;
  Scene scene = smallObjectOverCheckers(sheet);
  scene.meshes[1] = makePlane(glm::vec2(0.5f), 1);
  scene.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.5f, 0.0f)) *
                                       glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0));
  return scene;
}

TEST(RasterEffectsGLTest, SeeThroughSheetShowsWhatIsBehindEachPixel) {
  TD_REQUIRE_GL_CONTEXT();
  // Tinted once, not twice: the view behind is peeled past the sheet.
  Scene scene = seeThroughSheetOverCheckers(0.0f, {1.0f, 0.3f, 0.3f});
  scene.meshes.push_back(makeBox(glm::vec3(0.12f)));
  scene.materials.push_back(gltest::plainMaterial({0.9f, 0.9f, 0.1f}));
  Instance behind;
  behind.mesh = 3;
  behind.material = 3;
  behind.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-0.1f, 1.5f, -0.1f));
  scene.instances.push_back(behind);
  ViewDiff d = compareEffect(scene, DebugView::Transmission, &FrameSettings::refraction, "behind");
  ASSERT_GT(d.compared, 3000);
  EXPECT_GE(d.close, d.compared * 97 / 100) << d.close << " of " << d.compared;
  EXPECT_GE(d.changedFromOff, d.compared * 9 / 10);
}

// A rough see-through sheet over the checkerboard: the rays spread what it transmits over the glossy lobe
// (converged over 32 frames), and the raster reads the view behind at the mip level of the lobe's width on
// screen. Both blur the checkers alike, and far from the sharp view behind.
TEST(RasterEffectsGLTest, RoughSeeThroughSheetBlursWhatIsBehindAsTheRaysDo) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = seeThroughSheetOverCheckers(0.3f, glm::vec3(1.0f));
  gltest::SceneFrame f = gltest::sceneFrame(*glContext_, scene, 160, 160);
  FrameSettings s = gltest::rasterOnly(160, 160);
  s.maxDepth = 1;
  s.debugView = DebugView::Transmission;
  s.refraction = EffectMode::Raster;
  const Image raster = gltest::drawFrame(f, s);
  s.refraction = EffectMode::Ray;
  const Image rays = gltest::accumulateFrames(f, s, 32);
  Scene smooth = scene;
  smooth.materials[1].roughness = 0.0f;
  gltest::SceneFrame g = gltest::sceneFrame(*glContext_, smooth, 160, 160);
  s.refraction = EffectMode::Raster;
  const Image sharp = gltest::drawFrame(g, s);
  gltest::savePng("behind-rough-raster.png", raster);
  gltest::savePng("behind-rough-rays.png", rays);
  // The sheet's pixels: where the sharp view differs from black.
  double blurred = 0.0, unblurred = 0.0;
  int n = 0;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 160; ++x) {
      if (sharp.at(x, y) == glm::u8vec4(0, 0, 0, 255)) continue;
      ++n;
      for (int c = 0; c < 3; ++c) {
        blurred += std::abs(int(raster.at(x, y)[c]) - int(rays.at(x, y)[c]));
        unblurred += std::abs(int(sharp.at(x, y)[c]) - int(rays.at(x, y)[c]));
      }
    }
  ASSERT_GT(n, 3000);
  blurred /= 3.0 * n;
  unblurred /= 3.0 * n;
  // 10.8 against 17.5 of 255 a channel here (the lobe's width read as half or twice itself: 11.1, 13.7); what is
  // left is the rays' noise after 32 frames and the mip chain's boxes.
  EXPECT_LT(blurred, 0.7 * unblurred) << blurred << " against " << unblurred << " (per channel, of 255)";
}

TEST(RasterEffectsGLTest, ProbeRefractionBendsAndWeighsByFresnel) {
  TD_REQUIRE_GL_CONTEXT();
  Material glass = gltest::plainMaterial({0.0f, 0.0f, 0.0f});
  glass.ka = glm::vec3(0.0f);
  glass.kt = 0.9f;
  glass.ior = 1.5f;
  Scene scene = smallObjectOverCheckers(glass);
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s = gltest::rasterOnly(160, 160);
  s.maxDepth = 1;
  s.refraction = EffectMode::Raster;
  s.debugView = DebugView::Transmission;
  renderer->render(scene.camera, s);
  ImageF bent = renderer->readLinear();
  scene.materials[1].ior = 1.0f;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  renderer->render(scene.camera, s);
  ImageF straight = renderer->readLinear();
  // At the sphere's centre the view is head-on: F = ((1.5 − 1)/(1.5 + 1))² = 0.04, so wT = 0.9·0.96.
  // Its rim bends the view away from what lies straight behind.
  int differing = 0, total = 0;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 160; ++x) {
      glm::vec3 a = bent.at(x, y), b = straight.at(x, y);
      if (b == glm::vec3(0.0f)) continue;
      ++total;
      differing += glm::length(a - b) > 0.05f ? 1 : 0;
    }
  EXPECT_GT(total, 3000);
  EXPECT_GT(differing, total / 10) << "IOR 1.5 must bend the refracted view";
}

TEST(RasterEffectsGLTest, TogglesChangeTheWhittedScene) {
  TD_REQUIRE_GL_CONTEXT();
  auto scene = loadDefaultScene();
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Camera camera = scene->camera;
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(std::move(*scene)).ok());
  FrameSettings off = *presetSettings("raster");
  off.width = 320;
  off.height = 180;
  off.shadows = off.reflections = off.refraction = EffectMode::Off;
  renderer->render(camera, off);
  Image base = renderer->readImage();
  auto changed = [&](EffectMode FrameSettings::*effect) {
    FrameSettings s = off;
    s.*effect = EffectMode::Raster;
    FrameStats stats = renderer->render(camera, s);
    EXPECT_EQ(stats.rays.total(), 0u);
    Image image = renderer->readImage();
    int n = 0;
    for (std::size_t i = 0; i < base.rgba.size(); i += 4)
      n += std::abs(int(image.rgba[i]) - int(base.rgba[i])) + std::abs(int(image.rgba[i + 1]) - int(base.rgba[i + 1])) > 16;
    return n;
  };
  EXPECT_GT(changed(&FrameSettings::shadows), 1000);
  EXPECT_GT(changed(&FrameSettings::reflections), 1000);
  EXPECT_GT(changed(&FrameSettings::refraction), 1000);
  FrameSettings all = *presetSettings("raster");
  all.width = 320;
  all.height = 180;
  renderer->render(camera, all);
  gltest::savePng("whitted-raster-preset.png", renderer->readImage());
}

}  // namespace
// FrameSettings::probesPerFrame: a new scene's first frame draws only that many probes (the other shows the
// environment for a frame); after an instance moves, a frame re-renders only that many probes (oldest first),
// so a mirror may show the old scene for a frame or two; once every probe has had its turn the frame is the
// exact one, to the bit. A budget of 0 re-renders them all at once.
TEST(RasterEffectsGLTest, ProbesPerFrameCatchUpWithTheExactFrame) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto exact = gltest::whittedRenderer(*glContext_, scene), budgeted = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(exact && budgeted);
  const Camera camera = scene.camera;
  std::uint32_t box = 0;
  while (box < scene.instances.size() && scene.instances[box].name != "matte-box") ++box;
  ASSERT_LT(box, scene.instances.size());
  FrameSettings all = *presetSettings("raster");  // raster reflections and refraction: two probes here
  all.width = 320;
  all.height = 180;
  FrameSettings one = all;
  one.probesPerFrame = 1;
  exact->render(camera, all);
  budgeted->render(camera, one);
  EXPECT_NE(budgeted->readImage().rgba, exact->readImage().rgba) << "a new scene's second probe waits a frame";
  budgeted->render(camera, one);
  EXPECT_EQ(budgeted->readImage().rgba, exact->readImage().rgba) << "and is drawn in the next";

  // The box moves into both spheres' view: the exact frame re-renders both probes.
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(1.6f, 0.3f, 1.2f)) * scene.instances[box].worldFromObject;
  exact->setInstanceTransform(box, moved);
  budgeted->setInstanceTransform(box, moved);
  exact->render(camera, all);
  const Image truth = exact->readImage();
  budgeted->render(camera, one);
  const Image lagging = budgeted->readImage();
  int differing = 0;
  for (std::size_t i = 0; i < truth.rgba.size(); ++i) differing += truth.rgba[i] != lagging.rgba[i];
  EXPECT_GT(differing, 100) << "one probe still shows the box where it was";
  // No further change: the next frame re-renders the other probe and the frame is exact.
  budgeted->render(camera, one);
  EXPECT_EQ(budgeted->readImage().rgba, truth.rgba);
}

}  // namespace tandem

namespace tandem {
namespace {

// A floor, a static box and a dynamic ball, under a point light (cube map), a spot (2D map) and a directional
// light (2D map). The ball stays within the floor's and the box's bounds, so the lights' cameras, fitted to the
// scene's bounds, are those a fresh renderer fits too.
Scene shadowsOfAMovingBall(glm::vec3 ball) {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(8.0f), 8), makeBox(glm::vec3(1.0f, 2.0f, 1.0f)), makeSphere(0.4f, 32, 16)};
  s.materials = {gltest::plainMaterial({0.8f, 0.8f, 0.8f}), gltest::plainMaterial({0.3f, 0.5f, 0.7f}),
                 gltest::plainMaterial({0.7f, 0.3f, 0.2f})};
  Instance floor, box, b;
  box.mesh = 1;
  box.material = 1;
  box.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-1.5f, 1.0f, -1.0f));
  b.mesh = 2;
  b.material = 2;
  b.dynamic = true;
  b.worldFromObject = glm::translate(glm::mat4(1.0f), ball);
  s.instances = {floor, box, b};
  Light point, spot, sun;
  point.type = LightType::Point;
  point.posW = {0.8f + 0.2f * ball.x, 3.0f, 0.6f};
  point.intensity = 0.6f;
  spot.type = LightType::Spot;
  spot.posW = {2.5f, 4.0f, 2.0f};
  spot.dirW = glm::normalize(glm::vec3(0.0f, 0.0f, 0.0f) - spot.posW);
  spot.innerConeDeg = 30.0f;
  spot.outerConeDeg = 40.0f;
  spot.intensity = 0.6f;
  sun.type = LightType::Directional;
  sun.dirW = glm::normalize(glm::vec3(-0.4f, -1.0f, -0.3f));
  sun.intensity = 0.5f;
  s.lights = {s.lights[0], point, spot, sun};
  s.camera.posW = {0.0f, 5.0f, 6.0f};
  s.camera.targetW = {0.0f, 0.0f, 0.0f};
  return s;
}

TEST(RasterEffectsGLTest, ShadowMapsDrawOnlyWhatADynamicInstanceChangesAndEqualAFreshDraw) {
  TD_REQUIRE_GL_CONTEXT();
  const glm::vec3 path[] = {{0.5f, 0.6f, 0.5f}, {1.0f, 0.6f, 0.3f}, {1.6f, 0.8f, -0.4f}, {-0.2f, 1.2f, 1.8f}};
  FrameSettings s = *presetSettings("raster");
  s.width = 160;
  s.height = 90;
  s.reflections = s.refraction = EffectMode::Off;
  auto moving = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(moving);
  ASSERT_TRUE(moving->setScene(shadowsOfAMovingBall(path[0])).ok());
  for (const glm::vec3& p : path) {
    SCOPED_TRACE(testing::Message() << "ball at " << p.x << " " << p.y << " " << p.z);
    moving->setInstanceTransform(2, glm::translate(glm::mat4(1.0f), p));
    // The point light moves with the ball (as the game's orbiting lights do): its cube is drawn whole.
    Light light = moving->scene().lights[1];
    light.posW = shadowsOfAMovingBall(p).lights[1].posW;
    moving->setLight(1, light);
    const FrameStats st = moving->render(moving->scene().camera, s);
    ASSERT_TRUE(st.error.empty()) << st.error;
    const Image kept = moving->readImage();
    auto fresh = gltest::makeRenderer(*glContext_);
    ASSERT_TRUE(fresh);
    ASSERT_TRUE(fresh->setScene(shadowsOfAMovingBall(p)).ok());
    fresh->render(fresh->scene().camera, s);
    const Image drawn = fresh->readImage();
    ASSERT_EQ(kept.rgba.size(), drawn.rgba.size());
    int differing = 0;
    for (std::size_t i = 0; i < kept.rgba.size(); ++i) differing += kept.rgba[i] != drawn.rgba[i];
    EXPECT_EQ(differing, 0) << "the shadow maps updated for the moved ball are not those drawn from scratch";
  }

  // The maps themselves: a move redraws the faces that see where the ball was or is, not the others.
  Scene scene = shadowsOfAMovingBall(path[0]);
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok());
  gl::ShadowMaps maps;
  auto update = [&](bool everything) {
    const std::vector<gl::Bounds> bounds = gl::instanceBounds(scene, gl::meshBounds(scene), gpu.anchor());
    gpu.updateInstances(scene, 0.0f, 0.5f);
    maps.update(scene, gpu, *pass, bounds, gl::instanceTransforms(scene, gpu.anchor()), 1, everything);
  };
  update(false);
  EXPECT_EQ(maps.facesDrawn(), maps.faceCount()) << "the first update draws every face";
  EXPECT_EQ(maps.faceCount(), 2 + 6);
  update(false);
  EXPECT_EQ(maps.facesDrawn(), 0) << "nothing moved";
  scene.instances[2].worldFromObject = glm::translate(glm::mat4(1.0f), path[1]);
  update(false);
  EXPECT_GT(maps.facesDrawn(), 0);
  EXPECT_LT(maps.facesDrawn(), maps.faceCount()) << "a small move redrew faces that cannot see the ball";
  update(true);
  EXPECT_EQ(maps.facesDrawn(), maps.faceCount());
  // A light that changes redraws its own maps whole (the point light's cube: six faces), not the others';
  // a static instance that moves, every map.
  scene.lights[1].posW.x += 0.1f;
  update(false);
  EXPECT_EQ(maps.facesDrawn(), 6);
  scene.instances[1].worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-1.4f, 1.0f, -1.0f));
  update(false);
  EXPECT_EQ(maps.facesDrawn(), maps.faceCount());
}

}  // namespace
}  // namespace tandem

namespace tandem {
namespace {

// A shadow map's or a probe's face draws only the instances it may see (gl::seenBy): the same ids and depth
// to the bit as drawing them all, and in a scene spread around the eye most faces leave some out.
TEST(RasterEffectsGLTest, CulledFaceDrawsEqualWholeSceneDrawsToTheBit) {
  TD_REQUIRE_GL_CONTEXT();
  auto loaded = loadDefaultScene();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded;
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok());
  const std::vector<gl::Bounds> bounds = gl::instanceBounds(scene, gl::meshBounds(scene), gpu.anchor());
  constexpr int kSize = 128;
  gl::Texture ids = gl::createTexture2D("test ids", gl::kChannelIds.internal, kSize, kSize);
  gl::Texture depth = gl::createTexture2D("test depth", gl::kChannelDepth.internal, kSize, kSize);
  gl::Framebuffer fbo = gl::createFramebuffer("test face");
  glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, ids.id(), 0);
  glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth.id(), 0);
  glNamedFramebufferDrawBuffer(fbo.id(), GL_COLOR_ATTACHMENT0);
  auto read = [&](std::vector<std::uint32_t>& outIds, std::vector<float>& outDepth) {
    outIds.assign(2 * kSize * kSize, 0);
    outDepth.assign(kSize * kSize, 0.0f);
    glGetTextureImage(ids.id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(outIds.size() * 4), outIds.data());
    glGetTextureImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, static_cast<GLsizei>(outDepth.size() * 4),
                      outDepth.data());
  };
  int left = 0, drawnPixels = 0;
  // From the middle of the scene's objects (render space, as the bounds): every face sees some of them.
  gl::Bounds world;
  for (const gl::Bounds& b : bounds) world.add(b);
  const glm::vec3 eye = 0.5f * (world.lo + world.hi) + glm::vec3(0.0f, 0.3f, 0.0f);
  std::vector<std::uint8_t> seen;
  for (int face = 0; face < 6; ++face) {
    SCOPED_TRACE(face);
    const Camera c = gl::cubeFaceCamera(eye, face, 1e-3f, std::numeric_limits<float>::infinity());
    gl::seenBy(c.clipFromView(glm::ivec2(kSize)) * c.viewFromWorld(), bounds, seen);
    for (std::uint8_t s : seen) left += s ? 0 : 1;
    std::vector<std::uint32_t> idsAll, idsCulled;
    std::vector<float> depthAll, depthCulled;
    pass->renderInto(fbo.id(), kSize, kSize, gpu, c);
    read(idsAll, depthAll);
    pass->renderInto(fbo.id(), kSize, kSize, gpu, c, std::nullopt, gl::GpuScene::Instances::All, true, &seen);
    read(idsCulled, depthCulled);
    EXPECT_EQ(idsCulled, idsAll);
    EXPECT_EQ(std::memcmp(depthCulled.data(), depthAll.data(), depthAll.size() * sizeof(float)), 0);
    for (std::size_t i = 0; i < idsAll.size(); i += 2) drawnPixels += idsAll[i] != 0 ? 1 : 0;
  }
  EXPECT_GT(left, static_cast<int>(scene.instances.size())) << "the faces left nothing out: the test proves nothing";
  EXPECT_GT(drawnPixels, 6 * kSize * kSize / 4) << "the faces see little of the scene";
}

// FrameSettings::probeSize: a change re-renders every probe at the new size at once, the frame that of a
// fresh renderer at that size; a smaller probe is a blurrier mirror (the frames differ).
TEST(RasterEffectsGLTest, ProbeSizeIsFollowedAtOnce) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto changing = gltest::whittedRenderer(*glContext_, scene), fresh = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(changing && fresh);
  FrameSettings small = *presetSettings("raster");
  small.width = 320;
  small.height = 180;
  small.probeSize = 32;
  FrameSettings large = small;
  large.probeSize = 256;
  changing->render(scene.camera, small);
  const Image blurry = changing->readImage();
  changing->render(scene.camera, large);
  fresh->render(scene.camera, large);
  const Image sharp = fresh->readImage();
  EXPECT_EQ(changing->readImage().rgba, sharp.rgba);
  int differing = 0;
  for (std::size_t i = 0; i < sharp.rgba.size(); ++i) differing += sharp.rgba[i] != blurry.rgba[i];
  EXPECT_GT(differing, 500) << "32² and 256² probes gave the same mirrors";
  FrameSettings odd = small;
  odd.probeSize = 100;
  EXPECT_EQ(odd.resolved().probeSize, 64);
  odd.probeSize = 4096;
  EXPECT_EQ(odd.resolved().probeSize, 512);
}

}  // namespace
}  // namespace tandem

namespace tandem {
namespace {

// n mirror spheres on a grid 2.5 apart (and a floor that reflects nothing).
Scene mirrorSpheres(int n) {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(200.0f), 1), makeSphere(1.0f, 12, 6)};
  Material mirror = gltest::plainMaterial(glm::vec3(0.2f));
  mirror.kr = 0.6f;
  s.materials = {gltest::plainMaterial(glm::vec3(0.7f)), mirror};
  s.instances = {Instance{}};
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  for (int k = 0; k < n; ++k) {
    Instance ball;
    ball.mesh = 1;
    ball.material = 1;
    ball.worldFromObject =
        glm::translate(glm::mat4(1.0f), glm::vec3(2.5f * static_cast<float>(k % side), 1.0f, 2.5f * static_cast<float>(k / side)));
    s.instances.push_back(ball);
  }
  s.camera.posW = {0.5f * 2.5f * static_cast<float>(side), 3.0f * static_cast<float>(side), 2.5f * static_cast<float>(side) + 4.0f};
  s.camera.targetW = {0.5f * 2.5f * static_cast<float>(side), 0.0f, 0.5f * 2.5f * static_cast<float>(side)};
  return s;
}

// FrameSettings::probeLimit: 10, 100 and 1000 mirror spheres get min(n, limit) probes; every sphere reads one,
// the nearest probe's (which is its own where it has one), and the probes are spread over the grid (no sphere
// farther from its probe than the grid's diagonal over the square root of the limit, about what k evenly
// spread points leave), the floor none. At or under the limit every instance keeps its own, as before.
TEST(ReflectionProbeLayout, ALimitedNumberOfProbesSpreadOverTheScene) {
  for (int n : {10, 100, 1000}) {
    SCOPED_TRACE("spheres " + std::to_string(n));
    const Scene scene = mirrorSpheres(n);
    for (int limit : {1, 16, 32, 2000}) {
      SCOPED_TRACE("limit " + std::to_string(limit));
      const gl::ProbeLayout layout = gl::probeLayout(scene, limit);
      ASSERT_EQ(layout.probes.size(), static_cast<std::size_t>(std::min(n, limit)));
      ASSERT_EQ(layout.slotOf.size(), scene.instances.size());
      EXPECT_EQ(layout.slotOf[0], -1) << "the floor reflects nothing";
      auto centre = [&](std::uint32_t i) { return glm::vec3(scene.instances[i].worldFromObject[3]); };
      const float side = std::ceil(std::sqrt(static_cast<float>(n)));
      const float spread = 2.5f * side * std::sqrt(2.0f) / std::sqrt(static_cast<float>(std::min(n, limit)));
      for (std::uint32_t i = 1; i < scene.instances.size(); ++i) {
        const std::int32_t slot = layout.slotOf[i];
        ASSERT_GE(slot, 0);
        ASSERT_LT(static_cast<std::size_t>(slot), layout.probes.size());
        const float mine = glm::distance(centre(i), centre(layout.probes[static_cast<std::size_t>(slot)]));
        for (std::uint32_t p : layout.probes) EXPECT_LE(mine, glm::distance(centre(i), centre(p)) + 1e-4f);
        EXPECT_LE(mine, spread + 1e-3f);
      }
      for (std::size_t slot = 0; slot < layout.probes.size(); ++slot)
        EXPECT_EQ(layout.slotOf[layout.probes[slot]], static_cast<std::int32_t>(slot)) << "a probe's own object";
    }
  }
}

// The raster frame draws the layout's probes, no more: 100 mirror spheres under a limit of 4 draw 4 (FrameStats
// probesDrawn and probes), and the spheres still reflect (the frame is not the one without reflections).
TEST(RasterEffectsGLTest, AFrameDrawsNoMoreProbesThanTheLimit) {
  TD_REQUIRE_GL_CONTEXT();
  FrameSettings s = *presetSettings("raster");
  s.width = 160;
  s.height = 90;
  s.probeSize = 16;
  for (int limit : {4, 200}) {
    SCOPED_TRACE("limit " + std::to_string(limit));
    s.probeLimit = limit;
    gltest::SceneFrame f = gltest::sceneFrame(*glContext_, mirrorSpheres(100), s.width, s.height);
    FrameStats st;
    gltest::drawFrame(f, s, &st);
    EXPECT_EQ(st.probesDrawn, std::min(100, limit));
    EXPECT_EQ(st.probes, std::min(100, limit));
    FrameSettings off = s;
    off.reflections = EffectMode::Off;
    const Image reflected = f.renderer->readImage(), plain = gltest::drawFrame(f, off);
    int differing = 0;
    for (std::size_t i = 0; i < plain.rgba.size(); ++i) differing += plain.rgba[i] != reflected.rgba[i] ? 1 : 0;
    EXPECT_GT(differing, 1000) << "no reflections";
    gltest::drawFrame(f, s, &st);
    gltest::drawFrame(f, s, &st);  // nothing changed: none drawn again
    EXPECT_EQ(st.probesDrawn, 0);
  }
}

}  // namespace
}  // namespace tandem
