// Context creation: each kind alone, the fallback chain, and failures that name the step. The expectations
// follow what this machine's EGL offers (read with EGL directly), not what llvmpipe happens to do.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "GlTestUtil.h"  // glad's GL header first: it refuses to follow another

// Generic EGL types: Xlib's macros (None, Bool, Status) would collide with the test framework's names.
#define EGL_NO_X11
#include <EGL/egl.h>
#include <EGL/eglext.h>

namespace tandem {
namespace {

void expectGl45(GlContext& ctx) {
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  EXPECT_GE(major * 10 + minor, 45) << ctx.describe();
  EXPECT_NE(ctx.describe().find("OpenGL"), std::string::npos) << ctx.describe();
}

TEST(ContextGLTest, HeadlessGivesCore45) {
  TD_REQUIRE_GL_CONTEXT();
  expectGl45(*glContext_);
  EXPECT_NE(glContext_->kind(), ContextKind::Window);
}

TEST(ContextGLTest, EglSurfacelessAlone) {
  auto ctx = createGlContext({.kind = ContextKind::EglSurfaceless});
  ASSERT_TRUE(ctx.ok()) << ctx.error().message;
  EXPECT_EQ((*ctx)->describe().rfind("EGL surfaceless", 0), 0u) << (*ctx)->describe();
  expectGl45(**ctx);
}

// OSMesa is a fallback loaded at run time: a machine without libOSMesa (the GPU machine's bundle has none)
// cannot give one, like a machine without a display cannot give a window. Its tests skip there, saying so,
// and fail only where the run asked for OSMesa: TANDEM_REQUIRE_OSMESA=1, which tools/test.sh sets (it
// installs libosmesa6).
bool osmesaMissing(const Result<std::unique_ptr<GlContext>>& ctx) {
  return !ctx.ok() && ctx.error().message.find("dlopen(libOSMesa.so.8) failed") != std::string::npos;
}
bool osmesaRequired() {
  const char* v = std::getenv("TANDEM_REQUIRE_OSMESA");
  return v != nullptr && std::string(v) == "1";
}
#define TD_SKIP_WITHOUT_OSMESA(ctx)                                                                   \
  if (osmesaMissing(ctx) && !osmesaRequired())                                                       \
  GTEST_SKIP() << (ctx).error().message << " (no libOSMesa here; TANDEM_REQUIRE_OSMESA=1 makes this a failure)"

TEST(ContextGLTest, OsMesaAlone) {
  auto ctx = createGlContext({.kind = ContextKind::OSMesa});
  TD_SKIP_WITHOUT_OSMESA(ctx);
  ASSERT_TRUE(ctx.ok()) << ctx.error().message;
  EXPECT_EQ((*ctx)->describe().rfind("OSMesa", 0), 0u) << (*ctx)->describe();
  expectGl45(**ctx);
}

TEST(ContextGLTest, OsMesaRendersTheSameBoxAsEgl) {
  // Two platforms in one process: glad's pointers must follow the current context.
  auto osmesa = createGlContext({.kind = ContextKind::OSMesa});
  TD_SKIP_WITHOUT_OSMESA(osmesa);
  ASSERT_TRUE(osmesa.ok()) << osmesa.error().message;
  auto renderer = gltest::makeRenderer(**osmesa);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(gltest::boxScene()).ok());
  renderer->render(renderer->scene().camera, gltest::rasterOnly(64, 48));
  Image a = renderer->readImage();
  renderer.reset();
  osmesa->reset();

  TD_REQUIRE_GL_CONTEXT();
  auto other = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(other);
  ASSERT_TRUE(other->setScene(gltest::boxScene()).ok());
  other->render(other->scene().camera, gltest::rasterOnly(64, 48));
  Image b = other->readImage();
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  int differing = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) differing += std::abs(int(a.rgba[i]) - int(b.rgba[i])) > 1;
  EXPECT_EQ(differing, 0);
}

