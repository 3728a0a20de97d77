// The motion view (DebugView::Motion, docs/motion.md) against closed forms: a wall facing a pinhole camera
// with a box in front of it. A sideways camera move of dx shifts every point at distance z by dx·f/z pixels
// (f = half the frame height / tan(fov/2)); an instance moved by dy shifts its own pixels by dy·f/z and no
// other; the wall pixels the box uncovers, and only those, are marked as not seen the frame before. The same
// far from the origin, and in throughput mode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "GlTestUtil.h"
#include "gl/GlObjects.h"
#include "tandem/Primitives.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 90;
constexpr float kFovDeg = 45.0f;
constexpr float kWallZ = 0.0f, kBoxFront = 1.25f, kCameraZ = 5.0f;  // the box: 0.5 wide, centred at z = 1

// Pixels per world unit of sideways motion at distance z.
double pixelsPerUnit(double z) { return (kH / 2.0) / std::tan(glm::radians(kFovDeg) / 2.0) / z; }

Scene wallAndBox(glm::dvec3 offset) {
  Scene s;
  s.name = "wall and box";
  Mesh wall = makePlane(glm::vec2(40.0f), 1);  // XZ, facing +Y: turned to face +Z below
  s.meshes.push_back(std::move(wall));
  s.meshes.push_back(makeBox(glm::vec3(0.5f)));
  s.materials.push_back(gltest::plainMaterial(glm::vec3(0.7f)));
  Instance w;
  w.name = "wall";
  w.mesh = 0;
  w.worldFromObject = glm::mat4(glm::translate(glm::dmat4(1.0), offset + glm::dvec3(0.0, 0.0, kWallZ)) *
                                glm::rotate(glm::dmat4(1.0), glm::radians(90.0), glm::dvec3(1.0, 0.0, 0.0)));
  s.instances.push_back(w);
  Instance b;
  b.name = "box";
  b.mesh = 1;
  b.worldFromObject = glm::mat4(glm::translate(glm::dmat4(1.0), offset + glm::dvec3(0.0, 0.0, 1.0)));
  s.instances.push_back(b);
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.intensity = 1.0f;
  s.lights.push_back(ambient);
  Light point;  // a light that casts shadows: the frame has a ray pass (throughput mode overlaps nothing else)
  point.type = LightType::Point;
  point.posW = glm::vec3(offset + glm::dvec3(1.0, 2.0, 4.0));
  point.intensity = 1.0f;
  s.lights.push_back(point);
  s.camera.posW = glm::vec3(offset + glm::dvec3(0.0, 0.0, kCameraZ));
  s.camera.targetW = glm::vec3(offset);
  s.camera.yFovDeg = kFovDeg;
  s.background = {0.1f, 0.2f, 0.3f};
  return s;
}

struct Motion {
  std::vector<glm::vec2> px;   // pixels, GL rows (y up): this frame's position less the last frame's
  std::vector<bool> unseen;    // not seen the frame before
  std::vector<std::uint32_t> instance;  // 1 wall, 2 box (instance + 1)
  glm::vec2 at(int x, int y) const { return px[static_cast<std::size_t>(y) * kW + x]; }
};

FrameSettings motionSettings() {
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = kW;
  s.height = kH;
  s.debugView = DebugView::Motion;
  return s;
}

// The linear frame of the motion view decoded, with each pixel's instance from the instance view's colours
// being unnecessary: the wall fills the view, so a pixel is the box's where the box's closed form says.
Motion decode(Renderer& r) {
  const ImageF lin = r.readLinear();
  Motion m;
  m.px.resize(lin.rgb.size());
  m.unseen.resize(lin.rgb.size());
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      // readLinear is top row first; the view's y runs up as GL's rows do.
      const glm::vec3 v = lin.at(x, kH - 1 - y);
      m.px[static_cast<std::size_t>(y) * kW + x] = (glm::vec2(v) - 0.5f) * 64.0f;
      m.unseen[static_cast<std::size_t>(y) * kW + x] = v.z > 0.5f;
    }
  return m;
}

