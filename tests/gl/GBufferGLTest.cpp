// The visibility G-buffer: ids match the geometry, reversed-Z depth is monotone and exact.
#include <gtest/gtest.h>

#include <cmath>

#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "gl/GpuScene.h"
#include "gl/VisibilityPass.h"

namespace tandem {
namespace {

struct RasterResult {
  std::vector<glm::uvec2> ids;  // top row first
  std::vector<float> depth;     // GL rows (bottom first)
};

RasterResult raster(const Scene& scene, int width, int height) {
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  EXPECT_TRUE(pass.ok()) << (pass.ok() ? "" : pass.error().message);
  RasterResult out;
  if (!pass.ok()) return out;
  EXPECT_TRUE(pass->resize(width, height).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));  // the GL copy is in render space
  pass->readIds(out.ids);
  out.depth.resize(static_cast<std::size_t>(width) * height);
  glGetTextureImage(pass->depth().id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    static_cast<GLsizei>(out.depth.size() * sizeof(float)), out.depth.data());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  return out;
}

TEST(GBufferGLTest, BoxHeadOnIds) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = gltest::boxScene();
  const int w = 64, h = 48;
  RasterResult r = raster(scene, w, h);
  ASSERT_EQ(r.ids.size(), std::size_t(w * h));
  // The centre sees the +Z face: triangles 8 and 9 of makeBox (faces +X, -X, +Y, -Y, +Z, -Z).
  glm::uvec2 centre = r.ids[(h / 2) * w + w / 2];
  EXPECT_EQ(centre.x, 1u);
  EXPECT_TRUE(centre.y == 8u || centre.y == 9u) << centre.y;
  // Corners are background.
  for (glm::ivec2 p : {glm::ivec2(0, 0), glm::ivec2(w - 1, 0), glm::ivec2(0, h - 1), glm::ivec2(w - 1, h - 1)})
    EXPECT_EQ(r.ids[p.y * w + p.x], glm::uvec2(0u, 0u)) << p.x << "," << p.y;
  // The visible face covers about the projected square: half-size 0.5 at distance 3.5, fov 45°.
  float halfPixels = 0.5f / 3.5f / std::tan(glm::radians(22.5f)) * (h / 2.0f);
  int covered = 0;
  for (const glm::uvec2& id : r.ids) covered += id.x == 1u;
  float expected = (2 * halfPixels) * (2 * halfPixels);
  EXPECT_NEAR(float(covered), expected, expected * 0.08f);
  // Row 0 is the top: the face's top edge is where the upper background ends.
  EXPECT_EQ(r.ids[2 * w + w / 2].x, 0u);
}

TEST(GBufferGLTest, InstancesAndPrimitiveIdsRestartPerInstance) {
  TD_REQUIRE_GL_CONTEXT();
  // Two boxes side by side, sharing one mesh, plus a plane behind: all drawn by one multi-draw.
  Scene scene = gltest::boxScene();
  scene.meshes.push_back(makePlane(glm::vec2(20.0f), 1));
  Instance left, right, wall;
  left.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-0.8f, 0.0f, 0.0f));
  right.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.8f, 0.0f, 0.0f));
  wall.mesh = 1;
  wall.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -2.0f)) *
                         glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1.0f, 0.0f, 0.0f));
  scene.instances = {wall, left, right};
  const int w = 96, h = 48;
  RasterResult r = raster(scene, w, h);
  ASSERT_EQ(r.ids.size(), std::size_t(w * h));
  glm::uvec2 l = r.ids[(h / 2) * w + w / 2 - 13];
  glm::uvec2 rr = r.ids[(h / 2) * w + w / 2 + 13];
  EXPECT_EQ(l.x, 2u);
  EXPECT_EQ(rr.x, 3u);
  // gl_PrimitiveID counts from 0 in every instance's draw, not across the multi-draw.
  EXPECT_TRUE(l.y == 8u || l.y == 9u) << l.y;
  EXPECT_TRUE(rr.y == 8u || rr.y == 9u) << rr.y;
  glm::uvec2 behind = r.ids[2 * w + 2];
  EXPECT_EQ(behind.x, 1u);
  EXPECT_LT(behind.y, 2u);
}