// A game that makes and drops contexts on one thread, as a test binary run in one process does: the shared
// EGL context drawing, then an OSMesa context made, drawn with and dropped, a second EGL context made and
// dropped, and the two kept side by side with each made current in turn. After each, the first context's
// renderers are made and draw what they drew before. (EGL kept its own record of its context as current while
// OSMesa's was bound, skipped the rebind, and the next renderer's first shader failed with an empty log.)
TEST(ContextGLTest, ContextsMadeAndDroppedOnOneThreadLeaveTheOthersDrawing) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = gltest::boxScene();
  auto draw = [&](GlContext& context) {
    context.makeCurrent();
    auto r = gltest::makeRenderer(context);
    EXPECT_TRUE(r->setScene(scene).ok());
    EXPECT_TRUE(r->render(scene.camera, gltest::rasterOnly(64, 48)).error.empty());
    return r->readImage();
  };
  const Image first = draw(*glContext_);
  int covered = 0;
  for (std::size_t i = 0; i < first.rgba.size(); i += 4) covered += first.rgba[i] != first.at(0, 0).r ? 1 : 0;
  ASSERT_GT(covered, 100) << "the box is drawn";
  {
    auto osmesa = createGlContext({.kind = ContextKind::OSMesa});
    TD_SKIP_WITHOUT_OSMESA(osmesa);
    ASSERT_TRUE(osmesa.ok()) << osmesa.error().message;
    EXPECT_EQ(draw(**osmesa).width, 64);
  }
  EXPECT_TRUE(gltest::sameImage(draw(*glContext_), first)) << "after an OSMesa context was dropped";
  {
    auto egl = createGlContext({.kind = ContextKind::EglSurfaceless});
    ASSERT_TRUE(egl.ok()) << egl.error().message;
    EXPECT_TRUE(gltest::sameImage(draw(**egl), first));
  }
  EXPECT_TRUE(gltest::sameImage(draw(*glContext_), first)) << "after a second EGL context was dropped";
  // Both alive, each renderer drawing on its own context in turn.
  auto osmesa = createGlContext({.kind = ContextKind::OSMesa});
  ASSERT_TRUE(osmesa.ok()) << osmesa.error().message;
  const Image onOsMesa = draw(**osmesa);
  (*osmesa)->makeCurrent();
  auto there = gltest::makeRenderer(**osmesa);
  ASSERT_TRUE(there->setScene(scene).ok());
  glContext_->makeCurrent();
  auto here = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(here->setScene(scene).ok());
  for (int round = 0; round < 2; ++round) {
    (*osmesa)->makeCurrent();
    EXPECT_TRUE(there->render(scene.camera, gltest::rasterOnly(64, 48)).error.empty());
    EXPECT_TRUE(gltest::sameImage(there->readImage(), onOsMesa)) << "round " << round;
    glContext_->makeCurrent();
    EXPECT_TRUE(here->render(scene.camera, gltest::rasterOnly(64, 48)).error.empty());
    EXPECT_TRUE(gltest::sameImage(here->readImage(), first)) << "round " << round;
  }
  (*osmesa)->makeCurrent();
  there.reset();
  osmesa->reset();
  EXPECT_TRUE(gltest::sameImage(draw(*glContext_), first)) << "after the OSMesa context in use was dropped";
}

// What this machine's EGL offers the device platform, read here with EGL itself (not through the code
// under test): whether the client can enumerate devices at all, and whether any listed device is not
// Mesa's software renderer.
struct EglDeviceSurvey {
  bool enumerable = false;
  int devices = 0;
  int hardware = 0;
};

EglDeviceSurvey surveyEglDevices() {
  EglDeviceSurvey survey;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::string exts = client ? std::string(" ") + client + " " : "";
  auto has = [&](const char* name) { return exts.find(std::string(" ") + name + " ") != std::string::npos; };
  survey.enumerable = has("EGL_EXT_platform_device") && (has("EGL_EXT_device_base") ||
                                                         (has("EGL_EXT_device_enumeration") && has("EGL_EXT_device_query")));
  if (!survey.enumerable) return survey;
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  EGLDeviceEXT devices[32];
  EGLint count = 0;
  if (!queryDevices || !queryString || !queryDevices(32, devices, &count)) return survey;
  survey.devices = count;
  for (EGLint i = 0; i < count; ++i) {
    const char* d = queryString(devices[i], EGL_EXTENSIONS);
    survey.hardware += d == nullptr || std::string(" ") .append(d).append(" ").find(" EGL_MESA_device_software ") ==
                                           std::string::npos;
  }
  return survey;
}

