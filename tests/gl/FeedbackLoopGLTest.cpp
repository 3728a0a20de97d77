// Rendering feedback loops (GL 4.5 core, 9.3): the check itself finds a sampled texture attached to the
// draw framebuffer (colour or depth, at a sampled mip level) and nothing else, and no pass of any frame
// samples its own target: the toon outlines and the depth view read the visibility depth that the shade
// pass keeps attached for its early depth test.
#include <gtest/gtest.h>

#include "GlTestUtil.h"
#include "gl/FeedbackLoop.h"
#include "gl/GlObjects.h"
#include "gl/Program.h"
#include "tandem/SceneFile.h"

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

// Every pass of every frame below runs under the check; the report must show draws and no loop.
void expectNoLoops(Renderer& renderer, const Camera& camera, const FrameSettings& settings, const char* what) {
  gl::takeFeedbackLoopReport();
  renderer.render(camera, settings);
  gl::FeedbackLoopReport report = gl::takeFeedbackLoopReport();
  EXPECT_GE(report.draws, 2u) << what << ": the passes did not run the check";
  for (const std::string& loop : report.loops) ADD_FAILURE() << what << ": " << loop;
  EXPECT_FALSE(renderer.readImage().rgba.empty()) << what;
}

struct ChecksOn {
  ChecksOn() { gl::setFeedbackLoopChecks(true); }
  ~ChecksOn() { gl::setFeedbackLoopChecks(false); }
};

TEST(FeedbackLoopGLTest, NoPassSamplesItsOwnTarget) {
  TD_REQUIRE_GL_CONTEXT();
  ChecksOn checks;
  auto scene = loadDefaultScene();
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  Camera camera = scene->camera;
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_NE(renderer, nullptr);
  ASSERT_TRUE(renderer->setScene(std::move(*scene)).ok());

  // Toon with raster shadows and reflection probes: the probe faces are shaded (toon outlines
  // included) by the same pass into their own targets.
  FrameSettings toon = *presetSettings("raster");
  toon.width = 160;
  toon.height = 90;
  toon.shadingOverride = ShadingModel::Toon;
  expectNoLoops(*renderer, camera, toon, "raster preset, toon");
  FrameSettings depthView = toon;
  depthView.shadingOverride = ShadingModel::Phong;
  depthView.debugView = DebugView::Depth;
  expectNoLoops(*renderer, camera, depthView, "depth view");
  FrameSettings hybridToon = *presetSettings("hybrid-fast");
  hybridToon.width = 160;
  hybridToon.height = 90;
  hybridToon.shadingOverride = ShadingModel::Toon;
  expectNoLoops(*renderer, camera, hybridToon, "hybrid-fast, toon");
}

}  // namespace
}  // namespace tandem
