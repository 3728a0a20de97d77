// Which rays a frame traces, decided from the scene and the settings: the decisions users found wrong.
//  - Glass reflects by Fresnel (wR = kr + kt·F) even when no material has kr > 0, and totally reflects
//    under TIR: the frame must trace those reflection rays.
//  - Raster shadows cover the primary points only; secondary hits have no shadow map and keep their
//    shadow rays.
#include <functional>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "GlTestUtil.h"
#include "core/Shading.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

Scene whittedWithoutMirrors() {
  auto s = loadDefaultScene();
  EXPECT_TRUE(s) << s.error().message;
  Scene scene = std::move(*s);
  for (Material& m : scene.materials) m.kr = 0.0f;  // the mirror stays as a dull sphere, the glass has no kr
  return scene;
}

TEST(FrameDecisions, GlassWithoutKrTracesItsFresnelReflections) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = whittedWithoutMirrors();
  const Camera camera = scene.camera;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings hybrid = *presetSettings("hybrid-full");
  hybrid.width = 320;
  hybrid.height = 180;
  FrameStats h = renderer->render(camera, hybrid);
  // The reference with the same depth and cut-off: it decides nothing by material, so it is the count a
  // correct decision gives (the primary hits differ only where raster and rays disagree at silhouettes).
  FrameSettings reference = *presetSettings("reference");
  reference.width = 320;
  reference.height = 180;
  reference.maxDepth = hybrid.maxDepth;
  reference.minContribution = hybrid.minContribution;
  FrameStats r = renderer->render(camera, reference);
  ASSERT_GT(r.rays.reflection, 3000u) << "the reference reflects off the glass";
  EXPECT_NEAR(double(h.rays.reflection), double(r.rays.reflection), 0.03 * double(r.rays.reflection));
}

TEST(FrameDecisions, TotalInternalReflectionIsTracedNotBlack) {
  // A slab of IOR 0.5 in air: seen obliquely, light entering it is totally reflected at its first face.
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = gltest::boxScene();
  scene.meshes = {makePlane({40.0f, 40.0f}, 1), makeBox({3.0f, 0.2f, 3.0f})};
  Material floor = gltest::plainMaterial({0.8f, 0.6f, 0.2f});
  Material slab;
  slab.ka = slab.kd = glm::vec3(0.0f);
  slab.ks = glm::vec3(0.0f);
  slab.kr = 0.0f;
  slab.kt = 1.0f;
  slab.ior = 0.5f;
  scene.materials = {floor, slab};
  Instance f;
  f.mesh = 0;
  f.material = 0;
  Instance b;
  b.mesh = 1;
  b.material = 1;
  b.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  scene.instances = {f, b};
  scene.camera.posW = {0.0f, 2.2f, 5.0f};
  scene.camera.targetW = {0.0f, 1.0f, 0.0f};
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings hybrid = *presetSettings("hybrid-full");
  hybrid.width = 160;
  hybrid.height = 120;
  FrameStats h = renderer->render(scene.camera, hybrid);
  const Image hi = renderer->readImage();
  FrameSettings reference = *presetSettings("reference");
  reference.width = 160;
  reference.height = 120;
  renderer->render(scene.camera, reference);
  const Image ri = renderer->readImage();
  gltest::savePng("tir-slab-hybrid.png", hi);
  gltest::savePng("tir-slab-reference.png", ri);
  EXPECT_GT(h.rays.reflection, 0u);
  int blackOnlyInHybrid = 0, slabPixels = 0;
  for (int y = 0; y < hi.height; ++y)
    for (int x = 0; x < hi.width; ++x) {
      const glm::u8vec4 a = hi.at(x, y), c = ri.at(x, y);
      const int la = a.r + a.g + a.b, lc = c.r + c.g + c.b;
      slabPixels += lc > 0;
      if (la < 6 && lc > 30) ++blackOnlyInHybrid;
    }
  // Before reflection rays followed the weights, most of the slab rendered black.
  EXPECT_LT(blackOnlyInHybrid, slabPixels / 200) << "pixels black in the hybrid frame but lit in the reference";
}

