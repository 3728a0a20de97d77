// Context creation: each kind alone, the fallback chain, and failures that name the step.
#include <gtest/gtest.h>

#include "GlTestUtil.h"

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

TEST(ContextGLTest, OsMesaAlone) {
  auto ctx = createGlContext({.kind = ContextKind::OSMesa});
  ASSERT_TRUE(ctx.ok()) << ctx.error().message;
  EXPECT_EQ((*ctx)->describe().rfind("OSMesa", 0), 0u) << (*ctx)->describe();
  expectGl45(**ctx);
}

TEST(ContextGLTest, OsMesaRendersTheSameBoxAsEgl) {
  // Two platforms in one process: glad's pointers must follow the current context.
  auto osmesa = createGlContext({.kind = ContextKind::OSMesa});
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

TEST(ContextGLTest, EglDeviceIsAGpuOrAnError) {
  // On a machine without a GPU this must fail cleanly (llvmpipe's software "device" is skipped).
  auto ctx = createGlContext({.kind = ContextKind::EglDevice});
  if (ctx.ok()) {
    EXPECT_EQ((*ctx)->describe().rfind("EGL device", 0), 0u);
    EXPECT_EQ((*ctx)->describe().find("llvmpipe"), std::string::npos) << (*ctx)->describe();
  } else {
    EXPECT_EQ(ctx.error().message.rfind("EGL device", 0), 0u) << ctx.error().message;
  }
}

TEST(ContextGLTest, ImpossibleVersionFailsWithTheStep) {
  for (ContextKind kind : {ContextKind::EglSurfaceless, ContextKind::OSMesa, ContextKind::Headless}) {
    auto ctx = createGlContext({.kind = kind, .glMajor = 9, .glMinor = 9});
    ASSERT_FALSE(ctx.ok());
    const std::string& m = ctx.error().message;
    EXPECT_NE(m.find("9.9"), std::string::npos) << m;
  }
  // The failure names the EGL error code for the EGL platform.
  auto egl = createGlContext({.kind = ContextKind::EglSurfaceless, .glMajor = 9, .glMinor = 9});
  ASSERT_FALSE(egl.ok());
  EXPECT_NE(egl.error().message.find("EGL_"), std::string::npos) << egl.error().message;
}

TEST(ContextGLTest, WindowWithoutADisplayIsAnError) {
  auto ctx = createGlContext({.kind = ContextKind::Window, .width = 64, .height = 64});
  if (ctx.ok()) {
    EXPECT_EQ((*ctx)->describe().rfind("GLFW window", 0), 0u);
    EXPECT_NE((*ctx)->window(), nullptr);
  } else {
    EXPECT_EQ(ctx.error().message.rfind("GLFW", 0), 0u) << ctx.error().message;
  }
}

}  // namespace
}  // namespace tandem