// The box's front face in GL pixels for a camera at camX and the box at boxY (world, relative to the offset).
glm::dvec4 boxRect(double camX, double boxY) {
  const double k = pixelsPerUnit(kCameraZ - kBoxFront);
  const double cx = kW / 2.0 + (0.0 - camX) * k, cy = kH / 2.0 + boxY * k;
  return {cx - 0.25 * k, cy - 0.25 * k, cx + 0.25 * k, cy + 0.25 * k};
}
bool inside(glm::dvec4 r, int x, int y, double margin) {
  return x + 0.5 > r.x + margin && x + 0.5 < r.z - margin && y + 0.5 > r.y + margin && y + 0.5 < r.w - margin;
}
bool near(glm::dvec4 r, int x, int y, double margin) {
  return x + 0.5 > r.x - margin && x + 0.5 < r.z + margin && y + 0.5 > r.y - margin && y + 0.5 < r.w + margin;
}

// Frames: the first (no history), then `change` applied and a second; the second's motion is returned.
Motion twoFrames(Renderer& r, Scene& scene, const std::function<void(Renderer&, Camera&)>& change, bool pipelined,
                 int samples = 1) {
  FrameSettings s = motionSettings();
  s.pipelined = pipelined;
  if (samples > 1) s.aa = AntiAlias::Ssaa, s.aaSamples = samples;
  Camera camera = scene.camera;
  EXPECT_TRUE(r.setScene(scene).ok());
  FrameStats first = r.render(camera, s);
  EXPECT_TRUE(first.error.empty()) << first.error;
  if (!pipelined) {
    const Motion m = decode(r);
    std::size_t unseen = 0;
    for (bool u : m.unseen) unseen += u ? 1 : 0;
    EXPECT_EQ(unseen, m.unseen.size()) << "the first frame has no last frame: every pixel is new";
  }
  change(r, camera);
  FrameStats second = r.render(camera, s);
  EXPECT_TRUE(second.error.empty()) << second.error;
  if (pipelined) {
    EXPECT_TRUE(second.pipelined);
    EXPECT_TRUE(r.finish().has_value());
  }
  return decode(r);
}

void checkCameraMove(GlContext& context, glm::dvec3 offset, bool pipelined, int samples = 1) {
  auto r = gltest::makeRenderer(context);
  ASSERT_TRUE(r);
  Scene scene = wallAndBox(offset);
  constexpr double dx = 0.1;
  const Motion m = twoFrames(*r, scene, [&](Renderer&, Camera& c) {
    c.posW.x += static_cast<float>(dx);
    c.targetW.x += static_cast<float>(dx);
  }, pipelined, samples);
  // The camera's x as the float it is (far away the step rounds to what the float holds).
  gltest::savePng(std::string("motion-camera") + (offset == glm::dvec3(0.0) ? "" : "-far") + (pipelined ? "-pipelined" : "") + ".png",
                  r->readImage());
  const double stepX = static_cast<double>(static_cast<float>(offset.x + dx)) - static_cast<double>(static_cast<float>(offset.x));
  const double wallShift = -stepX * pixelsPerUnit(kCameraZ - kWallZ), boxShift = -stepX * pixelsPerUnit(kCameraZ - kBoxFront);
  const glm::dvec4 box = boxRect(stepX, 0.0), boxBefore = boxRect(0.0, 0.0);
  int wall = 0, front = 0, unseen = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const glm::vec2 v = m.at(x, y);
      const bool u = m.unseen[static_cast<std::size_t>(y) * kW + x];
      if (inside(box, x, y, 1.0)) {
        EXPECT_NEAR(v.x, boxShift, 2e-3) << x << "," << y;
        EXPECT_NEAR(v.y, 0.0, 2e-3) << x << "," << y;
        EXPECT_FALSE(u) << x << "," << y;
        ++front;
      } else if (!near(box, x, y, 1.0) && !near(boxBefore, x, y, 1.0) && x + 0.5 - wallShift < kW - 1.0) {
        EXPECT_NEAR(v.x, wallShift, 2e-3) << x << "," << y;
        EXPECT_NEAR(v.y, 0.0, 2e-3) << x << "," << y;
        EXPECT_FALSE(u) << x << "," << y;
        ++wall;
      }
      // New in view: the wall beside the box's silhouette that the box uncovered, and the columns the move
      // brought in at the frame's edge (their last position lay off the frame).
      const bool cameFromOffFrame = x + 0.5 - wallShift >= kW - 1.0 || x + 0.5 - wallShift < 1.0;
      if (u) {
        ++unseen;
        EXPECT_TRUE((near(box, x, y, 2.0) && !inside(box, x, y, 1.0)) || cameFromOffFrame)
            << "marked unseen away from the box and the frame's edge: " << x << "," << y;
      } else if (x + 0.5 - wallShift >= kW + 1.0) {
        ADD_FAILURE() << "came from off the frame but marked seen: " << x << "," << y;
      }
    }
  EXPECT_GT(front, 100);
  EXPECT_GT(wall, 10000);
  EXPECT_GT(unseen, 0) << "the box's move uncovers a sliver of wall";
}

