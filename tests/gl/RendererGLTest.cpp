// The Renderer end to end: an analytic Phong check, debug views, ray-pass inputs, scene validation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "GlTestUtil.h"
#include "core/Shading.h"

namespace tandem {
namespace {

using namespace tandem::shading;

// Nearest hit of a ray on a mesh (object = world here), brute force.
struct MeshHit {
  bool hit = false;
  float t = std::numeric_limits<float>::infinity();
  std::uint32_t triangle = 0;
  glm::vec3 bary{0.0f};
};

MeshHit intersect(const Mesh& mesh, const Ray& ray) {
  MeshHit best;
  for (std::uint32_t tri = 0; tri < mesh.triangleCount(); ++tri) {
    glm::vec3 p0 = mesh.positions[mesh.indices[3 * tri]], p1 = mesh.positions[mesh.indices[3 * tri + 1]],
              p2 = mesh.positions[mesh.indices[3 * tri + 2]];
    glm::vec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(ray.dir, e2);
    float det = glm::dot(e1, pv);
    if (std::abs(det) < 1e-12f) continue;
    glm::vec3 tv = ray.origin - p0;
    float b1 = glm::dot(tv, pv) / det;
    glm::vec3 qv = glm::cross(tv, e1);
    float b2 = glm::dot(ray.dir, qv) / det;
    float t = glm::dot(e2, qv) / det;
    if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0 || t >= best.t) continue;
    best = {true, t, tri, {1 - b1 - b2, b1, b2}};
  }
  return best;
}

Scene sphereScene() {
  Scene s = gltest::boxScene();
  s.meshes = {makeSphere(1.0f, 64, 32)};
  Material m;
  m.ka = {0.1f, 0.1f, 0.1f};
  m.kd = {0.7f, 0.5f, 0.3f};
  m.ks = {0.5f, 0.5f, 0.5f};
  m.ns = 20.0f;
  s.materials = {m};
  s.lights[0].intensity = 0.2f;  // ambient
  s.lights[1].posW = {2.0f, 3.0f, 4.0f};
  s.lights[1].attenuation = {1.0f, 0.05f, 0.01f};
  s.lights[1].intensity = 1.5f;
  return s;
}

TEST(RendererGLTest, PhongSphereMatchesTheFormula) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = sphereScene();
  ASSERT_TRUE(renderer->setScene(scene).ok());
  const int w = 160, h = 120;
  FrameSettings settings = gltest::rasterOnly(w, h);
  renderer->render(scene.camera, settings);
  Image image = renderer->readImage();
  gltest::savePng("phong-sphere.png", image);
  ASSERT_EQ(image.width, w);

  const Material& mat = scene.materials[0];
  GpuLight light = packLight(scene.lights[1]);
  glm::vec3 ia = scene.ambientIntensity();
  int compared = 0, worst = 0;
  for (int y = 2; y < h; y += 3)
    for (int x = 2; x < w; x += 3) {
      Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {w, h});
      // Stay off the silhouette, where coverage may legitimately differ by a pixel.
      float closest = glm::length(glm::cross(ray.dir, -ray.origin));
      glm::u8vec4 got = image.at(x, y);
      if (closest > 1.05f) {
        glm::vec3 bg = tdSrgbEncode(tdToneMap(scene.background, TD_TONEMAP_NONE)) * 255.0f;
        EXPECT_NEAR(got.r, bg.r, 1.0) << x << "," << y;
        continue;
      }
      if (closest > 0.97f) continue;
      MeshHit hit = intersect(scene.meshes[0], ray);
      ASSERT_TRUE(hit.hit) << x << "," << y;
      const Mesh& mesh = scene.meshes[0];
      glm::vec3 n = glm::normalize(hit.bary.x * mesh.normals[mesh.indices[3 * hit.triangle]] +
                                   hit.bary.y * mesh.normals[mesh.indices[3 * hit.triangle + 1]] +
                                   hit.bary.z * mesh.normals[mesh.indices[3 * hit.triangle + 2]]);
      glm::vec3 posW = ray.origin + hit.t * ray.dir;
      glm::vec3 toLight;
      float dist;
      glm::vec3 e = tdLightIncident(light, posW, toLight, dist);
      glm::vec3 radiance = mat.ka * ia + tdShadeLight(mat.kd, mat.ks, mat.ns, TD_MODEL_PHONG, n, -ray.dir, e, toLight, 0.0f);
      glm::vec3 expected = tdSrgbEncode(tdToneMap(radiance, TD_TONEMAP_NONE)) * 255.0f;
      for (int c = 0; c < 3; ++c) {
        int diff = static_cast<int>(std::lround(std::abs(float(got[c]) - expected[c])));
        worst = std::max(worst, diff);
        EXPECT_LE(diff, 2) << "pixel " << x << "," << y << " channel " << c << " got " << int(got[c])
                           << " expected " << expected[c];
      }
      ++compared;
    }
  EXPECT_GT(compared, 300);
  RecordProperty("worst8bit", worst);
}