TEST(ContextGLTest, EglDeviceTakesAHardwareDeviceOrSaysWhyNot) {
  // Where the EGL client offers devices and lists a GPU, the device platform must give a context on it,
  // named in describe(); where it lists only Mesa's software device (this machine class), it must refuse
  // and name that device, leaving llvmpipe to surfaceless.
  EglDeviceSurvey survey = surveyEglDevices();
  auto ctx = createGlContext({.kind = ContextKind::EglDevice});
  if (survey.enumerable && survey.hardware > 0) {
    ASSERT_TRUE(ctx.ok()) << survey.hardware << " hardware EGL device(s) listed, yet: " << ctx.error().message;
    const std::string d = (*ctx)->describe();
    EXPECT_EQ(d.rfind("EGL device ", 0), 0u) << d;
    EXPECT_NE(d.find(" of " + std::to_string(survey.devices)), std::string::npos) << d;
    EXPECT_EQ(d.find("llvmpipe"), std::string::npos) << d;
    expectGl45(**ctx);
  } else {
    ASSERT_FALSE(ctx.ok()) << (*ctx)->describe();
    const std::string& m = ctx.error().message;
    EXPECT_EQ(m.rfind("EGL device: ", 0), 0u) << m;
    if (!survey.enumerable) {
      EXPECT_NE(m.find("the EGL client extensions lack"), std::string::npos) << m;
    } else if (survey.devices > 0) {
      EXPECT_NE(m.find("EGL lists " + std::to_string(survey.devices) + ", and device 0 is a software renderer "
                       "(EGL_MESA_device_software)"),
                std::string::npos)
          << m;
    }
  }
}

// The message of a context refused for OpenGL 9.9 names the step that refused it: the driver refusing
// the version (eglCreateContext with its EGL error, OSMesaCreateContextAttribs), or the driver handing
// out the newest context it has instead, which the version check after it catches.
bool namesTheVersionStep(const std::string& m) {
  return m.find("eglCreateContext(OpenGL 9.9 core) failed (EGL_") != std::string::npos ||
         m.find("OSMesaCreateContextAttribs(OpenGL 9.9 core) returned no context") != std::string::npos ||
         m.find(", need 9.9 core") != std::string::npos;
}

TEST(ContextGLTest, ImpossibleVersionFailsWithTheStep) {
  // Only platforms that give this machine a 4.5 context can show where 9.9 fails: one that is absent
  // (OSMesa not installed, no hardware EGL device) fails earlier, for that reason.
  TD_REQUIRE_GL_CONTEXT();
  int checked = 0;
  for (ContextKind kind : {ContextKind::EglDevice, ContextKind::EglSurfaceless, ContextKind::OSMesa}) {
    if (!createGlContext({.kind = kind}).ok()) continue;
    auto ctx = createGlContext({.kind = kind, .glMajor = 9, .glMinor = 9});
    ASSERT_FALSE(ctx.ok()) << (*ctx)->describe();
    EXPECT_TRUE(namesTheVersionStep(ctx.error().message)) << ctx.error().message;
    ++checked;
  }
  EXPECT_GE(checked, 1) << "the shared headless context came from one of these platforms";
  // Headless names the version, then each platform's own failure on a line of its own.
  auto headless = createGlContext({.kind = ContextKind::Headless, .glMajor = 9, .glMinor = 9});
  ASSERT_FALSE(headless.ok());
  const std::string& m = headless.error().message;
  EXPECT_EQ(m.rfind("no headless OpenGL 9.9 core context:\n  EGL device", 0), 0u) << m;
  EXPECT_NE(m.find("\n  EGL surfaceless: "), std::string::npos) << m;
  EXPECT_NE(m.find("\n  OSMesa: "), std::string::npos) << m;
  EXPECT_TRUE(namesTheVersionStep(m)) << m;
}

TEST(ContextGLTest, WindowWithoutADisplayIsAnError) {
  // No display server named in the environment: no window can exist, and the error says GLFW could not make one
  // (the positive case, a window under Xvfb, is GameRun.WindowUnderXvfbCapturesFrameAndHud). The environment is restored after.
  std::string saved[2];
  const char* names[2] = {"DISPLAY", "WAYLAND_DISPLAY"};
  bool had[2];
  for (int i = 0; i < 2; ++i) {
    const char* v = std::getenv(names[i]);
    had[i] = v != nullptr;
    if (had[i]) saved[i] = v;
    ::unsetenv(names[i]);
  }
  auto ctx = createGlContext({.kind = ContextKind::Window, .width = 64, .height = 64});
  for (int i = 0; i < 2; ++i)
    if (had[i]) ::setenv(names[i], saved[i].c_str(), 1);
  ASSERT_FALSE(ctx.ok()) << "a window without DISPLAY or WAYLAND_DISPLAY: " << (*ctx)->describe();
  EXPECT_EQ(ctx.error().message.rfind("GLFW", 0), 0u) << ctx.error().message;
}

}  // namespace
}  // namespace tandem