TEST(MotionGLTest, ACameraMoveShiftsEachPointByItsDepthsClosedForm) {
  TD_REQUIRE_GL_CONTEXT();
  checkCameraMove(*glContext_, glm::dvec3(0.0), false);
}

TEST(MotionGLTest, ACameraMoveFarFromTheOriginIsTheSame) {
  TD_REQUIRE_GL_CONTEXT();
  checkCameraMove(*glContext_, glm::dvec3(1e6, -2e5, 1e6), false);
}

TEST(MotionGLTest, ThroughputModeMeasuresFromTheFrameBeforeToo) {
  TD_REQUIRE_GL_CONTEXT();
  checkCameraMove(*glContext_, glm::dvec3(0.0), true);
}

// A frame of several jittered samples: each measures from the frame before (not from the sample before it),
// unjittered, so their mean is the one-sample motion.
TEST(MotionGLTest, EverySampleOfAFrameMovesFromTheFrameBefore) {
  TD_REQUIRE_GL_CONTEXT();
  checkCameraMove(*glContext_, glm::dvec3(0.0), false, 4);
}

TEST(MotionGLTest, AnInstanceMovesItsOwnPixelsAndUncoversTheWallBehind) {
  TD_REQUIRE_GL_CONTEXT();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r);
  Scene scene = wallAndBox(glm::dvec3(0.0));
  constexpr double dy = 0.2;
  const Motion m = twoFrames(*r, scene, [&](Renderer& rr, Camera&) {
    scene.instances[1].worldFromObject =
        glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, static_cast<float>(dy), 0.0f)) * scene.instances[1].worldFromObject;
    rr.setInstanceTransform(1, scene.instances[1].worldFromObject);
  }, false);
  gltest::savePng("motion-instance.png", r->readImage());
  const double boxShift = dy * pixelsPerUnit(kCameraZ - kBoxFront);
  const glm::dvec4 now = boxRect(0.0, dy), before = boxRect(0.0, 0.0);
  int front = 0, uncovered = 0, wall = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const glm::vec2 v = m.at(x, y);
      const bool u = m.unseen[static_cast<std::size_t>(y) * kW + x];
      if (inside(now, x, y, 1.0)) {
        EXPECT_NEAR(v.x, 0.0, 2e-3) << x << "," << y;
        EXPECT_NEAR(v.y, boxShift, 2e-3) << x << "," << y;
        EXPECT_FALSE(u) << "each point of the box's front was on it the frame before: " << x << "," << y;
        ++front;
      } else if (!near(now, x, y, 1.0)) {
        EXPECT_EQ(v, glm::vec2(0.0f)) << "the wall and the camera stood still: exactly no motion at " << x << "," << y;
        if (inside(before, x, y, 1.0)) {
          EXPECT_TRUE(u) << "the wall the box uncovered: " << x << "," << y;
          ++uncovered;
        } else if (!near(before, x, y, 1.0)) {
          EXPECT_FALSE(u) << x << "," << y;
          ++wall;
        }
      }
    }
  EXPECT_GT(front, 100);
  EXPECT_GT(uncovered, 20);
  EXPECT_GT(wall, 10000);
}

// Three frames, the camera stepping 0.1 then 0.2: the third frame's motion is the second step's, in both
// modes (a frame measured from any but the one composited just before it would show 0.3 or 0.1).
TEST(MotionGLTest, EachFrameMovesFromTheOneJustBeforeIt) {
  TD_REQUIRE_GL_CONTEXT();
  for (bool pipelined : {false, true}) {
    SCOPED_TRACE(pipelined ? "throughput mode" : "latency mode");
    auto r = gltest::makeRenderer(*glContext_);
    ASSERT_TRUE(r);
    Scene scene = wallAndBox(glm::dvec3(0.0));
    ASSERT_TRUE(r->setScene(scene).ok());
    FrameSettings s = motionSettings();
    s.pipelined = pipelined;
    Camera c = scene.camera;
    for (float x : {0.0f, 0.1f, 0.3f}) {
      c.posW.x = x;
      c.targetW.x = x;
      ASSERT_TRUE(r->render(c, s).error.empty());
    }
    if (pipelined) {
      ASSERT_TRUE(r->finish().has_value());
    }
    const Motion m = decode(*r);
    const double step = static_cast<double>(0.3f) - static_cast<double>(0.1f);
    EXPECT_NEAR(m.at(10, 10).x, -step * pixelsPerUnit(kCameraZ - kWallZ), 2e-3);
    EXPECT_NEAR(m.at(kW - 40, kH - 10).x, -step * pixelsPerUnit(kCameraZ - kWallZ), 2e-3);
    EXPECT_FALSE(m.unseen[10 * kW + 10]);
  }
}