Scene shadowScene() {
  Scene s = gltest::boxScene();
  s.meshes = {makePlane(glm::vec2(8.0f), 4), makeBox(glm::vec3(1.0f)), makeSphere(0.5f, 32, 16)};
  Material floor = gltest::plainMaterial({0.8f, 0.8f, 0.8f});
  floor.kd2 = {0.2f, 0.2f, 0.2f};
  floor.checkerFrequency = 1.0f;
  Material mirror = gltest::plainMaterial({0.2f, 0.2f, 0.6f});
  mirror.kr = 0.5f;
  Material glass = gltest::plainMaterial({0.1f, 0.1f, 0.1f});
  glass.kt = 0.8f;
  glass.ior = 1.5f;
  s.materials = {floor, mirror, glass};
  Instance plane, box, ball;
  plane.mesh = 0;
  box.mesh = 1;
  box.material = 1;
  box.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-0.8f, 0.5f, 0.0f));
  ball.mesh = 2;
  ball.material = 2;
  ball.dynamic = true;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.9f, 0.5f, 0.5f));
  s.instances = {plane, box, ball};
  s.lights[1].posW = {0.5f, 4.0f, 1.0f};
  s.lights[1].intensity = 1.0f;
  s.camera.posW = {0.0f, 3.0f, 5.0f};
  s.camera.targetW = {0.0f, 0.3f, 0.0f};
  return s;
}

int distinctColours(const Image& image) {
  std::set<std::uint32_t> colours;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    colours.insert(std::uint32_t(image.rgba[i]) | std::uint32_t(image.rgba[i + 1]) << 8 |
                   std::uint32_t(image.rgba[i + 2]) << 16);
  return static_cast<int>(colours.size());
}

TEST(RendererGLTest, EveryDebugViewRenders) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = shadowScene();
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s;
  s.width = 160;
  s.height = 90;
  Image finalImage;
  for (int v = 0; v <= static_cast<int>(DebugView::Transmission); ++v) {
    s.debugView = static_cast<DebugView>(v);
    FrameStats stats = renderer->render(scene.camera, s);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    Image image = renderer->readImage();
    gltest::savePng("debug-" + std::string(toString(s.debugView)) + ".png", image);
    // One light: the light mask is black or white; every other view has many values.
    EXPECT_GE(distinctColours(image), s.debugView == DebugView::LightMask ? 2 : 3) << toString(s.debugView);
    if (v == 0) {
      finalImage = image;
    } else {
      EXPECT_NE(image.rgba, finalImage.rgba) << toString(s.debugView) << " looks like the final image";
    }
    // The views show ray results: traced by the first frame, then reused, since only the view changes.
    EXPECT_EQ(stats.raysReused, v > 0) << toString(s.debugView);
    if (v == 0) {
      EXPECT_GT(stats.rays.total(), 0u);
    } else {
      EXPECT_EQ(stats.rays.total(), 0u) << toString(s.debugView);
    }
  }
}