TEST(FrameDecisions, RasterShadowsKeepShadowRaysAtSecondaryHits) {
  // The mirror sphere of the Whitted scene reflects the floor with the other spheres' shadows on it: with
  // raster shadows (primary points only) the reflected light must be what it is with ray shadows.
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  auto scene = loadDefaultScene();
  ASSERT_TRUE(scene);
  const Camera camera = scene->camera;
  ASSERT_TRUE(renderer->setScene(*scene).ok());
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = 240;
  s.height = 135;
  s.refraction = EffectMode::Off;
  s.debugView = DebugView::Reflection;
  s.shadows = EffectMode::Ray;
  FrameStats ray = renderer->render(camera, s);
  const Image withRays = renderer->readImage();
  s.shadows = EffectMode::Raster;
  FrameStats raster = renderer->render(camera, s);
  const Image withMaps = renderer->readImage();
  s.shadows = EffectMode::Off;
  renderer->render(camera, s);
  const Image without = renderer->readImage();
  EXPECT_GT(raster.rays.shadow, 0u) << "secondary hits trace shadow rays under raster shadows";
  EXPECT_LT(raster.rays.shadow, ray.rays.shadow) << "the primary points' shadows come from the maps";
  EXPECT_EQ(withMaps.rgba, withRays.rgba) << "the reflected light is shadowed the same way";
  EXPECT_NE(without.rgba, withRays.rgba) << "the test scene has shadows in its reflections";
}

// A game that turns away from everything reflective must not stall on a shader compile (up to a second
// on a software GL): the shade variant follows what the frame's plan can produce, and the ray results a
// frame left empty are a uniform. Turning back shows the first frame again, exactly.
TEST(FrameDecisions, FramesWhoseRaysLeaveChannelsEmptyCompileNoShader) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = 160;
  s.height = 90;
  const Camera towards = scene.camera;
  Camera away = scene.camera;  // straight up from the camera: sky only
  away.targetW = away.posW + glm::vec3(0.0f, 1.0f, 0.0f);
  away.upW = glm::vec3(0.0f, 0.0f, -1.0f);

  const FrameStats first = renderer->render(towards, s);
  ASSERT_TRUE(first.error.empty()) << first.error;
  const Image firstImage = renderer->readImage();
  ASSERT_GT(first.rays.shadow, 0u);
  ASSERT_GT(first.rays.reflection, 0u);
  ASSERT_GT(first.rays.refraction, 0u);
  EXPECT_GT(first.shaderCompiles, 0) << "a new renderer's first frame compiles its variants";

  const FrameStats up = renderer->render(away, s);
  EXPECT_EQ(up.rays.total(), 0u) << "the view was meant to hold nothing but sky";
  EXPECT_EQ(up.shaderCompiles, 0);

  const FrameStats back = renderer->render(towards, s);
  EXPECT_EQ(back.shaderCompiles, 0);
  EXPECT_EQ(back.rays.total(), first.rays.total());
  const Image backImage = renderer->readImage();
  EXPECT_EQ(backImage.rgba, firstImage.rgba);

  // Another view of the same plan compiles nothing either; another preset may.
  Camera side = scene.camera;
  side.posW += glm::vec3(1.5f, 0.0f, 0.0f);
  EXPECT_EQ(renderer->render(side, s).shaderCompiles, 0);
}

// The shade variant is compiled for each light's type and, with raster shadows, its map kind: a spot
// whose cone widens past 60° (a cube map instead of a 2D one) compiles its variants once under raster
// shadows, and nothing under ray-traced shadows, where the map kind does not matter. The frame after the
// change equals a renderer that had the wide cone from the start.
TEST(FrameDecisions, ASpotWideningPastTheMapLimitCompilesOnlyWhereMapsAreUsed) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const std::uint32_t spot = 2;  // whitted.json: sky (ambient), key (point), spot
  ASSERT_EQ(scene.lights[spot].type, LightType::Spot);
  Light wide = scene.lights[spot];
  wide.innerConeDeg = 62.0f;
  wide.outerConeDeg = 70.0f;
  for (const char* preset : {"hybrid-full", "raster"}) {
    SCOPED_TRACE(preset);
    FrameSettings s = *presetSettings(preset);
    s.width = 96;
    s.height = 54;
    renderer->setLight(spot, scene.lights[spot]);
    ASSERT_TRUE(renderer->render(scene.camera, s).error.empty());
    EXPECT_EQ(renderer->render(scene.camera, s).shaderCompiles, 0);
    renderer->setLight(spot, wide);
    const FrameStats widened = renderer->render(scene.camera, s);
    // Raster: the frame's variant and the probes' (their faces are shaded with the same maps).
    EXPECT_EQ(widened.shaderCompiles, std::string(preset) == "raster" ? 2 : 0);
    EXPECT_EQ(renderer->render(scene.camera, s).shaderCompiles, 0);
    const ImageF got = renderer->readLinear();

    Scene wideScene = scene;
    wideScene.lights[spot] = wide;
    auto fresh = gltest::makeRenderer(*glContext_);
    ASSERT_TRUE(fresh);
    ASSERT_TRUE(fresh->setScene(wideScene).ok());
    ASSERT_TRUE(fresh->render(wideScene.camera, s).error.empty());
    EXPECT_EQ(got.rgb, fresh->readLinear().rgb);
  }
}