// A box turning about its own centre (its transform's translation is not the anchor's): each front pixel's
// motion is its point turned back about that centre and projected, worked out here in double from the
// scene's own float matrices; at the origin and 1e6 away, where the render anchor is far from the origin too.
TEST(MotionGLTest, AnInstanceTurningAboutItsCentreMovesAsItsPointsDo) {
  TD_REQUIRE_GL_CONTEXT();
  for (glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e6, -2e5, 1e6)}) {
    SCOPED_TRACE(offset.x);
    auto r = gltest::makeRenderer(*glContext_);
    ASSERT_TRUE(r);
    Scene scene = wallAndBox(offset);
    const glm::dmat4 before(scene.instances[1].worldFromObject);
    constexpr double turn = glm::radians(10.0);
    const Motion m = twoFrames(*r, scene, [&](Renderer& rr, Camera&) {
      scene.instances[1].worldFromObject = scene.instances[1].worldFromObject *
                                           glm::rotate(glm::mat4(1.0f), static_cast<float>(turn), glm::vec3(0.0f, 1.0f, 0.0f));
      rr.setInstanceTransform(1, scene.instances[1].worldFromObject);
    }, false);
    const glm::dmat4 now(scene.instances[1].worldFromObject);
    const glm::dmat4 previousFromCurrent = before * glm::inverse(now);
    const glm::dvec3 eye = glm::dvec3(scene.camera.posW);
    const double t = std::tan(glm::radians(double(kFovDeg)) / 2.0), aspect = double(kW) / kH;
    // The front face (object z = +0.25) now: its plane in world space.
    const glm::dvec3 n = glm::normalize(glm::dvec3(now * glm::dvec4(0, 0, 1, 0)));
    const glm::dvec3 centre = glm::dvec3(now * glm::dvec4(0, 0, 0.25, 1));
    int checked = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const glm::dvec3 dir((2.0 * (x + 0.5) / kW - 1.0) * t * aspect, (2.0 * (y + 0.5) / kH - 1.0) * t, -1.0);
        const glm::dvec3 p = eye + dir * (glm::dot(n, centre - eye) / glm::dot(n, dir));
        const glm::dvec3 local = glm::dvec3(glm::inverse(now) * glm::dvec4(p, 1.0));
        if (std::abs(local.x) > 0.23 || std::abs(local.y) > 0.23) continue;  // the face, a pixel in from its edges
        const glm::dvec3 q = glm::dvec3(previousFromCurrent * glm::dvec4(p, 1.0)) - eye;
        const glm::dvec2 then((q.x / -q.z / (t * aspect) + 1.0) * kW / 2.0, (q.y / -q.z / t + 1.0) * kH / 2.0);
        const glm::dvec2 want = glm::dvec2(x + 0.5, y + 0.5) - then;
        EXPECT_NEAR(m.at(x, y).x, want.x, 0.01) << x << "," << y;
        EXPECT_NEAR(m.at(x, y).y, want.y, 0.01) << x << "," << y;
        ++checked;
      }
    EXPECT_GT(checked, 150);
  }
}

// The motion the spatiotemporal filter reads (FrameSettings::denoise: the shade pass writes it into the
// filter's target, shade_debug.glsl's denoiseMotion) against the same closed forms: a sideways camera move
// shifts each point by its depth's pixels, its view depth then is the distance along the camera's axis, and it
// lay in the last frame's view unless it came in at the frame's edge. The target is found by the label the
// renderer gives it (the renderer has no accessor for a filter's internals).
GLuint textureLabelled(const std::string& label) {
  GLuint found = 0;
  for (GLuint name = 1; name < 65536; ++name) {
    if (glIsTexture(name) == GL_FALSE) continue;
    if (gl::objectLabel(GL_TEXTURE, name) == label) {
      EXPECT_EQ(found, 0u) << "two textures labelled " << label;
      found = name;
    }
  }
  return found;
}