TEST(RendererGLTest, RayShadowsDarkenOnlyTheShadow) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = shadowScene();
  scene.materials[1].kr = 0.0f;
  scene.materials[2].kt = 0.0f;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s = gltest::rasterOnly(160, 90);
  renderer->render(scene.camera, s);
  Image off = renderer->readImage();
  s.shadows = EffectMode::Ray;
  FrameStats stats = renderer->render(scene.camera, s);
  Image ray = renderer->readImage();
  gltest::savePng("shadows-ray.png", ray);
  EXPECT_GT(stats.rays.shadow, 0u);
  EXPECT_EQ(stats.rays.reflection, 0u);  // no mirror in the scene: not traced
  int darker = 0, brighter = 0;
  for (std::size_t i = 0; i < off.rgba.size(); i += 4) {
    darker += ray.rgba[i + 1] + 2 < off.rgba[i + 1];
    brighter += ray.rgba[i + 1] > off.rgba[i + 1] + 1;
  }
  EXPECT_GT(darker, 200);
  EXPECT_EQ(brighter, 0);

  // Half-resolution rays, upsampled edge-aware: nearly the same shadow.
  s.rayScale = 2;
  stats = renderer->render(scene.camera, s);
  EXPECT_EQ(stats.rayWidth, 80);
  EXPECT_EQ(stats.rayHeight, 45);
  Image half = renderer->readImage();
  gltest::savePng("shadows-ray-half.png", half);
  // Only the shadow's outline may move by up to a grid pixel; its area stays.
  int differing = 0, darkerHalf = 0;
  for (std::size_t i = 0; i < ray.rgba.size(); i += 4) {
    differing += std::abs(int(half.rgba[i + 1]) - int(ray.rgba[i + 1])) > 8;
    darkerHalf += half.rgba[i + 1] + 2 < off.rgba[i + 1];
  }
  EXPECT_LT(differing, darker / 2);
  EXPECT_NEAR(darkerHalf, darker, darker / 4);
}

TEST(RendererGLTest, NoRayPassWhenNothingNeedsIt) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = gltest::boxScene();  // no mirror, no glass
  scene.lights[1].castShadows = false;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s;  // every effect Ray
  s.width = 64;
  s.height = 48;
  FrameStats stats = renderer->render(scene.camera, s);
  EXPECT_EQ(stats.rays.total(), 0u);
  EXPECT_EQ(stats.rayWidth, 0);
}

TEST(RendererGLTest, InvalidSceneKeepsTheOldOne) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(gltest::boxScene()).ok());
  FrameSettings s = gltest::rasterOnly(64, 48);
  renderer->render(renderer->scene().camera, s);
  Image before = renderer->readImage();

  Scene bad = gltest::boxScene();
  bad.instances[0].mesh = 7;
  auto result = renderer->setScene(bad);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("mesh index"), std::string::npos) << result.error().message;
  EXPECT_EQ(renderer->scene().instances[0].mesh, 0u);
  renderer->render(renderer->scene().camera, s);
  EXPECT_EQ(renderer->readImage().rgba, before.rgba);
}

TEST(RendererGLTest, DynamicInstanceMoves) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = gltest::boxScene();
  scene.instances[0].dynamic = true;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s = gltest::rasterOnly(64, 48);
  s.shadows = EffectMode::Ray;
  renderer->render(scene.camera, s);
  Image before = renderer->readImage();
  EXPECT_NE(before.at(32, 24), before.at(1, 1));  // the box covers the centre
  renderer->setInstanceTransform(0, glm::translate(glm::mat4(1.0f), glm::vec3(5.0f, 0.0f, 0.0f)));
  renderer->render(scene.camera, s);
  Image after = renderer->readImage();
  EXPECT_EQ(after.at(32, 24), after.at(1, 1));  // moved out of view: background everywhere
}

