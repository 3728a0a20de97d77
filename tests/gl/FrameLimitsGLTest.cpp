// Frames the GL cannot hold are errors naming the limit or the refused allocation, never black frames:
// the limit check itself, the allocation helper's GL-error path, Renderer::resize beyond the driver's
// queried limit, and (on llvmpipe, which refuses any texture over 2 GiB without allocating it) render()
// at a size whose radiance target the driver refuses. No test allocates a large frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "GlTestUtil.h"
#include "gl/FrameLimits.h"
#include "gl/GlObjects.h"

namespace tandem {
namespace {

gl::FrameLimits uniformLimits(int n) { return {n, n, n, n, n}; }

TEST(FrameLimitsTest, NamesTheFirstLimitExceeded) {
  EXPECT_TRUE(gl::checkFrameLimits(16384, 16384, uniformLimits(16384)).ok());
  auto wide = gl::checkFrameLimits(16385, 1, uniformLimits(16384));
  ASSERT_FALSE(wide.ok());
  EXPECT_EQ(wide.error().message, "width 16385 exceeds GL_MAX_TEXTURE_SIZE = 16384");
  auto tall = gl::checkFrameLimits(1, 16385, uniformLimits(16384));
  ASSERT_FALSE(tall.ok());
  EXPECT_EQ(tall.error().message, "height 16385 exceeds GL_MAX_TEXTURE_SIZE = 16384");

  gl::FrameLimits l = uniformLimits(32768);
  l.maxFramebufferHeight = 8192;
  auto fbo = gl::checkFrameLimits(100, 9000, l);
  ASSERT_FALSE(fbo.ok());
  EXPECT_EQ(fbo.error().message, "height 9000 exceeds GL_MAX_FRAMEBUFFER_HEIGHT = 8192");
  l = uniformLimits(32768);
  l.maxViewportWidth = 4096;
  auto viewport = gl::checkFrameLimits(4097, 10, l);
  ASSERT_FALSE(viewport.ok());
  EXPECT_EQ(viewport.error().message, "width 4097 exceeds GL_MAX_VIEWPORT_DIMS[0] = 4096");
}

TEST(FrameLimitsGLTest, AllocationHelperNamesTheGlError) {
  // A real GL error from glTextureStorage2D without a large allocation: a side the driver does not allow.
  TD_REQUIRE_GL_CONTEXT();
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  gltest::ExpectGlDebug invalid("GL_INVALID_VALUE");  // the error this test provokes, and no other
  auto texture = gl::tryCreateTexture2D("too wide", GL_R32UI, maxSize + 1, 1);
  ASSERT_FALSE(texture.ok());
  EXPECT_EQ(invalid.seen(), 1) << "the driver's debug output reports the GL error";
  const std::string& m = texture.error().message;
  EXPECT_NE(m.find("'too wide' (" + std::to_string(maxSize + 1) + "x1 GL_R32UI"), std::string::npos) << m;
  EXPECT_NE(m.find("failed with GL_INVALID_VALUE"), std::string::npos) << m;
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << "the helper leaves no error behind";
  auto fine = gl::tryCreateTexture2D("fine", GL_R32UI, 4, 4);
  EXPECT_TRUE(fine.ok());

  gl::Framebuffer empty = gl::createFramebuffer("no attachments");
  auto complete = gl::checkFramebufferComplete(empty, "no attachments");
  ASSERT_FALSE(complete.ok());
  EXPECT_EQ(complete.error().message,
            "GL framebuffer 'no attachments' is incomplete: GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT");
}

TEST(FrameLimitsGLTest, ResizeBeyondTheDriverLimitNamesIt) {
  TD_REQUIRE_GL_CONTEXT();
  gl::FrameLimits limits = gl::queryFrameLimits();
  int widest = std::min({limits.maxTextureSize, limits.maxFramebufferWidth, limits.maxViewportWidth});
  const char* name = widest == limits.maxTextureSize        ? "GL_MAX_TEXTURE_SIZE"
                     : widest == limits.maxFramebufferWidth ? "GL_MAX_FRAMEBUFFER_WIDTH"
                                                            : "GL_MAX_VIEWPORT_DIMS[0]";
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_NE(renderer, nullptr);
  ASSERT_TRUE(renderer->setScene(gltest::boxScene()).ok());
  std::size_t objects = renderer->resources().glObjects;
  auto refused = renderer->resize(widest + 1, 16);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message,
            "width " + std::to_string(widest + 1) + " exceeds " + name + " = " + std::to_string(widest));
  EXPECT_LE(renderer->resources().glObjects, objects) << "nothing allocated for a size over the limit";
  EXPECT_TRUE(renderer->readImage().rgba.empty());
  EXPECT_FALSE(renderer->resize(0, 16).ok());