// A frame whose camera, scene and ray settings equal the last frame's reuses its rays (FrameSettings::
// reuseRays): it traces nothing and must equal, to the bit, the frame a renderer that traces every frame
// draws. Anything the rays depend on — the camera, a light, an instance, a new scene, a ray setting, the
// frame size — makes the next frame trace again; what they do not depend on (tone map, exposure, setting a
// transform or light to the value it has) does not.
TEST(FrameDecisions, AStillFrameReusesItsRaysAndEqualsATracedOne) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  Scene same = scene;
  auto tracing = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(tracing);
  ASSERT_TRUE(tracing->setScene(same).ok());
  for (const char* preset : {"hybrid-full", "hybrid-fast", "reference"}) {
    SCOPED_TRACE(preset);
    FrameSettings s = *presetSettings(preset);
    s.width = 120;
    s.height = 68;
    FrameSettings always = s;
    always.reuseRays = false;
    Camera camera = scene.camera;
    // Each step: what changes before the frame, and whether that frame may reuse the last one's rays.
    struct Step {
      const char* what;
      std::function<void()> change;
      bool reuses;
    } steps[] = {
        {"first frame", [] {}, false},
        {"nothing", [] {}, true},
        {"tone map and exposure", [&] { s.toneMap = ToneMap::Reinhard, s.exposure = 1.7f; }, true},
        {"camera", [&] { camera.posW.x += 0.25f; }, false},
        {"nothing again", [] {}, true},
        {"a light", [&] {
           Light l = scene.lights[1];
           l.intensity *= 0.5f;
           scene.lights[1] = l;
           same.lights[1] = l;
           renderer->setLight(1, l);
           tracing->setLight(1, l);
         }, false},
        {"an instance", [&] {
           const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.1f, 0.0f)) *
                                   scene.instances.back().worldFromObject;
           scene.instances.back().worldFromObject = moved;
           renderer->setInstanceTransform(static_cast<std::uint32_t>(scene.instances.size() - 1), moved);
           tracing->setInstanceTransform(static_cast<std::uint32_t>(scene.instances.size() - 1), moved);
         }, false},
        {"the same transform and light again", [&] {
           const auto last = static_cast<std::uint32_t>(scene.instances.size() - 1);
           renderer->setInstanceTransform(last, scene.instances.back().worldFromObject);
           tracing->setInstanceTransform(last, scene.instances.back().worldFromObject);
           renderer->setLight(1, scene.lights[1]);
           tracing->setLight(1, scene.lights[1]);
         }, true},
        {"the same scene set again", [&] {
           ASSERT_TRUE(renderer->setScene(scene).ok());
           ASSERT_TRUE(tracing->setScene(scene).ok());
         }, false},
        {"depth", [&] { s.maxDepth = 3; }, false},
        {"size", [&] { s.width = 100; }, false},
        {"nothing at the end", [] {}, true},
    };
    for (const Step& step : steps) {
      SCOPED_TRACE(step.what);
      step.change();
      always = s;
      always.reuseRays = false;
      const FrameStats got = renderer->render(camera, s);
      ASSERT_TRUE(got.error.empty()) << got.error;
      EXPECT_EQ(got.raysReused, step.reuses);
      EXPECT_EQ(got.rays.total() == 0, step.reuses) << "a reused frame traces nothing; a traced one something";
      const FrameStats want = tracing->render(camera, always);
      EXPECT_FALSE(want.raysReused);
      EXPECT_EQ(renderer->readLinear().rgb, tracing->readLinear().rgb);
      EXPECT_EQ(renderer->readImage().rgba, tracing->readImage().rgba);
    }
  }
}

