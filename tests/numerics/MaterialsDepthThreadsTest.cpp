// Materials and lights (ns 0 and 1e4, kr + kt = 1, intensity 0 and 1e6, tone mapping, recursion depth
// 0 and 64), depth range (near/far 1e-3 / 1e5, coincident and nearly coincident surfaces), geometry
// (degenerate and needle triangles, zero-length normals) and thread-count independence.
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "numerics/NumericsSupport.h"

namespace tandem::numerics {
namespace {

bool sameFrame(const Frame& a, const Frame& b) {
  return a.reference.rgb == b.reference.rgb && a.vis.ids == b.vis.ids && a.rays.lightMask == b.rays.lightMask &&
         a.rays.reflected == b.rays.reflected && a.rays.transmitted == b.rays.transmitted &&
         a.composite.rgb == b.composite.rgb;
}

TEST(Materials, SpecularExponentZeroAndTenThousandStayBounded) {
  for (float ns : {0.0f, 1e-6f, 1e4f}) {
    Scene scene = whittedScene();
    for (Material& m : scene.materials) m.ns = ns;
    Frame f = renderFrame(scene, numericsSettings(96, 54));
    EXPECT_EQ(nonFiniteCount(f), 0u) << "ns " << ns;
    // ns = 0: the highlight is ks·E wherever R·V > 0, so never more than kd + ks times the light.
    for (const glm::vec3& c : f.reference.rgb) ASSERT_LT(glm::max(c.x, glm::max(c.y, c.z)), 20.0f) << "ns " << ns;
  }
  // The formula itself at the extremes.
  glm::vec3 n(0, 1, 0), l = glm::normalize(glm::vec3(0.3f, 1.0f, 0.0f));
  glm::vec3 r = glm::reflect(-l, n);
  for (float ns : {0.0f, 1e4f, 1e30f})
    for (glm::vec3 v : {r, glm::normalize(r + glm::vec3(0.0f, 0.0f, 1e-3f)), -r}) {
      float s = shading::tdSpecular(n, l, v, ns);
      EXPECT_TRUE(std::isfinite(s) && s >= 0.0f && s <= 1.0f) << ns;
    }
}

TEST(Materials, MirrorAndGlassWithKrPlusKtOneStayBounded) {
  Scene scene = whittedScene();
  for (Material& m : scene.materials) {
    if (m.kt > 0.0f) m.kr = 1.0f - m.kt;
    else if (m.kr > 0.0f) m.kr = 1.0f;
  }
  FrameSettings s = numericsSettings(96, 54);
  s.maxDepth = 64;
  Frame f = renderFrame(scene, s);
  EXPECT_EQ(nonFiniteCount(f), 0u);
  // With kr + kt = 1 and Fresnel weights every bounce passes at most what arrives: radiance never
  // exceeds the brightest local term of the scene.
  for (const glm::vec3& c : f.reference.rgb) {
    ASSERT_LT(glm::max(c.x, glm::max(c.y, c.z)), 10.0f);
  }
}

TEST(Lights, IntensityZeroGivesAmbientOnlyAndAMillionToneMapsIntoRange) {
  Scene scene = whittedScene();
  for (Light& l : scene.lights)
    if (l.type != LightType::Ambient) l.intensity = 0.0f;
  FrameSettings s = numericsSettings(96, 54);
  Frame dark = renderFrame(scene, s);
  EXPECT_EQ(nonFiniteCount(dark), 0u);
  Scene ambientOnly = whittedScene();
  std::erase_if(ambientOnly.lights, [](const Light& l) { return l.type != LightType::Ambient; });
  Frame ambient = renderFrame(ambientOnly, s);
  // Same radiance with no shadow rays needed: a light of intensity 0 reaches nothing.
  EXPECT_EQ(dark.reference.rgb, ambient.reference.rgb);
  EXPECT_EQ(dark.rays.counts.shadow, 0u);

  for (Light& l : scene.lights) l.intensity = 1e6f;
  Frame bright = renderFrame(scene, s);
  EXPECT_EQ(nonFiniteCount(bright), 0u);
  for (int op : {TD_TONEMAP_NONE, TD_TONEMAP_REINHARD, TD_TONEMAP_ACES})
    for (const glm::vec3& c : bright.reference.rgb) {
      glm::vec3 t = shading::tdToneMap(c, op);
      ASSERT_TRUE(finite(t) && glm::all(glm::greaterThanEqual(t, glm::vec3(0.0f))) &&
                  glm::all(glm::lessThanEqual(t, glm::vec3(1.0f))))
          << op;
    }
}

// tdToneMap over the whole float range: finite and in [0, 1] up to FLT_MAX and +inf (radiance that
// overflowed upstream must still display as white, not as NaN from inf/inf).
TEST(Lights, ToneMapIsFiniteAndBoundedUpToInfinity) {
  const float big[] = {0.0f, 1e-30f, 1.0f, 1e6f, 1e19f, 1e20f, 1e30f, std::numeric_limits<float>::max(),
                       std::numeric_limits<float>::infinity()};
  for (int op : {TD_TONEMAP_NONE, TD_TONEMAP_REINHARD, TD_TONEMAP_ACES})
    for (float v : big) {
      glm::vec3 t = shading::tdToneMap(glm::vec3(v, v * 0.5f, 0.0f), op);
      EXPECT_TRUE(finite(t)) << "op " << op << " value " << v;
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(t, glm::vec3(0.0f))) && glm::all(glm::lessThanEqual(t, glm::vec3(1.0f))))
          << "op " << op << " value " << v;
    }
  // Monotone at the top end: brighter never displays darker.
  EXPECT_GE(shading::tdToneMap(glm::vec3(1e30f), TD_TONEMAP_ACES).x, shading::tdToneMap(glm::vec3(1e3f), TD_TONEMAP_ACES).x);
  EXPECT_GE(shading::tdToneMap(glm::vec3(1e30f), TD_TONEMAP_REINHARD).x, shading::tdToneMap(glm::vec3(1e3f), TD_TONEMAP_REINHARD).x);
}