TEST(GBufferGLTest, ReversedZDepthIsMonotoneAndExact) {
  TD_REQUIRE_GL_CONTEXT();
  // A floor seen at a slant: depth falls from the bottom row (near) to the horizon (far).
  Scene scene = gltest::boxScene();
  scene.meshes = {makePlane(glm::vec2(2000.0f), 1)};
  scene.camera.posW = {0.0f, 1.0f, 0.0f};
  scene.camera.targetW = {0.0f, 0.8f, -10.0f};
  scene.camera.nearZ = 0.01f;
  const int w = 32, h = 200;
  RasterResult r = raster(scene, w, h);
  ASSERT_EQ(r.depth.size(), std::size_t(w * h));
  int x = w / 2;
  int floorRows = 0;
  float previous = 2.0f;
  for (int y = 0; y < h; ++y) {  // GL row 0 = bottom of the image = nearest floor
    float d = r.depth[static_cast<std::size_t>(y) * w + x];
    if (d == 0.0f) break;       // the sky: cleared to the far value
    EXPECT_LT(d, previous) << "row " << y;
    EXPECT_GT(d, 0.0f);
    EXPECT_LE(d, 1.0f);
    previous = d;
    ++floorRows;
  }
  EXPECT_GT(floorRows, h / 3);
  // Infinite reversed-Z: depth = near / view distance along -Z. Check the pixel at the image centre
  // column, bottom row, against the ray's hit on the plane y = 0.
  Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(h) - 0.5f}, {w, h});
  float t = -ray.origin.y / ray.dir.y;
  glm::vec3 hitW = ray.origin + t * ray.dir;
  float viewZ = -(scene.camera.viewFromWorld() * glm::vec4(hitW, 1.0f)).z;
  float expected = scene.camera.nearZ / viewZ;
  EXPECT_NEAR(r.depth[x], expected, expected * 1e-3f);
}

TEST(GBufferGLTest, FarAwaySceneKeepsItsIds) {
  TD_REQUIRE_GL_CONTEXT();
  // Translated 1e5: camera-relative transforms keep the box where it belongs.
  Scene scene = gltest::boxScene();
  glm::vec3 offset(1e5f, 0.0f, 1e5f);
  scene.instances[0].worldFromObject = glm::translate(glm::mat4(1.0f), offset);
  scene.camera.posW += offset;
  scene.camera.targetW += offset;
  const int w = 64, h = 48;
  RasterResult far = raster(scene, w, h);
  RasterResult near = raster(gltest::boxScene(), w, h);
  int differing = 0;
  for (std::size_t i = 0; i < near.ids.size(); ++i) differing += far.ids[i].x != near.ids[i].x;
  EXPECT_LE(differing, 2 * w);  // at most a row of silhouette pixels may flip
}

// The ids' read-back in two halves (gl/PixelReadback.h, throughput mode's): what finish() gives is the ids
// texture as it was when start() was called, row 0 at the top, even when the pass draws something else in
// between, at each of three sizes.
TEST(GBufferGLTest, SplitReadBackIsTheTextureAtItsStartTopRowFirst) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = gltest::boxScene();
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok()) << pass.error().message;
  for (glm::ivec2 size : {glm::ivec2(64, 48), glm::ivec2(37, 29), glm::ivec2(96, 54)}) {
    SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y));
    const int w = size.x, h = size.y;
    ASSERT_TRUE(pass->resize(w, h).ok());
    const Camera camera = toRenderSpace(scene.camera, gpu.anchor());
    pass->render(gpu, camera);
    // The texture itself, bottom row first as GL stores it.
    std::vector<glm::uvec2> texels(static_cast<std::size_t>(w) * h);
    glGetTextureImage(pass->ids().id(), 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                      static_cast<GLsizei>(texels.size() * sizeof(glm::uvec2)), texels.data());
    pass->startReadIds();
    EXPECT_TRUE(pass->readingIds());
    // Another view drawn into the same pass before the read-back is finished.
    Camera away = camera;
    away.posW += glm::vec3(3.0f, 0.0f, 0.0f);
    pass->render(gpu, away);
    std::vector<glm::uvec2> ids;
    pass->finishReadIds(ids);
    EXPECT_FALSE(pass->readingIds());
    ASSERT_EQ(ids.size(), texels.size());
    std::size_t differ = 0, covered = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::uvec2 got = ids[static_cast<std::size_t>(y) * w + x];
        differ += got != texels[static_cast<std::size_t>(h - 1 - y) * w + x] ? 1 : 0;
        covered += got.x != 0 ? 1 : 0;
      }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(covered, 0u);
    EXPECT_LT(covered, ids.size()) << "the box and the background both in view";
    // The whole read again now: the view drawn second, which differs.
    std::vector<glm::uvec2> after;
    pass->readIds(after);
    EXPECT_NE(after, ids);
  }
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace
}  // namespace tandem
