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
  for (const std::string& problem : report.samplers) ADD_FAILURE() << what << ": " << problem;
  EXPECT_FALSE(renderer.readImage().rgba.empty()) << what;
}

// (The shared context turns the checks on for every GL test; this says so where they are the subject.)
struct ChecksOn {
  ChecksOn() { gl::setFeedbackLoopChecks(true); }
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

namespace tandem {
namespace {

// A program with a shadow sampler, an unsigned-integer sampler and a float sampler, compiled here.
GLuint samplerTestProgram() {
  const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
  const char* fs =
      "#version 450 core\n"
      "layout(binding = 3) uniform sampler2DArrayShadow shadows;\n"
      "layout(binding = 4) uniform usampler2D ids;\n"
      "layout(binding = 5) uniform sampler2D colour;\n"
      "out vec4 o;\n"
      "void main() { o = vec4(texture(shadows, vec4(0.5, 0.5, 0.0, 0.5)) + float(texelFetch(ids, ivec2(0), 0).x) +\n"
      "                       texture(colour, vec2(0.5)).x); }\n";
  GLuint program = glCreateProgram();
  for (auto [stage, text] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
    GLuint s = glCreateShader(stage);
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    glAttachShader(program, s);
    glDeleteShader(s);
  }
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  EXPECT_EQ(linked, GL_TRUE);
  return program;
}

// Whether one of `problems` mentions both strings.
bool mentions(const std::vector<std::string>& problems, const std::string& sampler, const std::string& what) {
  for (const std::string& p : problems)
    if (p.find("'" + sampler + "'") != std::string::npos && p.find(what) != std::string::npos) return true;
  return false;
}

TEST(FeedbackLoopGLTest, FindsSamplersThatReadWhatTheyMustNot) {
  // What NVIDIA's driver calls undefined behaviour and llvmpipe lets pass: the passes check for it before
  // every draw (gl/FeedbackLoop.h), so the tests fail on it here too.
  TD_REQUIRE_GL_CONTEXT();
  const GLuint program = samplerTestProgram();
  glUseProgram(program);
  for (GLuint unit : {3u, 4u, 5u}) glBindTextureUnit(unit, 0);
  std::vector<std::string> problems = gl::findSamplerProblems();
  EXPECT_TRUE(mentions(problems, "shadows", "no texture of its type bound")) << ::testing::PrintToString(problems);
  EXPECT_TRUE(mentions(problems, "ids", "no texture of its type bound"));
  EXPECT_TRUE(mentions(problems, "colour", "no texture of its type bound"));

  gl::Texture colourArray = gl::createTexture2DArray("colour array", GL_RGBA8, 2, 2, 1, 1);
  gl::Texture depthArray = gl::createTexture2DArray("depth array", GL_DEPTH_COMPONENT32F, 2, 2, 1, 1);
  gl::Texture uintLinear = gl::createTexture2D("uint linear", GL_R32UI, 2, 2);
  gl::Texture colour = gl::createTexture2D("colour", GL_RGBA8, 2, 2);
  gl::Texture depth = gl::createTexture2D("depth", GL_DEPTH_COMPONENT32F, 2, 2);
  for (const gl::Texture* t : {&colourArray, &depthArray, &colour, &depth}) gl::setSampling(*t, GL_NEAREST, GL_NEAREST);
  gl::setSampling(uintLinear, GL_LINEAR, GL_LINEAR);
  glBindTextureUnit(3, colourArray.id());
  glBindTextureUnit(4, uintLinear.id());
  glBindTextureUnit(5, depth.id());
  glTextureParameteri(depth.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  problems = gl::findSamplerProblems();
  EXPECT_TRUE(mentions(problems, "shadows", "has no depth format")) << ::testing::PrintToString(problems);
  EXPECT_TRUE(mentions(problems, "ids", "linear filtering"));
  EXPECT_TRUE(mentions(problems, "colour", "depth comparison on"));

  glBindTextureUnit(3, depthArray.id());  // depth, but comparing nothing
  glBindTextureUnit(4, colour.id());      // a float format for an unsigned-integer sampler
  problems = gl::findSamplerProblems();
  EXPECT_TRUE(mentions(problems, "shadows", "compares no depths")) << ::testing::PrintToString(problems);
  EXPECT_TRUE(mentions(problems, "ids", "another kind of format"));

  // Each fixed: nothing to say.
  glTextureParameteri(depthArray.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  gl::setSampling(uintLinear, GL_NEAREST, GL_NEAREST);
  glBindTextureUnit(4, uintLinear.id());
  glTextureParameteri(depth.id(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
  EXPECT_TRUE(gl::findSamplerProblems().empty()) << ::testing::PrintToString(gl::findSamplerProblems());

  // Before a draw the check reports what it finds as a KHR_debug message of type undefined behaviour, which
  // fails a GL test (GlTestUtil.h) unless it expects it.
  // (Where assertions are on, the check asserts instead: not run there.)
#ifdef NDEBUG
  glBindTextureUnit(5, 0);
  {
    gltest::ExpectGlDebug expected("sampler 'colour' (unit 5) has no texture of its type bound");
    gl::assertNoFeedbackLoop("sampler test");
    EXPECT_EQ(expected.seen(), 1);
  }
  gl::takeFeedbackLoopReport();
#endif
  for (GLuint unit : {3u, 4u, 5u}) glBindTextureUnit(unit, 0);
  glUseProgram(0);
  glDeleteProgram(program);
}

}  // namespace
}  // namespace tandem
