#pragma once
// Shared set-up for the tests that need a GL context. A test that cannot get a headless context FAILS
// with the reason (these tests exist to exercise GL; skipping would hide a broken machine).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "gl/FeedbackLoop.h"
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

/// A KHR_debug message of type error or undefined behaviour (the driver's, or the passes' own check of
/// their bindings before each draw: gl/FeedbackLoop.h) fails the test that caused it, on llvmpipe and on any
/// driver, unless the test expects it: ExpectGlDebug, for the tests that provoke a GL error on purpose.
class ExpectGlDebug {
 public:
  explicit ExpectGlDebug(std::string substring) : substring_(std::move(substring)) { active().push_back(this); }
  ~ExpectGlDebug() { active().erase(std::find(active().begin(), active().end(), this)); }
  ExpectGlDebug(const ExpectGlDebug&) = delete;
  ExpectGlDebug& operator=(const ExpectGlDebug&) = delete;
  /// The expected messages seen so far.
  int seen() const { return seen_; }

  static std::vector<ExpectGlDebug*>& active() {
    static std::vector<ExpectGlDebug*> list;
    return list;
  }
  bool take(const std::string& text) {
    if (text.find(substring_) == std::string::npos) return false;
    ++seen_;
    return true;
  }

 private:
  std::string substring_;
  int seen_ = 0;
};

inline void failOnGlDebugErrors() {
  setGlDebugHandler([](const GlDebugMessage& m) {
    if (m.kind != GlDebugMessage::Kind::Error && m.kind != GlDebugMessage::Kind::UndefinedBehavior) return;
    for (ExpectGlDebug* e : ExpectGlDebug::active())
      if (e->take(m.text)) return;
    ADD_FAILURE() << (m.kind == GlDebugMessage::Kind::Error ? "GL error: " : "GL undefined behaviour: ") << m.text;
  });
}