// Reuse when something moves (rt/RayReuse.h): with the camera still, frames where instances move and a
// light changes keep the shadow answers of rays clear of them, and every frame equals one traced whole,
// to the bit, in every hybrid preset, at a coarser ray grid and with hybrid shadows.
TEST(FrameDecisions, MovingThingsKeepOnlyTheShadowAnswersTheyCannotChange) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  auto tracing = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(tracing);
  const Scene start = scene;
  struct Case {
    const char* name;
    const char* preset;
    int scale;
    bool hybridShadows;
  } cases[] = {{"hybrid-full", "hybrid-full", 1, false},
               {"hybrid-fast", "hybrid-fast", 2, false},
               {"hybrid-full, hybrid shadows, 1/2 grid", "hybrid-full", 2, true}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    scene = start;
    ASSERT_TRUE(renderer->setScene(scene).ok());
    ASSERT_TRUE(tracing->setScene(scene).ok());
    FrameSettings s = *presetSettings(c.preset);
    s.width = 160;
    s.height = 90;
    s.rayScale = c.scale;
    s.hybridShadows = c.hybridShadows;
    FrameSettings always = s;
    always.reuseRays = false;
    const std::uint32_t last = static_cast<std::uint32_t>(scene.instances.size() - 1);
    std::uint64_t kept = 0, answers = 0;
    for (int frame = 0; frame < 10; ++frame) {
      SCOPED_TRACE("frame " + std::to_string(frame));
      // Frame 4: nothing changes (the whole frame reused); frame 5: only the spot light moves (it keeps
      // from the frames before 4, through the reused one).
      const bool still = frame == 4;
      if (frame == 5) {
        scene.lights[2].posW += glm::vec3(0.4f, 0.0f, -0.3f);
        renderer->setLight(2, scene.lights[2]);
        tracing->setLight(2, scene.lights[2]);
      } else if (frame > 0 && !still) {
        // One instance bobs up and down; on every third frame a direct light dims as well.
        Instance& moving = scene.instances[last];
        moving.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, (frame % 2 ? 0.15f : -0.15f), 0.0f)) *
                                 moving.worldFromObject;
        renderer->setInstanceTransform(last, moving.worldFromObject);
        tracing->setInstanceTransform(last, moving.worldFromObject);
        if (frame % 3 == 0) {
          for (std::uint32_t j = 0; j < scene.lights.size(); ++j)
            if (scene.lights[j].type != LightType::Ambient) {
              scene.lights[j].intensity *= 0.9f;
              renderer->setLight(j, scene.lights[j]);
              tracing->setLight(j, scene.lights[j]);
              break;
            }
        }
      }
      const FrameStats got = renderer->render(scene.camera, s);
      ASSERT_TRUE(got.error.empty()) << got.error;
      const FrameStats want = tracing->render(scene.camera, always);
      ASSERT_TRUE(want.error.empty()) << want.error;
      const ImageF gotLinear = renderer->readLinear(), wantLinear = tracing->readLinear();
      ASSERT_EQ(gotLinear.rgb.size(), wantLinear.rgb.size());
      EXPECT_EQ(std::memcmp(gotLinear.rgb.data(), wantLinear.rgb.data(), gotLinear.rgb.size() * sizeof(glm::vec3)), 0)
          << "the linear frame differs from the traced one";
      EXPECT_EQ(renderer->readImage().rgba, tracing->readImage().rgba);
      EXPECT_EQ(want.rays.shadowKept, 0u);
      if (still) {
        EXPECT_TRUE(got.raysReused) << "nothing changed: the whole frame is reused";
        continue;
      }
      EXPECT_FALSE(got.raysReused) << "something moved: this frame traces";
      if (frame == 0) {
        EXPECT_EQ(got.rays.shadowKept, 0u) << "nothing to keep on the first frame";
      }
      // Every answer is a traced ray, a map's, a shaft's or a kept one, and the kept ones are what tracing gives.
      EXPECT_EQ(got.rays.shadow + got.rays.shadowByMap + got.rays.shadowByShaft + got.rays.shadowKept,
                want.rays.shadow + want.rays.shadowByMap + want.rays.shadowByShaft);
      EXPECT_EQ(got.rays.primary, want.rays.primary);
      EXPECT_EQ(got.rays.reflection, want.rays.reflection) << "reflections are traced again";
      EXPECT_EQ(got.rays.refraction, want.rays.refraction);
      EXPECT_LE(got.rays.shadow, want.rays.shadow);
      if (frame > 0) {
        EXPECT_GT(got.rays.shadowKept, 0u);
      }
      kept += got.rays.shadowKept;
      answers += want.rays.shadow + want.rays.shadowByMap + want.rays.shadowByShaft;
    }
    // The moving box is small next to the frame: most primary shadow answers outlive its moves (measured
    // 45 % of all answers in hybrid-full, whose reflections' shadow rays are never kept; 76 % otherwise).
    EXPECT_GT(kept, answers * 3 / 10) << "kept " << kept << " of " << answers;
  }
}

