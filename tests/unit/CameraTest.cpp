// The camera contract shared by the rasterizer (clipFromView·viewFromWorld) and the ray pass
// (rayThroughPixel): both must see the same point at the same pixel, with reversed-Z depth.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/RenderSpace.h"
#include "tandem/Camera.h"
#include "tandem/Scene.h"

namespace tandem {
namespace {

/// Depth in [0, 1] of a point at view-space z (negative in front of the camera).
float depthAt(const Camera& c, float zView) {
  glm::vec4 clip = c.clipFromView(16.0f / 9.0f) * glm::vec4(0.0f, 0.0f, zView, 1.0f);
  return clip.z / clip.w;
}

/// Projects a world point to pixels (y down), in double so only the camera's own rounding shows.
glm::dvec2 project(const Camera& c, glm::ivec2 size, glm::dvec3 pW) {
  const float aspect = float(size.x) / float(size.y);
  glm::dmat4 m = glm::dmat4(c.clipFromView(aspect)) * glm::dmat4(c.viewFromWorld());
  glm::dvec4 clip = m * glm::dvec4(pW, 1.0);
  glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {(ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y};
}

/// In double: forming the point in float near the camera would add rounding of its own.
glm::dvec3 pointOnRay(const Ray& r, double t) { return glm::dvec3(r.origin) + glm::dvec3(r.dir) * t; }

Camera tiltedCamera() {
  Camera c;
  c.posW = {1.5f, 2.0f, 6.0f};
  c.targetW = {-0.5f, 0.7f, 0.0f};
  c.upW = {0.1f, 1.0f, 0.0f};  // not orthogonal to the view direction: lookAt must orthogonalize
  c.yFovDeg = 40.0f;
  c.nearZ = 0.1f;
  c.farZ = 100.0f;
  return c;
}

TEST(Camera, ViewFromWorldPutsTargetOnNegativeZ) {
  Camera c = tiltedCamera();
  glm::vec4 eye = c.viewFromWorld() * glm::vec4(c.posW, 1.0f);
  EXPECT_NEAR(glm::length(glm::vec3(eye)), 0.0f, 1e-5f);
  glm::vec4 t = c.viewFromWorld() * glm::vec4(c.targetW, 1.0f);
  EXPECT_NEAR(t.x, 0.0f, 1e-5f);
  EXPECT_NEAR(t.y, 0.0f, 1e-5f);
  EXPECT_NEAR(t.z, -glm::length(c.targetW - c.posW), 1e-5f);
  glm::mat4 id = c.worldFromView() * c.viewFromWorld();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(id[i][j], i == j ? 1.0f : 0.0f, 1e-5f);
}

TEST(Camera, PerspectiveIsReversedZ) {
  Camera c = tiltedCamera();
  EXPECT_NEAR(depthAt(c, -c.nearZ), 1.0f, 1e-6f);
  EXPECT_NEAR(depthAt(c, -c.farZ), 0.0f, 1e-6f);
  // Nearer is larger everywhere in between.
  float prev = 1.0f;
  for (float z = c.nearZ * 2; z < c.farZ; z *= 2) {
    float d = depthAt(c, -z);
    EXPECT_LT(d, prev) << "z " << z;
    EXPECT_GT(d, 0.0f);
    prev = d;
  }
}

TEST(Camera, InfiniteFarPlaneTendsToZero) {
  Camera c = tiltedCamera();
  c.farZ = std::numeric_limits<float>::infinity();
  EXPECT_NEAR(depthAt(c, -c.nearZ), 1.0f, 1e-6f);
  EXPECT_NEAR(depthAt(c, -1e9f), 0.0f, 1e-9f);
  EXPECT_GT(depthAt(c, -1e9f), 0.0f);  // never behind the far plane
  EXPECT_NEAR(depthAt(c, -2.0f * c.nearZ), 0.5f, 1e-6f);
}

TEST(Camera, RayThroughPixelAgreesWithProjection) {
  const glm::ivec2 size(640, 360);
  Camera c = tiltedCamera();
  for (bool infinite : {false, true}) {
    c.farZ = infinite ? std::numeric_limits<float>::infinity() : 100.0f;
    for (glm::vec2 px : {glm::vec2(0.5f, 0.5f), glm::vec2(320.5f, 180.5f), glm::vec2(639.5f, 359.5f),
                         glm::vec2(17.5f, 300.5f), glm::vec2(600.5f, 20.5f)}) {
      Ray r = c.rayThroughPixel(px, size);
      EXPECT_NEAR(glm::length(r.dir), 1.0f, 1e-6f);
      EXPECT_NEAR(glm::length(r.origin - c.posW), 0.0f, 1e-6f);
      // viewFromWorld is float: its translation carries ~eps·|posW| of rounding, which is 1e-4 px only
      // for points at least about |posW| away; nearer points get the looser bound that rounding allows.
      for (double t : {0.5, 5.0, 12.0, 40.0}) {
        const double tolerance = t < 5.0 ? 1e-3 : 1e-4;
        glm::dvec2 back = project(c, size, pointOnRay(r, t));
        EXPECT_NEAR(back.x, px.x, tolerance) << "pixel " << px.x << "," << px.y << " t " << t;
        EXPECT_NEAR(back.y, px.y, tolerance) << "pixel " << px.x << "," << px.y << " t " << t;
      }
    }
  }
}

TEST(Camera, RayThroughCentreLooksAtTarget) {
  Camera c = tiltedCamera();
  Ray r = c.rayThroughPixel({320.0f, 180.0f}, {640, 360});  // the exact image centre
  glm::vec3 expected = glm::normalize(c.targetW - c.posW);
  EXPECT_NEAR(glm::dot(r.dir, expected), 1.0f, 1e-6f);
}

TEST(Camera, OrthographicRaysAreParallelAndProjectBack) {
  const glm::ivec2 size(400, 300);
  Camera c = tiltedCamera();
  c.orthographic = true;
  c.orthoHeight = 5.0f;
  const glm::vec3 forward = glm::normalize(c.targetW - c.posW);
  EXPECT_NEAR(depthAt(c, -c.nearZ), 1.0f, 1e-6f);
  EXPECT_NEAR(depthAt(c, -c.farZ), 0.0f, 1e-6f);
  Ray a = c.rayThroughPixel({0.5f, 0.5f}, size);
  Ray b = c.rayThroughPixel({399.5f, 299.5f}, size);
  EXPECT_NEAR(glm::dot(a.dir, forward), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(b.dir, forward), 1.0f, 1e-6f);
  // The image spans orthoHeight vertically and orthoHeight·aspect horizontally.
  glm::vec3 span = glm::vec3(c.viewFromWorld() * glm::vec4(b.origin - a.origin, 0.0f));
  EXPECT_NEAR(span.x, 5.0f * 4.0f / 3.0f * 399.0f / 400.0f, 1e-4f);
  EXPECT_NEAR(span.y, -5.0f * 299.0f / 300.0f, 1e-4f);
  for (glm::vec2 px : {glm::vec2(0.5f, 0.5f), glm::vec2(200.5f, 150.5f), glm::vec2(399.5f, 10.5f)}) {
    Ray r = c.rayThroughPixel(px, size);
    glm::dvec2 back = project(c, size, pointOnRay(r, 7.0));
    EXPECT_NEAR(back.x, px.x, 1e-4);
    EXPECT_NEAR(back.y, px.y, 1e-4);
  }
}

// Camera-relative rendering (core/RenderSpace.h) far from the origin: the scene's camera at 1e6, its target
// a short way off at an oblique angle. The frame's camera in render space must look exactly where the world
// camera looks (the direction worked out here in double), and its rays through the image centre too;
// rounding its position or target at the world's magnitude (1/16 at 1e6) would turn it by up to a radian.
TEST(RenderSpace, ACameraFarFromTheOriginLooksAlongItsWorldDirection) {
  const glm::vec3 positions[] = {{1e6f, 2e6f, -3e6f}, {-1048576.0f, 524288.5f, 999999.0f}, {3e5f, -7e5f, 1.5e6f}};
  const glm::vec3 directions[] = {{0.3f, -0.7f, 1.1f}, {-1.0f, 0.05f, -0.2f}, {0.01f, 0.9f, 0.4f}};
  for (glm::vec3 pos : positions)
    for (glm::vec3 d : directions)
      for (float distance : {0.25f, 1.0f, 37.0f}) {
        Scene scene;
        scene.camera.posW = pos;
        scene.camera.targetW = pos + distance * glm::normalize(d);  // rounded to the floats at 1e6: the world's own target
        scene.camera.upW = {0.0f, 1.0f, 0.0f};
        // (rounded to the world's floats, a target may end up straight above: no camera the scene file takes)
        if (glm::length(glm::cross(glm::dvec3(scene.camera.targetW) - glm::dvec3(scene.camera.posW), glm::dvec3(0, 1, 0))) < 1e-3)
          continue;
        const glm::dvec3 world = glm::normalize(glm::dvec3(scene.camera.targetW) - glm::dvec3(scene.camera.posW));
        // The renderer's anchor (the scene camera at upload), then the frame's camera, also after it moved a
        // little from where the anchor was taken.
        const glm::vec3 anchor = renderAnchor(scene);
        for (glm::vec3 moved : {glm::vec3(0.0f), glm::vec3(3.3f, -1.7f, 2.9f)}) {
          SCOPED_TRACE(testing::Message() << "camera at " << pos.x << " " << pos.y << " " << pos.z << ", direction "
                                          << d.x << " " << d.y << " " << d.z << ", distance " << distance << ", moved "
                                          << moved.x);
          Camera camera = scene.camera;
          camera.posW += moved;
          camera.targetW += moved;
          const glm::dvec3 expected = glm::normalize(glm::dvec3(camera.targetW) - glm::dvec3(camera.posW));
          if (moved == glm::vec3(0.0f)) {
            EXPECT_LT(glm::length(expected - world), 1e-12);
          }
          const Camera rebased = toRenderSpace(camera, anchor);
          EXPECT_LT(glm::length(glm::dvec3(rebased.posW)), 8.0) << "render space is near the camera";
          const glm::dvec3 got = glm::normalize(glm::dvec3(rebased.targetW) - glm::dvec3(rebased.posW));
          EXPECT_LT(glm::length(got - expected), 2e-6) << "the rebased view direction";
          // The view matrix's forward axis and the ray through the image centre.
          const glm::mat4 view = rebased.viewFromWorld();
          const glm::dvec3 forward = -glm::dvec3(view[0][2], view[1][2], view[2][2]);
          EXPECT_LT(glm::length(forward - expected), 4e-6) << "viewFromWorld's -z";
          const Ray centre = rebased.rayThroughPixel({320.0f, 180.0f}, {640, 360});
          EXPECT_LT(glm::length(glm::dvec3(centre.dir) - expected), 4e-6) << "the centre pixel's ray";
        }
      }
}

// The same far from the anchor, not only far from the origin: a camera the floating origin has not yet caught
// up with (up to anchorReach away, and beyond it for a caller that never moves the anchor), its target a
// thousandth of a unit off at an oblique angle. Its render-space view direction is the double-precision one of
// its world points to float rounding (rounded separately at |posR| = 1e3, the two points would tilt it by
// ulp(1e3) / 1e-3, a hundredth of a radian; at 1e6, by more than a radian). A camera at the anchor keeps its
// target as it was, and a thin lens its plane in focus.
TEST(RenderSpace, ACameraFarFromTheAnchorLooksAlongItsWorldDirection) {
  // (the camera near the world's origin, where a float holds a target 1e-3 away; the anchor far from it)
  const glm::vec3 position(1.5f, -0.25f, 2.0f);
  for (const double away : {51.2, 1e3, 1e6})
    for (const glm::vec3 d : {glm::vec3(0.3f, -0.7f, 1.1f), glm::vec3(-1.0f, 0.05f, -0.2f)})
      for (const float distance : {1e-3f, 0.5f}) {
        SCOPED_TRACE(testing::Message() << away << " from the anchor, target " << distance << " away");
        const glm::vec3 anchor(glm::dvec3(position) - away * glm::normalize(glm::dvec3(1.0, 0.4, -0.6)));
        Camera camera;
        camera.posW = position;
        camera.targetW = camera.posW + distance * glm::normalize(d);
        camera.aperture = 0.1f;
        const glm::dvec3 expected = glm::normalize(glm::dvec3(camera.targetW) - glm::dvec3(camera.posW));
        const Camera rebased = toRenderSpace(camera, anchor);
        const glm::dvec3 got = glm::normalize(glm::dvec3(rebased.targetW) - glm::dvec3(rebased.posW));
        EXPECT_LT(glm::length(got - expected), 1e-6) << "the rebased view direction";
        const glm::mat4 view = rebased.viewFromWorld();
        EXPECT_LT(glm::length(-glm::dvec3(view[0][2], view[1][2], view[2][2]) - expected), 2e-6) << "viewFromWorld's -z";
        EXPECT_NEAR(rebased.focusPlane(), glm::length(glm::dvec3(camera.targetW) - glm::dvec3(camera.posW)),
                    1e-6 * distance)
            << "the plane in focus";
      }
  const glm::vec3 anchor(12.0f, -3.0f, 40.0f);
  Camera at;
  at.posW = anchor;
  at.targetW = anchor + glm::vec3(0.3f, -0.2f, -1.0f);
  const Camera same = toRenderSpace(at, anchor);
  EXPECT_EQ(same.posW, glm::vec3(0.0f));
  EXPECT_EQ(same.targetW, glm::vec3(glm::dvec3(at.targetW) - glm::dvec3(at.posW))) << "a camera at the anchor";
  EXPECT_EQ(same.focusDistance, at.focusDistance);
}

// The floating origin's rule: the anchor moves to a camera farther from it than 1024 near distances (a finite
// one: a camera with a non-finite position, which the scene checks refuse, never moves it).
TEST(RenderSpace, TheAnchorMovesToACameraFartherThanItsReach) {
  Camera c;
  c.nearZ = 0.05f;
  EXPECT_DOUBLE_EQ(anchorReach(c), 1024.0 * 0.05f);
  const glm::vec3 anchor(1e6f, 0.0f, -2e5f);
  c.posW = anchor + glm::vec3(30.0f, 40.0f, 0.0f);  // 50 away: within 51.2
  EXPECT_FALSE(anchorDue(anchor, c));
  c.posW = anchor + glm::vec3(30.0f, 42.0f, 0.0f);  // 51.6 away
  EXPECT_TRUE(anchorDue(anchor, c));
  c.nearZ = 0.1f;  // reach 102.4: within again
  EXPECT_FALSE(anchorDue(anchor, c));
  c.posW = glm::vec3(std::numeric_limits<float>::infinity(), 0.0f, 0.0f);
  EXPECT_FALSE(anchorDue(anchor, c));
}

}  // namespace
}  // namespace tandem