// Two parallel mirrors facing each other (kr = 1): depth 64 terminates with at most 64 bounces per
// pixel, finite; depth 0 traces no secondary ray.
TEST(Recursion, DepthZeroAndSixtyFourBetweenParallelMirrors) {
  Scene scene;
  Material mirror = diffuse(glm::vec3(0.05f));
  mirror.kr = 1.0f;
  std::uint32_t mat = addMaterial(scene, mirror);
  std::uint32_t plane = addMesh(scene, makePlane({4000.0f, 4000.0f}, 1));
  addInstance(scene, plane, mat, glm::mat4(1.0f));
  addInstance(scene, plane, mat, translate({0.0f, 1.0f, 0.0f}) * glm::rotate(glm::mat4(1.0f), glm::pi<float>(), glm::vec3(1, 0, 0)));
  scene.lights.push_back(ambientLight(1.0f));
  scene.camera.posW = {0.0f, 0.5f, 3.0f};
  scene.camera.targetW = {0.0f, 0.0f, 2.0f};  // steep enough for 64 bounces within the mirrors
  const int w = 48, h = 32;
  for (int depth : {0, 64}) {
    FrameSettings s = numericsSettings(w, h);
    s.maxDepth = depth;
    s.minContribution = 0.0f;
    Frame f = renderFrame(scene, s);
    EXPECT_EQ(nonFiniteCount(f), 0u);
    std::uint64_t hitPixels = static_cast<std::uint64_t>(std::count_if(f.vis.ids.begin(), f.vis.ids.end(), [](glm::uvec2 id) { return id.x != 0; }));
    if (depth == 0) {
      EXPECT_EQ(f.rays.counts.reflection, 0u);
      EXPECT_EQ(f.referenceCounts.reflection, 0u);
    } else {
      EXPECT_GT(f.rays.counts.reflection, hitPixels * 10);
      EXPECT_LE(f.rays.counts.reflection, hitPixels * 64);
    }
  }
}