// The frame's shade pass writes the display values itself (fused output) instead of a second pass over
// the linear target: for every view and tone map, each displayed pixel is tdDisplay of the linear pixel
// the renderer keeps (computed here by the C++ twin of that formula), the sky included.
TEST(FrameDecisions, DisplayIsTheToneMappedLinearFrameInEveryView) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto renderer = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(renderer);
  const Camera camera = scene.camera;
  struct Case {
    const char* preset;
    DebugView view;
    ToneMap toneMap;
    float exposure;
  } cases[] = {{"hybrid-full", DebugView::Final, ToneMap::Aces, 1.0f},
               {"raster", DebugView::Final, ToneMap::Reinhard, 2.0f},
               {"hybrid-fast", DebugView::Reflection, ToneMap::None, 0.5f},
               {"hybrid-full", DebugView::NormalW, ToneMap::Aces, 1.0f},
               {"raster", DebugView::Depth, ToneMap::Aces, 1.0f}};
  for (const Case& k : cases) {
    SCOPED_TRACE(std::string(k.preset) + " " + std::string(toString(k.view)));
    FrameSettings s = *presetSettings(k.preset);
    s.width = 96;
    s.height = 54;
    s.debugView = k.view;
    s.toneMap = k.toneMap;
    s.exposure = k.exposure;
    ASSERT_TRUE(renderer->render(camera, s).error.empty());
    const Image display = renderer->readImage();
    const ImageF linear = renderer->readLinear();
    ASSERT_EQ(linear.rgb.size(), static_cast<std::size_t>(s.width * s.height));
    // GL 4.5 §2.3.5.1: a float becomes an 8-bit unorm as "one of the two" levels closest to f·255, rounding to
    // nearest only preferred. A value exactly between two levels (0.5 + 0.5·N of an axis-aligned normal is
    // 127.5: 5211 of the normal view's 15552 values) may go either way: llvmpipe rounds it up, NVIDIA's driver
    // was seen to differ on 5264 of them, and on 1.8–3.4 % of the other views' values, near half steps. So:
    // every value within the two closest levels; a value farther than a tenth of a level from a half step
    // rounded to nearest (a wrong tone map, exposure or view moves values by more than that).
    int outside = 0, ties = 0, off = 0, others = 0;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        const glm::vec3 want = shading::tdDisplay(linear.at(x, y), s.exposure, static_cast<int>(s.toneMap),
                                                  !isRadianceView(s.debugView)) * 255.0f;
        const glm::u8vec4 got = display.at(x, y);
        for (int c = 0; c < 3; ++c) {
          const float level = want[c];
          outside += std::abs(float(got[c]) - level) >= 1.0f + 1e-4f;
          if (std::abs(level - std::floor(level) - 0.5f) < 0.1f) {
            ++ties;
            continue;
          }
          ++others;
          off += int(got[c]) != int(std::lround(level));
        }
      }
    std::printf("%s %s: %d of %d values within a tenth of a level of a half step; %d of the others not rounded to "
                "nearest\n", k.preset, std::string(toString(k.view)).c_str(), ties, ties + others, off);
    EXPECT_EQ(outside, 0) << "a display value more than a level from tdDisplay of the linear pixel";
    EXPECT_EQ(off, 0) << "display values not rounded to nearest, away from any half step";
  }
}

}  // namespace
}  // namespace tandem
