#pragma once
// Shared set-up for the tests that need a GL context. A test that cannot get a headless context FAILS
// with the reason (these tests exist to exercise GL; skipping would hide a broken machine).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/Gl.h"
#include "support/TestSupport.h"
#include "tandem/Context.h"
#include "tandem/Image.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Primitives.h"
#include "tandem/Renderer.h"
#include "tandem/Scene.h"
#include "tandem/SceneFile.h"

namespace tandem::gltest {

/// One headless context for the whole test binary, made current again for every caller (tests that
/// create contexts of their own leave theirs current).
inline GlContext* sharedContext(std::string& error) {
  static std::unique_ptr<GlContext> context;
  static std::string failure;
  static bool tried = false;
  if (!tried) {
    tried = true;
    auto created = createGlContext({.kind = ContextKind::Headless, .debug = true});
    if (created) context = std::move(*created);
    else failure = created.error().message;
  }
  error = failure;
  if (context) context->makeCurrent();
  return context.get();
}

#define TD_REQUIRE_GL_CONTEXT()                                                      \
  std::string contextError_;                                                         \
  ::tandem::GlContext* glContext_ = ::tandem::gltest::sharedContext(contextError_);  \
  ASSERT_NE(glContext_, nullptr) << "no headless GL context: " << contextError_

/// Settings with every ray effect off and no tone map, so the image is local shading only.
inline FrameSettings rasterOnly(int width, int height) {
  FrameSettings s;
  s.width = width;
  s.height = height;
  s.shadows = s.reflections = s.refraction = EffectMode::Off;
  s.toneMap = ToneMap::None;
  return s;
}

inline Material plainMaterial(glm::vec3 kd, ShadingModel model = ShadingModel::Phong) {
  Material m;
  m.kd = kd;
  m.ka = glm::vec3(0.1f);
  m.ks = glm::vec3(0.0f);
  m.shading = model;
  return m;
}

/// A unit box at the origin seen head-on along -Z from z = 4 (its +Z face fills the centre).
inline Scene boxScene() {
  Scene s;
  s.name = "box";
  s.meshes.push_back(makeBox(glm::vec3(1.0f)));
  s.materials.push_back(plainMaterial(glm::vec3(0.8f)));
  Instance inst;
  inst.name = "box";
  s.instances.push_back(inst);
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.intensity = 1.0f;
  s.lights.push_back(ambient);
  Light point;
  point.type = LightType::Point;
  point.posW = {1.0f, 2.0f, 4.0f};
  point.intensity = 1.0f;
  s.lights.push_back(point);
  s.camera.posW = {0.0f, 0.0f, 4.0f};
  s.camera.targetW = {0.0f, 0.0f, 0.0f};
  s.camera.yFovDeg = 45.0f;
  s.background = {0.1f, 0.2f, 0.3f};
  return s;
}

inline void savePng(const std::string& name, const Image& image) {
  auto ok = writePng(test::outputDir() + "/" + name, image);
  EXPECT_TRUE(ok.ok()) << name;
}

inline std::unique_ptr<Renderer> makeRenderer(GlContext& context) {
  auto r = Renderer::create(context);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? std::move(*r) : nullptr;
}

/// A renderer holding the embedded Whitted scene, and that scene (for its camera and instances); a null
/// renderer (with the failure recorded) when either cannot be made.
inline std::unique_ptr<Renderer> whittedRenderer(GlContext& context, Scene& scene) {
  auto loaded = loadDefaultScene();
  EXPECT_TRUE(loaded.ok()) << (loaded.ok() ? "" : loaded.error().message);
  if (!loaded.ok()) return nullptr;
  scene = std::move(*loaded);
  auto renderer = makeRenderer(context);
  if (!renderer) return nullptr;
  auto set = renderer->setScene(scene);
  EXPECT_TRUE(set.ok()) << (set.ok() ? "" : set.error().message);
  return set.ok() ? std::move(renderer) : nullptr;
}

/// A renderer holding one scene, its camera and the frame size its tests draw at.
struct SceneFrame {
  std::unique_ptr<Renderer> renderer;
  Camera camera;
  FrameSettings base;  // width and height only
};

/// `scene` (loaded or failed) in a renderer of its own with `threads` ray threads (0: all).
inline SceneFrame sceneFrame(GlContext& context, Result<Scene> scene, int width, int height, int threads = 0) {
  SceneFrame f;
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
  if (!scene.ok()) return f;
  RendererDesc desc;
  desc.threads = threads;
  auto renderer = Renderer::create(context, desc);
  EXPECT_TRUE(renderer.ok()) << (renderer.ok() ? "" : renderer.error().message);
  if (!renderer.ok()) return f;
  f.renderer = std::move(*renderer);
  f.camera = scene->camera;
  f.base.width = width;
  f.base.height = height;
  EXPECT_TRUE(f.renderer->setScene(std::move(*scene)).ok());
  return f;
}

/// One frame with `settings` from the frame's camera, its display image (the stats in `stats`).
inline Image drawFrame(SceneFrame& f, const FrameSettings& settings, FrameStats* stats = nullptr) {
  FrameStats st = f.renderer->render(f.camera, settings);
  EXPECT_TRUE(st.error.empty()) << st.error;
  if (stats != nullptr) *stats = st;
  return f.renderer->readImage();
}

/// The converged image of an accumulation of `frames` frames (FrameSettings::accumulate).
inline Image accumulateFrames(SceneFrame& f, FrameSettings settings, int frames) {
  settings.accumulate = frames;
  Image image;
  for (int i = 0; i < frames; ++i) image = drawFrame(f, settings);
  return image;
}

/// Mean LDR-FLIP of two images (1 when they cannot be compared, with the failure recorded).
inline double flipMean(const Image& a, const Image& b) {
  auto r = flip(a, b);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r->mean : 1.0;
}

}  // namespace tandem::gltest