/// One headless context for the whole test binary, made current again for every caller (tests that
/// create contexts of their own leave theirs current). Debug output on, every draw's bindings checked, and
/// any error or undefined behaviour the driver or the checks report fails the test (failOnGlDebugErrors).
inline GlContext* sharedContext(std::string& error) {
  static std::unique_ptr<GlContext> context;
  static std::string failure;
  static bool tried = false;
  if (!tried) {
    tried = true;
    auto created = createGlContext({.kind = ContextKind::Headless, .debug = true});
    if (created) context = std::move(*created);
    else failure = created.error().message;
    gl::setFeedbackLoopChecks(true);
    failOnGlDebugErrors();
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

/// What ends a test whose renderer, or the scene its helper sets, could not be made: the helpers below record
/// the failure and throw this, which gtest reports as the test's failure (and goes on with the next test), so
/// that no helper hands a test a null renderer to dereference.
struct NotMade : std::runtime_error {
  using std::runtime_error::runtime_error;
};
[[noreturn]] inline void endTest(const std::string& why) {
  ADD_FAILURE() << why;
  throw NotMade(why);
}

/// The renderer `made`, or the test's end.
inline std::unique_ptr<Renderer> madeOrEnd(Result<std::unique_ptr<Renderer>> made) {
  if (!made.ok()) endTest("Renderer::create: " + made.error().message);
  return std::move(*made);
}

inline std::unique_ptr<Renderer> makeRenderer(GlContext& context) { return madeOrEnd(Renderer::create(context)); }

/// A renderer holding the embedded Whitted scene, and that scene (for its camera and instances).
inline std::unique_ptr<Renderer> whittedRenderer(GlContext& context, Scene& scene) {
  auto loaded = loadDefaultScene();
  if (!loaded.ok()) endTest("loadDefaultScene: " + loaded.error().message);
  scene = std::move(*loaded);
  auto renderer = makeRenderer(context);
  auto set = renderer->setScene(scene);
  if (!set.ok()) endTest("setScene: " + set.error().message);
  return renderer;
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
  if (!scene.ok()) endTest("the scene: " + scene.error().message);
  RendererDesc desc;
  desc.threads = threads;
  f.renderer = madeOrEnd(Renderer::create(context, desc));
  f.camera = scene->camera;
  f.base.width = width;
  f.base.height = height;
  auto set = f.renderer->setScene(std::move(*scene));
  if (!set.ok()) endTest("setScene: " + set.error().message);
  return f;
}

/// One frame with `settings` from the frame's camera, its display image (the stats in `stats`).
inline Image drawFrame(SceneFrame& f, const FrameSettings& settings, FrameStats* stats = nullptr) {
  FrameStats st = f.renderer->render(f.camera, settings);
  EXPECT_TRUE(st.error.empty()) << st.error;
  if (stats != nullptr) *stats = st;
  return f.renderer->readImage();
}

/// One frame with `settings` from `camera` (not the frame's), its display image (the stats in `stats`).
inline Image drawFrame(SceneFrame& f, const Camera& camera, const FrameSettings& settings, FrameStats* stats = nullptr) {
  FrameStats st = f.renderer->render(camera, settings);
  EXPECT_TRUE(st.error.empty()) << st.error;
  if (stats != nullptr) *stats = st;
  return f.renderer->readImage();
}

/// Preset `name` at the frame's size; `samples` > 1: that many supersamples in one frame (ssaa), each with
/// its own sub-pixel offset, lens point and shutter time. The reference at 1 spp.
inline FrameSettings presetFor(const SceneFrame& f, const char* name, int samples = 1) {
  FrameSettings s = *presetSettings(name, f.base);
  if (samples > 1) {
    s.aa = AntiAlias::Ssaa;
    s.aaSamples = samples;
  }
  s.referenceSpp = 1;
  return s;
}

inline bool sameImage(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba == b.rgba;
}

/// The converged image of an accumulation of `frames` frames (FrameSettings::accumulate).
inline Image accumulateFrames(SceneFrame& f, FrameSettings settings, int frames) {
  settings.accumulate = frames;
  Image image;
  for (int i = 0; i < frames; ++i) image = drawFrame(f, settings);
  return image;
}

/// Draws one frame with `settings` in both renderers (of the same scene, different ray thread counts) and
/// expects their linear frames identical to the bit.
inline void expectSameFrame(SceneFrame& one, SceneFrame& two, const FrameSettings& settings, const std::string& what) {
  drawFrame(one, settings);
  drawFrame(two, settings);
  const ImageF a = one.renderer->readLinear(), b = two.renderer->readLinear();
  ASSERT_EQ(a.rgb.size(), b.rgb.size()) << what;
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0) << what;
}

/// Mean LDR-FLIP of two images (1 when they cannot be compared, with the failure recorded).
inline double flipMean(const Image& a, const Image& b) {
  auto r = flip(a, b);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r->mean : 1.0;
}

/// The sampled effects' thread check: hybrid-full and hybrid-fast at 8 supersamples and the reference at 3×3
/// spp, identical from renderers of 1 and of 2 ray threads.
inline void expectSameOnAnyThreadCount(SceneFrame& one, SceneFrame& two) {
  for (const char* name : {"hybrid-full", "hybrid-fast"}) expectSameFrame(one, two, presetFor(one, name, 8), name);
  FrameSettings reference = presetFor(one, "reference");
  reference.referenceSpp = 3;
  expectSameFrame(one, two, reference, "reference");
}

/// A sampled effect's convergence (depth of field, motion blur): hybrid-full at 4, 16 and 64 supersamples in
/// one frame against a 256-sample reference (8×8 spp × 4 accumulated frames), each nearer than the last; the
/// reference's own 64 samples; and hybrid-full at 16 from `without`, the camera without the effect.
struct Convergence {
  Image truth, hybrid64;
  double error64 = 1.0, withoutEffect = 1.0, reference64 = 1.0;
};
inline Convergence converge(SceneFrame& f, const Camera& without, const char* what) {
  Convergence c;
  FrameSettings truthSettings = presetFor(f, "reference");
  truthSettings.referenceSpp = 8;
  c.truth = accumulateFrames(f, truthSettings, 4);
  c.withoutEffect = flipMean(drawFrame(f, without, presetFor(f, "hybrid-full", 16)), c.truth);
  double previous = 1.0;
  for (int samples : {4, 16, 64}) {
    c.hybrid64 = drawFrame(f, presetFor(f, "hybrid-full", samples));
    c.error64 = flipMean(c.hybrid64, c.truth);
    std::printf("hybrid-full, %d %s samples: FLIP vs reference %.5f\n", samples, what, c.error64);
    EXPECT_LT(c.error64, previous) << samples << " " << what << " samples";
    previous = c.error64;
  }
  FrameSettings reference64 = presetFor(f, "reference");
  reference64.referenceSpp = 8;
  c.reference64 = flipMean(drawFrame(f, reference64), c.truth);
  std::printf("without the effect %.5f, reference 64 samples %.5f\n", c.withoutEffect, c.reference64);
  return c;
}

}  // namespace tandem::gltest