std::vector<glm::vec4> filtersMotion() {
  const GLuint motion = textureLabelled("denoise: motion");
  EXPECT_NE(motion, 0u) << "no texture labelled 'denoise: motion'";
  std::vector<glm::vec4> texels(static_cast<std::size_t>(kW) * kH, glm::vec4(-7.0f));
  if (motion != 0)
    glGetTextureImage(motion, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(texels.size() * sizeof(glm::vec4)),
                      texels.data());
  return texels;
}

TEST(MotionGLTest, TheFiltersMotionHasTheDepthThenAndSaysWhatCameIntoTheFrame) {
  TD_REQUIRE_GL_CONTEXT();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r);
  Scene scene = wallAndBox(glm::dvec3(0.0));
  ASSERT_TRUE(r->setScene(scene).ok());
  FrameSettings s = *presetSettings("hybrid-full");
  s.width = kW;
  s.height = kH;
  s.denoise = true;
  Camera camera = scene.camera;
  ASSERT_TRUE(r->render(camera, s).error.empty());
  for (const glm::vec4& m : filtersMotion()) {
    ASSERT_EQ(m.w, 0.0f) << "the first frame: no last frame, nothing in its view";
  }
  constexpr double dx = 0.1;
  camera.posW.x += static_cast<float>(dx);
  camera.targetW.x += static_cast<float>(dx);
  ASSERT_TRUE(r->render(camera, s).error.empty());
  const std::vector<glm::vec4> motion = filtersMotion();
  gltest::savePng("motion-filter.png", r->readImage());
  const double stepX = static_cast<double>(static_cast<float>(dx));
  const double wallShift = -stepX * pixelsPerUnit(kCameraZ - kWallZ), boxShift = -stepX * pixelsPerUnit(kCameraZ - kBoxFront);
  const glm::dvec4 box = boxRect(stepX, 0.0), boxBefore = boxRect(0.0, 0.0);
  int wall = 0, front = 0, cameIn = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const glm::vec4 m = motion[static_cast<std::size_t>(y) * kW + x];
      if (inside(box, x, y, 1.0)) {
        EXPECT_NEAR(m.x, boxShift, 2e-3) << x << "," << y;
        EXPECT_NEAR(m.y, 0.0, 2e-3) << x << "," << y;
        EXPECT_NEAR(m.z, kCameraZ - kBoxFront, 1e-4) << x << "," << y;
        EXPECT_EQ(m.w, 1.0f) << x << "," << y;
        ++front;
      } else if (!near(box, x, y, 1.0) && !near(boxBefore, x, y, 1.0)) {
        EXPECT_NEAR(m.x, wallShift, 2e-3) << x << "," << y;
        EXPECT_NEAR(m.y, 0.0, 2e-3) << x << "," << y;
        EXPECT_NEAR(m.z, kCameraZ - kWallZ, 1e-4) << x << "," << y;
        // Where the point lay then: the pixel's centre less the shift, within the frame's sub-pixel offset
        // (half a pixel at most): decided only a margin clear of the frame's edge.
        const double then = x + 0.5 - wallShift;
        if (then > kW + 0.6) {
          EXPECT_EQ(m.w, 0.0f) << "came into the frame but said to be in the last one's view: " << x << "," << y;
          ++cameIn;
        } else if (then < kW - 0.6) {
          EXPECT_EQ(m.w, 1.0f) << x << "," << y;
          ++wall;
        }
      }
    }
  EXPECT_GT(front, 100);
  EXPECT_GT(wall, 10000);
  std::printf("the filter's motion: %d box front, %d wall pixels in the last view, %d came into the frame\n", front,
              wall, cameIn);
  EXPECT_GE(cameIn, kH) << "the move brings in a column or two at the frame's right edge";
}

