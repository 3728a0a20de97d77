// Rendering feedback loops (GL 4.5 core, 9.3): the check finds a sampled texture attached to the draw
// framebuffer (colour or depth, at a sampled mip level) and nothing else.
#include <gtest/gtest.h>

#include "GlTestUtil.h"
#include "gl/FeedbackLoop.h"
#include "gl/GlObjects.h"
#include "gl/Program.h"

namespace tandem {
namespace {

// The tone-map program samples `linearColor` on unit 0; the framebuffer gets `target` at `point`.
struct LoopFixture {
  gl::Program program;
  gl::Framebuffer fbo;

  bool build() {
    auto built = gl::buildProgram("feedback test", {{GL_VERTEX_SHADER, "shaders/fullscreen.vert"},
                                                    {GL_FRAGMENT_SHADER, "shaders/tonemap.frag"}});
    EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.error().message);
    if (!built.ok()) return false;
    program = std::move(*built);
    fbo = gl::createFramebuffer("feedback test target");
    return true;
  }
  std::vector<std::string> loopsWith(GLuint sampled) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
    glUseProgram(program.id());
    glBindTextureUnit(0, sampled);
    std::vector<std::string> loops = gl::findFeedbackLoops();
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glBindTextureUnit(0, 0);
    return loops;
  }
};

TEST(FeedbackLoopGLTest, FindsASampledColourAttachment) {
  TD_REQUIRE_GL_CONTEXT();
  LoopFixture f;
  ASSERT_TRUE(f.build());
  gl::Texture target = gl::createTexture2D("loop colour", GL_RGBA8, 8, 8);
  gl::Texture other = gl::createTexture2D("other colour", GL_RGBA8, 8, 8);
  gl::setSampling(target, GL_NEAREST, GL_NEAREST);
  glNamedFramebufferTexture(f.fbo.id(), GL_COLOR_ATTACHMENT0, target.id(), 0);

  std::vector<std::string> loops = f.loopsWith(target.id());
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_NE(loops[0].find("'linearColor' (unit 0)"), std::string::npos) << loops[0];
  EXPECT_NE(loops[0].find("'loop colour'"), std::string::npos) << loops[0];
  EXPECT_NE(loops[0].find("GL_COLOR_ATTACHMENT0"), std::string::npos) << loops[0];
  EXPECT_TRUE(f.loopsWith(other.id()).empty());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(FeedbackLoopGLTest, FindsASampledReadOnlyDepthAttachment) {
  // What the shade pass did: depth attached for the depth test only (no writes), and sampled.
  TD_REQUIRE_GL_CONTEXT();
  LoopFixture f;
  ASSERT_TRUE(f.build());
  gl::Texture colour = gl::createTexture2D("colour", GL_RGBA8, 8, 8);
  gl::Texture depth = gl::createTexture2D("loop depth", GL_DEPTH_COMPONENT32F, 8, 8);
  gl::setSampling(depth, GL_NEAREST, GL_NEAREST);
  glNamedFramebufferTexture(f.fbo.id(), GL_COLOR_ATTACHMENT0, colour.id(), 0);
  glNamedFramebufferTexture(f.fbo.id(), GL_DEPTH_ATTACHMENT, depth.id(), 0);
  glDepthMask(GL_FALSE);
  std::vector<std::string> loops = f.loopsWith(depth.id());
  glDepthMask(GL_TRUE);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_NE(loops[0].find("GL_DEPTH_ATTACHMENT"), std::string::npos) << loops[0];
  EXPECT_NE(loops[0].find("'loop depth'"), std::string::npos) << loops[0];
}

TEST(FeedbackLoopGLTest, MipLevelsCountOnlyWhenSampled) {
  // Rendering into level 1 while sampling level 0 alone is defined; a mipmapping filter reads level 1 too.
  TD_REQUIRE_GL_CONTEXT();
  LoopFixture f;
  ASSERT_TRUE(f.build());
  gl::Texture target = gl::createTexture2D("mipmapped", GL_RGBA8, 8, 8, 2);
  gl::setSampling(target, GL_NEAREST, GL_NEAREST);
  glNamedFramebufferTexture(f.fbo.id(), GL_COLOR_ATTACHMENT0, target.id(), 1);
  EXPECT_TRUE(f.loopsWith(target.id()).empty());
  glTextureParameteri(target.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
  EXPECT_EQ(f.loopsWith(target.id()).size(), 1u);
}

}  // namespace
}  // namespace tandem