  // The renderer carries on at a size the GL holds.
  ASSERT_TRUE(renderer->resize(64, 48).ok());
  FrameStats stats = renderer->render(renderer->scene().camera, gltest::rasterOnly(64, 48));
  EXPECT_TRUE(stats.error.empty()) << stats.error;
  Image image = renderer->readImage();
  EXPECT_EQ(image.width, 64);
  EXPECT_EQ(image.rgba.size(), std::size_t(64 * 48 * 4));
}

long residentMiB() {
  long pages = 0, resident = 0;
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return -1;
  if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = -1;
  std::fclose(f);
  return resident * 4096 / (1024 * 1024);
}

TEST(FrameLimitsGLTest, RefusedAllocationIsAFrameErrorNotABlackFrame) {
  // The reported failure: 16384x16384 on llvmpipe, within every size limit, but its 4 GiB RGBA32F
  // radiance target is over the 2 GiB llvmpipe allocates for one texture. llvmpipe refuses that before
  // allocating, and the renderer asks for it first, so this costs no memory. Other drivers have other
  // (unqueryable) memory caps, and a GPU with the memory would really allocate the frame: not run there.
  TD_REQUIRE_GL_CONTEXT();
  std::string rendererName = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (rendererName.find("llvmpipe") == std::string::npos)
    GTEST_SKIP() << "needs llvmpipe's 2 GiB cap on one texture; the GL here is " << rendererName;
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_NE(renderer, nullptr);
  ASSERT_TRUE(renderer->setScene(gltest::boxScene()).ok());
  long before = residentMiB();
  gltest::ExpectGlDebug outOfMemory("GL_OUT_OF_MEMORY");  // the refusal this test provokes, and no other
  FrameStats stats = renderer->render(renderer->scene().camera, gltest::rasterOnly(kMaxFrameSide, kMaxFrameSide));
  EXPECT_LT(residentMiB() - before, 256) << "the refused frame allocated memory";
  EXPECT_EQ(stats.error, "frame 16384x16384: the frame's GL targets need 8192.0 MiB; GL texture 'linear radiance' "
                         "(16384x16384 GL_RGBA32F, 4096.0 MiB): glTextureStorage2D failed with GL_OUT_OF_MEMORY");
  EXPECT_TRUE(renderer->readImage().rgba.empty()) << "no image pretends to be the frame";
  // Asked again, render() reports the same without trying; resize() tries again and says the same.
  EXPECT_EQ(renderer->render(renderer->scene().camera, gltest::rasterOnly(kMaxFrameSide, kMaxFrameSide)).error,
            stats.error);
  auto again = renderer->resize(kMaxFrameSide, kMaxFrameSide);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ("frame 16384x16384: " + again.error().message, stats.error);
  EXPECT_EQ(outOfMemory.seen(), 2) << "the driver reports each refused allocation";

  FrameStats small = renderer->render(renderer->scene().camera, gltest::rasterOnly(64, 48));
  EXPECT_TRUE(small.error.empty()) << small.error;
  EXPECT_EQ(renderer->readImage().width, 64);
}

}  // namespace
}  // namespace tandem