// Without a last frame to measure from every pixel is new: after the scene is set again, at a new size, and
// when the view comes back after frames drawn without it.
TEST(MotionGLTest, ANewSceneSizeOrViewHasNoLastFrame) {
  TD_REQUIRE_GL_CONTEXT();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r);
  Scene scene = wallAndBox(glm::dvec3(0.0));
  ASSERT_TRUE(r->setScene(scene).ok());
  FrameSettings s = motionSettings();
  auto allNew = [&](const char* what) {
    const ImageF lin = r->readLinear();
    std::size_t unseen = 0;
    for (const glm::vec3& v : lin.rgb) unseen += v.z > 0.5f ? 1 : 0;
    return ::testing::AssertionResult(unseen == lin.rgb.size()) << what << ": " << unseen << " of " << lin.rgb.size() << " new";
  };
  auto someSeen = [&]() {
    const ImageF lin = r->readLinear();
    for (const glm::vec3& v : lin.rgb)
      if (v.z < 0.5f) return true;
    return false;
  };
  ASSERT_TRUE(r->render(scene.camera, s).error.empty());
  EXPECT_TRUE(allNew("the first frame"));
  ASSERT_TRUE(r->render(scene.camera, s).error.empty());
  ASSERT_TRUE(someSeen()) << "a still frame after a frame: seen";
  ASSERT_TRUE(r->setScene(scene).ok());
  ASSERT_TRUE(r->render(scene.camera, s).error.empty());
  EXPECT_TRUE(allNew("the scene set again"));
  ASSERT_TRUE(r->render(scene.camera, s).error.empty());
  FrameSettings smaller = s;
  smaller.width -= 16;
  ASSERT_TRUE(r->render(scene.camera, smaller).error.empty());
  EXPECT_TRUE(allNew("a new size"));
  FrameSettings final = smaller;
  final.debugView = DebugView::Final;
  ASSERT_TRUE(r->render(scene.camera, final).error.empty());
  ASSERT_TRUE(r->render(scene.camera, smaller).error.empty());
  EXPECT_TRUE(allNew("the view back after a frame without it"));
  // Every direction of a resize: the height alone (the last frame's ids and depth would be read at another
  // size and projection with the width the same), the width alone, both; smaller and larger.
  FrameSettings sized = smaller;
  for (const glm::ivec2 change : {glm::ivec2(0, -12), glm::ivec2(0, 20), glm::ivec2(24, 0), glm::ivec2(-8, -8),
                                  glm::ivec2(16, 12), glm::ivec2(-16, 12)}) {
    ASSERT_TRUE(r->render(scene.camera, sized).error.empty());
    ASSERT_TRUE(someSeen()) << "a still frame after one of its size: seen";
    sized.width += change.x;
    sized.height += change.y;
    ASSERT_TRUE(r->render(scene.camera, sized).error.empty());
    const std::string what = "resized by " + std::to_string(change.x) + "x" + std::to_string(change.y);
    EXPECT_TRUE(allNew(what.c_str()));
  }
}

// A face of the same instance turning into view: the camera swings round to see the box's side, whose points
// lay behind its front the frame before (the same instance there, further away): only the depth test tells them
// new. The box's pixels are told apart by the instance view of the same frame.
TEST(MotionGLTest, AFaceTurningIntoViewIsNewByItsDepth) {
  TD_REQUIRE_GL_CONTEXT();
  auto r = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(r);
  Scene scene = wallAndBox(glm::dvec3(0.0));
  const Motion m = twoFrames(*r, scene, [&](Renderer&, Camera& c) {
    c.posW = glm::vec3(2.0f, 0.0f, 4.0f);
    c.targetW = glm::vec3(0.0f, 0.0f, 1.0f);
  }, false);
  gltest::savePng("motion-side.png", r->readImage());
  FrameSettings ids = motionSettings();
  ids.debugView = DebugView::InstanceId;
  Camera camera = scene.camera;
  camera.posW = glm::vec3(2.0f, 0.0f, 4.0f);
  camera.targetW = glm::vec3(0.0f, 0.0f, 1.0f);
  ASSERT_TRUE(r->render(camera, ids).error.empty());
  const Image instances = r->readImage();
  const glm::u8vec4 box = instances.at(kW / 2, kH / 2);  // the box is in the middle of the view
  int boxPixels = 0, boxNew = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (instances.at(x, kH - 1 - y) != box) continue;
      ++boxPixels;
      boxNew += m.unseen[static_cast<std::size_t>(y) * kW + x] ? 1 : 0;
    }
  EXPECT_GT(boxPixels, 200);
  // The side face (x = +0.25) faces the camera now and faced away before: all of it is new, about 43 % of the
  // box's pixels from there (144 of 334 measured; the instance test alone, without depth, finds 66: the side's
  // points that fall beside the front's silhouette the frame before).
  EXPECT_GT(boxNew, boxPixels / 3) << "of " << boxPixels << " box pixels";
  EXPECT_LT(boxNew, boxPixels / 2) << "the front face was seen before";
}

}  // namespace
}  // namespace tandem