// Near/far from 1e-3 to 1e5: the ray pass keeps what the rasterizer keeps, a surface 2e-3 away and one
// 5e4 away are both seen, and the reversed-Z float depth separates surfaces 1e-5 apart (relatively) over
// the whole range (no z-fighting for the raster pass either).
TEST(DepthRange, NearOneThousandthFarOneHundredThousand) {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.5f)));
  std::uint32_t quad = addMesh(scene, makePlane({1.0f, 1.0f}, 1));
  // A tiny quad 2e-3 in front of the camera covering the left half, a huge one 5e4 away behind all.
  auto facing = glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), glm::vec3(1, 0, 0));
  addInstance(scene, quad, mat, translate({-1e-3f, 0.0f, -2e-3f}) * glm::scale(glm::mat4(1.0f), glm::vec3(2e-3f)) * facing);
  addInstance(scene, quad, mat, translate({0.0f, 0.0f, -5e4f}) * glm::scale(glm::mat4(1.0f), glm::vec3(1e6f)) * facing);
  scene.lights.push_back(ambientLight(1.0f));
  scene.camera.posW = {0.0f, 0.0f, 0.0f};
  scene.camera.targetW = {0.0f, 0.0f, -1.0f};
  scene.camera.nearZ = 1e-3f;
  scene.camera.farZ = 1e5f;
  const int w = 64, h = 64;
  Frame f = renderFrame(scene, numericsSettings(w, h));
  EXPECT_EQ(nonFiniteCount(f), 0u);
  EXPECT_EQ(f.vis.ids[pixelIndex(16, 32, w)].x, 1u);
  EXPECT_EQ(f.vis.ids[pixelIndex(48, 32, w)].x, 2u);
  // Beyond far: the huge quad moved to 2e5 is clipped away, as GL clips it.
  Scene beyond = scene;
  beyond.instances[1].worldFromObject[3].z = -2e5f;
  Frame g = renderFrame(beyond, numericsSettings(w, h));
  EXPECT_EQ(g.vis.ids[pixelIndex(48, 32, w)].x, 0u);

  // Reversed-Z depth of view distances z and z·(1 + 1e-5) differ in float at every scale of the range.
  for (float farZ : {1e5f, std::numeric_limits<float>::infinity()}) {
    Camera cam = scene.camera;
    cam.farZ = farZ;
    glm::mat4 proj = cam.clipFromView(1.0f);
    auto depth = [&](float z) {
      glm::vec4 c = proj * glm::vec4(0.0f, 0.0f, -z, 1.0f);
      return c.z / c.w;
    };
    EXPECT_NEAR(depth(1e-3f), 1.0f, 1e-6f);
    if (std::isfinite(farZ)) {
      EXPECT_NEAR(depth(farZ), 0.0f, 1e-6f);
    }
    for (float z = 1.1e-3f; z < 0.9e5f; z *= 1.37f) {
      float a = depth(z), b = depth(z * (1.0f + 1e-5f));
      EXPECT_GT(a, b) << "z " << z << " far " << farZ;
      EXPECT_TRUE(a >= 0.0f && a <= 1.0f);
    }
  }
}

// Coincident and nearly coincident surfaces: which one the ray pass sees is deterministic (identical
// frames, 1 and 2 threads, frame after frame); separated by 1e-4 relative, the nearer always wins.
TEST(DepthRange, CoincidentSurfacesAreDeterministicAndSeparatedOnesNeverFight) {
  for (float gap : {0.0f, 1e-7f, 1e-4f}) {
    Scene scene;
    std::uint32_t red = addMaterial(scene, diffuse({1.0f, 0.0f, 0.0f}));
    std::uint32_t green = addMaterial(scene, diffuse({0.0f, 1.0f, 0.0f}));
    std::uint32_t plane = addMesh(scene, makePlane({10.0f, 10.0f}, 8));
    addInstance(scene, plane, red, glm::mat4(1.0f));
    // The second plane: the same triangles differently split (rotated 90°), `gap` above.
    addInstance(scene, plane, green, translate({0.0f, gap, 0.0f}) * glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), glm::vec3(0, 1, 0)));
    scene.lights.push_back(directional({0.3f, -1.0f, 0.2f}));
    scene.camera.posW = {0.0f, 1.0f, 1.0f};
    scene.camera.targetW = {0.0f, 0.0f, 0.0f};
    FrameSettings s = numericsSettings(64, 48);
    Frame a = renderFrame(scene, s, 1), b = renderFrame(scene, s, 2);
    auto rt = makeTracer(scene, 2);
    ASSERT_TRUE(rt);
    Frame c1 = renderFrame(*rt, scene, s), c2 = renderFrame(*rt, scene, s);
    EXPECT_TRUE(sameFrame(a, b)) << "gap " << gap;
    EXPECT_TRUE(sameFrame(c1, c2)) << "gap " << gap;
    EXPECT_EQ(nonFiniteCount(a), 0u);
    // The coincident plane must not shadow its twin: every visible pixel sees the light.
    for (std::uint32_t m : a.rays.lightMask) ASSERT_EQ(m, 1u) << "gap " << gap;
    if (gap >= 1e-4f) {
      for (glm::uvec2 id : a.vis.ids) ASSERT_EQ(id.x, 2u) << "the nearer plane must win everywhere";
    }
  }
}