// The ids' read-back memory (gl/PixelReadback, mapped once and made again when a frame needs more) follows the
// frame's size both ways: a renderer that draws small, then large, then small and larger still, in latency and in
// throughput mode (whose two visibility buffers each read back), shows at each size the frame a fresh renderer
// draws there, to the bit, and leaves no GL error. (A read past a mapping the GL did not fill is not ASan's to
// see: it shows in the frame.)
TEST(RendererGLTest, TheIdReadBackFollowsTheFrameSizeBothWays) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene;
  auto r = gltest::whittedRenderer(*glContext_, scene);
  ASSERT_TRUE(r);
  // (the last: a frame needing less than the buffer the one before made, and more than a quarter of it: its rows
  // are read from the start of the larger buffer)
  const std::vector<glm::ivec2> sizes{{64, 36}, {160, 90}, {64, 36}, {200, 120}, {160, 90}};
  auto settingsAt = [](glm::ivec2 size, bool pipelined) {
    FrameSettings s = *presetSettings("hybrid-full");
    s.width = size.x;
    s.height = size.y;
    s.pipelined = pipelined;
    return s;
  };
  // The camera of the k-th size's frames (each frame at a size a little further along: every one traces).
  auto cameraAt = [&](std::size_t k, int frame) {
    Camera c = scene.camera;
    c.posW.x += 0.02f * static_cast<float>(2 * k + static_cast<std::size_t>(frame));
    return c;
  };
  std::vector<Image> fresh;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    Scene copy;
    auto f = gltest::whittedRenderer(*glContext_, copy);
    ASSERT_TRUE(f);
    ASSERT_TRUE(f->render(cameraAt(k, 1), settingsAt(sizes[k], false)).error.empty());
    fresh.push_back(f->readImage());
  }
  for (const bool pipelined : {false, true}) {
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      SCOPED_TRACE(std::string(pipelined ? "throughput" : "latency") + " mode, " + std::to_string(sizes[k].x) + "x" +
                   std::to_string(sizes[k].y));
      for (int frame = 0; frame < 2; ++frame) {
        const FrameStats st = r->render(cameraAt(k, frame), settingsAt(sizes[k], pipelined));
        EXPECT_TRUE(st.error.empty()) << st.error;
      }
      if (pipelined) {
        ASSERT_TRUE(r->finish());
      }
      const Image got = r->readImage();
      EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
      ASSERT_EQ(got.width, fresh[k].width);
      ASSERT_EQ(got.height, fresh[k].height);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < got.rgba.size(); i += 4)
        differ += std::memcmp(&got.rgba[i], &fresh[k].rgba[i], 4) != 0 ? 1 : 0;
      EXPECT_EQ(differ, 0u) << "pixels unlike the fresh renderer's frame";
    }
  }
}

TEST(RendererGLTest, ReferenceModeUsesTheSameOutputPath) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  Scene scene = sphereScene();
  scene.lights[1].castShadows = false;
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings s = gltest::rasterOnly(80, 60);
  s.shadows = EffectMode::Ray;
  renderer->render(scene.camera, s);
  ImageF raster = renderer->readLinear();
  s.reference = true;
  FrameStats stats = renderer->render(scene.camera, s);
  EXPECT_GT(stats.rays.primary, 0u);
  ImageF reference = renderer->readLinear();
  gltest::savePng("reference-sphere.png", renderer->readImage());
  ASSERT_EQ(reference.rgb.size(), raster.rgb.size());
  // Away from the silhouette the two agree (one sample per pixel centre in both).
  int compared = 0;
  for (int y = 10; y < 50; ++y)
    for (int x = 20; x < 60; ++x) {
      Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {80, 60});
      if (glm::length(glm::cross(ray.dir, -ray.origin)) > 0.95f) continue;
      EXPECT_NEAR(reference.at(x, y).g, raster.at(x, y).g, 2e-3f + 2e-3f * raster.at(x, y).g) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 200);
}

}  // namespace
}  // namespace tandem