TEST(Geometry, DegenerateNeedleTrianglesAndZeroNormalsStayFinite) {
  Scene scene;
  Mesh m;
  // A fan of triangles: normal, zero-area (collinear and repeated points), needles 1e-7 wide, with
  // normals of zero length, NaN-free but denormal, and unnormalised.
  auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 n) {
    auto base = static_cast<std::uint32_t>(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.normals.insert(m.normals.end(), {n, n, n});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
  };
  add({-1, 0, -1}, {1, 0, -1}, {0, 0, 1}, {0, 0, 0});                       // zero-length normals
  add({-1, 0.1f, 0}, {0, 0.1f, 0}, {1, 0.1f, 0}, {0, 1, 0});                // collinear
  add({0.2f, 0.2f, 0.2f}, {0.2f, 0.2f, 0.2f}, {0.2f, 0.2f, 0.2f}, {0, 1, 0});  // a point
  add({-1, 0.3f, 0.5f}, {1, 0.3f, 0.5f}, {0, 0.3f, 0.5000001f}, {0, 1e-30f, 0});  // needle, denormal-ish normal
  add({-1, 0.05f, -0.5f}, {1, 0.05f, -0.5f}, {1, 0.05f + 1e-7f, -0.5f + 1e-7f}, {3, 4, 0});  // needle, unnormalised
  addInstance(scene, addMesh(scene, m), addMaterial(scene, diffuse(glm::vec3(0.7f))), glm::mat4(1.0f));
  Material mirror = diffuse(glm::vec3(0.1f));
  mirror.kr = 0.8f;
  Mesh copy = m;
  addInstance(scene, addMesh(scene, copy), addMaterial(scene, mirror), translate({0.0f, -0.5f, 0.0f}));
  scene.lights.push_back(directional({0.1f, -1.0f, 0.3f}));
  scene.lights.push_back(pointLight({0.0f, 0.3f, 0.5f}));  // on the needle
  scene.lights.push_back(ambientLight(0.2f));
  scene.camera.posW = {0.0f, 2.0f, 2.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  for (auto model : {ShadingModel::Flat, ShadingModel::Gouraud, ShadingModel::Phong, ShadingModel::Toon}) {
    FrameSettings s = numericsSettings(96, 96);
    s.shadingOverride = model;
    Frame f = renderFrame(scene, s);
    EXPECT_EQ(nonFiniteCount(f), 0u) << static_cast<int>(model);
    EXPECT_GT(std::count_if(f.vis.ids.begin(), f.vis.ids.end(), [](glm::uvec2 id) { return id.x != 0; }), 1000);
  }
}

// Thread count: 1, 2 and 4 threads give bit-identical outputs on the full Whitted scene (every effect,
// reference supersampling included).
TEST(Threads, OneTwoAndFourThreadsGiveIdenticalFrames) {
  Scene scene = whittedScene();
  FrameSettings s = numericsSettings(128, 72);
  s.referenceSpp = 2;
  Frame one = renderFrame(scene, s, 1);
  for (int threads : {2, 4}) {
    Frame n = renderFrame(scene, s, threads);
    EXPECT_TRUE(sameFrame(one, n)) << threads << " threads";
    EXPECT_EQ(one.rays.counts.shadow, n.rays.counts.shadow);
    EXPECT_EQ(one.referenceCounts.reflection, n.referenceCounts.reflection);
  }
  EXPECT_EQ(nonFiniteCount(one), 0u);
}

}  // namespace
}  // namespace tandem::numerics
