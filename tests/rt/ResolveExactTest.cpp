// Exact solids in the hybrid frame (docs/csg.md, "In the raster frame"): the resolve step traces the camera
// ray of every pixel the raster drew with a solid's proxy and hands back what that ray sees — the solid's
// exact hit, what lies behind the proxy where the ray passes the solid by, or the background — so the frame
// agrees with Embree's own camera rays at every pixel. The raster is stood in for by camera rays on the same
// scene with the solids' exact parts taken away (their proxies left), which is what it draws.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/Solids.h"
#include "rt/RtTestScenes.h"
#include "tandem/PixelTrace.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

// A mesh that is the exact solid `s`, its proxy the solid's bounding box (as the scene file makes one).
Mesh exactMesh(const solid::Solid& s) {
  const solid::Bounds b = solid::bounds(s);
  Mesh m = makeBox(glm::vec3(b.hi - b.lo));
  for (glm::vec3& p : m.positions) p += glm::vec3(0.5 * (b.lo + b.hi));
  m.exact = s;
  return m;
}

solid::Solid leaf(solid::Shape shape, glm::dvec3 size) {
  solid::Solid s;
  s.nodes.push_back({});
  s.nodes[0].primitive = {shape, size};
  return s;
}

// A unit box less a sphere of radius 0.62 at its centre: a hole through each face.
solid::Solid die() {
  solid::Solid s;
  s.nodes.resize(3);
  s.nodes[0].op = solid::Op::Difference;
  s.nodes[0].children = {1, 2};
  s.nodes[1].primitive = {solid::Shape::Box, glm::dvec3(0.5)};
  s.nodes[2].primitive = {solid::Shape::Sphere, glm::dvec3(0.62)};
  return s;
}

// A floor, an upright ring (torus, its hole facing the camera), an exact sphere in a coarse circumscribed
// proxy, and a die: every kind of resolved pixel (a hit on a solid, the floor or the sky through a hole).
Scene resolveScene() {
  Scene s;
  addInstance(s, addMesh(s, makePlane({12.0f, 12.0f}, 1)), addMaterial(s, diffuse(glm::vec3(0.7f))), glm::mat4(1.0f));
  const std::uint32_t mat = addMaterial(s, diffuse(glm::vec3(0.3f, 0.5f, 0.9f)));
  addInstance(s, addMesh(s, exactMesh(leaf(solid::Shape::Torus, {0.8, 0.25, 0.0}))), mat,
              glm::rotate(translate({-1.4f, 1.1f, 0.0f}), glm::radians(90.0f), glm::vec3(1.0f, 0.0f, 0.0f)));
  Mesh sphere = makeSphere(0.6f * 1.25f, 8, 4);  // circumscribes a sphere of 0.6 (1.25 > 1/cos(45°/2)·1/cos(22.5°))
  sphere.exact = leaf(solid::Shape::Sphere, glm::dvec3(0.6));
  addInstance(s, addMesh(s, sphere), mat, translate({0.3f, 0.6f, 0.3f}));
  addInstance(s, addMesh(s, exactMesh(die())), mat,
              glm::rotate(translate({1.7f, 0.5f, -0.4f}), glm::radians(25.0f), glm::vec3(0.0f, 1.0f, 0.0f)));
  s.lights.push_back(ambientLight(0.2f));
  s.lights.push_back(pointLight({-2.0f, 5.0f, 3.0f}, 0.9f));
  s.camera.posW = {0.0f, 1.6f, 5.5f};
  s.camera.targetW = {0.0f, 0.6f, 0.0f};
  s.camera.yFovDeg = 45.0f;
  return s;
}

// What the raster draws: the proxies, each instance where it is.
Scene proxiesOnly(Scene s) {
  for (Mesh& m : s.meshes) m.exact.reset();
  return s;
}

constexpr int kW = 200, kH = 120;

struct Resolved {
  VisibilityBuffer raster;  // the proxies' ids
  VisibilityBuffer ids;     // after the resolve step
  VisibilityBuffer truth;   // Embree's camera rays on the exact scene
  std::vector<ResolvedPixel> records;
  RayCounts counts;
};

Resolved resolve(const Scene& scene, int threads = 2) {
  Resolved r;
  auto proxies = makeTracer(proxiesOnly(scene), threads);
  auto exact = makeTracer(scene, threads);
  if (!proxies || !exact) return r;
  proxies->castVisibility(scene.camera, kW, kH, r.raster);
  exact->castVisibility(scene.camera, kW, kH, r.truth);
  r.ids = r.raster;
  // Every pixel as if the GL had proved all its shadow rays: the resolve step must drop the proofs of the
  // pixels whose hit it changes (they were the raster's hit's).
  r.ids.proofs.assign(r.ids.ids.size(), 0xFFFFu);
  exact->resolveExact(scene, scene.camera, r.ids, r.records, r.counts);
  return r;
}

bool isExact(const Scene& s, std::uint32_t idX) { return idX != 0 && s.meshes[s.instances[idX - 1].mesh].exact.has_value(); }

TEST(ResolveExact, EveryProxyPixelShowsWhatItsCameraRaySees) {
  const Scene scene = resolveScene();
  const Resolved r = resolve(scene);
  ASSERT_EQ(r.ids.ids.size(), static_cast<std::size_t>(kW * kH));
  std::uint64_t proxyPixels = 0, onSolids = 0, behind = 0, sky = 0, mismatched = 0;
  for (std::size_t i = 0; i < r.ids.ids.size(); ++i) {
    const glm::uvec2 got = r.ids.ids[i], want = r.truth.ids[i];
    if (isExact(scene, r.raster.ids[i].x)) {
      ++proxyPixels;
      if (got.y == kExactTriangle) ++onSolids;
      else if (got.x != 0) ++behind;
      else ++sky;
    } else {
      // The proxy encloses its solid: a pixel the raster gave something else sees no solid, and is left as it was.
      EXPECT_EQ(got, r.raster.ids[i]) << "pixel " << i;
    }
    // Embree names a hit on a solid by its instance (the user geometry's one primitive, 0).
    const glm::uvec2 expected = isExact(scene, want.x) ? glm::uvec2(want.x, kExactTriangle) : want;
    if (got != expected) ++mismatched;
  }
  EXPECT_EQ(mismatched, 0u) << "pixels whose id differs from the exact scene's camera ray";
  EXPECT_EQ(r.counts.resolved, proxyPixels) << "one ray per proxy pixel, no more";
  EXPECT_EQ(r.records.size(), proxyPixels);
  // Each kind is there: hits on the solids, the floor through the ring and the die, the sky around the sphere.
  EXPECT_GT(onSolids, 1000u);
  EXPECT_GT(behind, 100u);
  EXPECT_GT(sky, 20u);
  // The ring's centre sees the sky behind it, through the hole (past the floor's far edge).
  const glm::vec4 ringW = glm::vec4(-1.4f, 1.1f, 0.0f, 1.0f);
  const glm::mat4 clip = scene.camera.clipFromView(glm::ivec2(kW, kH)) * scene.camera.viewFromWorld();
  const glm::vec4 c = clip * ringW;
  const int px = static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kW), py = static_cast<int>((0.5f - c.y / c.w * 0.5f) * kH);
  const glm::uvec2 centre = r.ids.ids[static_cast<std::size_t>(py) * kW + static_cast<std::size_t>(px)];
  EXPECT_TRUE(isExact(scene, r.raster.ids[static_cast<std::size_t>(py) * kW + static_cast<std::size_t>(px)].x));
  EXPECT_EQ(centre.x, 0u) << "the sky, seen through the ring";
}

TEST(ResolveExact, RecordsCarryTheHitTheIdsAndTheRasterDepth) {
  const Scene scene = resolveScene();
  const Resolved r = resolve(scene);
  ASSERT_FALSE(r.records.empty());
  const glm::vec3 forward = glm::normalize(scene.camera.targetW - scene.camera.posW);
  for (const ResolvedPixel& rec : r.records) {
    ASSERT_LT(rec.pixel.x, static_cast<std::uint32_t>(kW));
    ASSERT_LT(rec.pixel.y, static_cast<std::uint32_t>(kH));
    const std::size_t i = static_cast<std::size_t>(rec.pixel.y) * kW + rec.pixel.x;
    EXPECT_EQ(rec.id, r.ids.ids[i]);
    if (rec.id.x == 0) {
      EXPECT_EQ(rec.depth, 0.0f) << "the background is at the far plane";
      continue;
    }
    ASSERT_GT(rec.depth, 0.0f);
    if (rec.id.y != kExactTriangle) continue;
    EXPECT_NEAR(glm::length(glm::vec3(rec.hit)), 1.0f, 1e-5f) << "a unit normal";
    // Reversed-Z with an infinite far plane: depth = near / z_view, z_view = t·(dir·forward) (closed form).
    const Ray ray = scene.camera.rayThroughPixel(glm::vec2(rec.pixel) + 0.5f, {kW, kH});
    const float zView = rec.hit.w * glm::dot(ray.dir, forward);
    EXPECT_NEAR(rec.depth, scene.camera.nearZ / zView, 1e-5f * rec.depth);
    // The normal faces the camera (the solid is seen from outside) and is the sphere's radial direction on it.
    EXPECT_LT(glm::dot(glm::vec3(rec.hit), ray.dir), 0.0f);
    if (rec.id.x == 3) {
      const glm::vec3 p = ray.origin + rec.hit.w * ray.dir - glm::vec3(0.3f, 0.6f, 0.3f);
      EXPECT_NEAR(glm::length(p), 0.6f, 1e-4f);
      EXPECT_GT(glm::dot(glm::normalize(p), glm::vec3(rec.hit)), 1.0f - 1e-5f);
    }
  }
}

TEST(ResolveExact, SameRecordsOnAnyThreadCount) {
  const Scene scene = resolveScene();
  const Resolved one = resolve(scene, 1), two = resolve(scene, 2);
  ASSERT_EQ(one.records.size(), two.records.size());
  ASSERT_FALSE(one.records.empty());
  EXPECT_EQ(std::memcmp(one.records.data(), two.records.data(), one.records.size() * sizeof(ResolvedPixel)), 0);
  EXPECT_EQ(one.ids.ids, two.ids.ids);
}

TEST(ResolveExact, CameraWithinAProxyResolvesEveryPixel) {
  // A flat ring around the camera: its proxy box holds the camera, so the raster draws the box's far side, and
  // a post inside the box's corner, behind the ring's tube, would hide the tube. Every pixel is resolved then.
  Scene s;
  const std::uint32_t mat = addMaterial(s, diffuse(glm::vec3(0.6f)));
  const std::uint32_t ring = addInstance(s, addMesh(s, exactMesh(leaf(solid::Shape::Torus, {4.0, 0.5, 0.0}))), mat,
                                         glm::mat4(1.0f));
  addInstance(s, addMesh(s, makeBox(glm::vec3(0.2f, 0.8f, 0.2f))), mat, translate({3.9f, 0.0f, 3.9f}));
  s.lights.push_back(ambientLight(1.0f));
  s.camera.posW = {0.0f, 0.0f, 0.0f};
  s.camera.targetW = {1.0f, 0.0f, 1.0f};
  s.camera.yFovDeg = 30.0f;
  const Resolved r = resolve(s);
  ASSERT_EQ(r.ids.ids.size(), static_cast<std::size_t>(kW * kH));
  EXPECT_EQ(r.counts.resolved, static_cast<std::uint64_t>(kW * kH)) << "every pixel";
  std::size_t mismatched = 0, ringPixels = 0;
  for (std::size_t i = 0; i < r.ids.ids.size(); ++i) {
    const glm::uvec2 want = r.truth.ids[i].x == ring + 1 ? glm::uvec2(ring + 1, kExactTriangle) : r.truth.ids[i];
    mismatched += r.ids.ids[i] != want ? 1 : 0;
    ringPixels += r.ids.ids[i].x == ring + 1 ? 1 : 0;
  }
  EXPECT_EQ(mismatched, 0u);
  // A pixel the resolve step gave another hit keeps no shadow proof of the raster's; the others keep theirs.
  std::size_t changed = 0;
  for (std::size_t i = 0; i < r.ids.ids.size(); ++i) {
    const bool moved = r.ids.ids[i] != r.raster.ids[i];
    changed += moved ? 1 : 0;
    EXPECT_EQ(r.ids.proofs[i], moved ? 0u : 0xFFFFu) << "pixel " << i;
  }
  EXPECT_GT(changed, 0u);
  // The centre looks along the diagonal at the tube, in front of the post: the raster alone showed the post.
  const std::size_t centre = static_cast<std::size_t>(kH / 2) * kW + kW / 2;
  EXPECT_EQ(r.raster.ids[centre].x, 2u) << "the raster sees the post (the set-up is as meant)";
  EXPECT_EQ(r.ids.ids[centre], glm::uvec2(ring + 1, kExactTriangle));
  EXPECT_GT(ringPixels, 1000u);
}

TEST(ResolveExact, NothingToDoWithoutExactSolids) {
  const Scene scene = proxiesOnly(resolveScene());
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  VisibilityBuffer ids;
  tracer->castVisibility(scene.camera, kW, kH, ids);
  const VisibilityBuffer before = ids;
  std::vector<ResolvedPixel> records(3);
  RayCounts counts;
  tracer->resolveExact(scene, scene.camera, ids, records, counts);
  EXPECT_TRUE(records.empty());
  EXPECT_EQ(counts.resolved, 0u);
  EXPECT_EQ(ids.ids, before.ids);
}

TEST(ResolveExact, TheRayPassAndItsPixelTraceStartFromTheResolvedHits) {
  const Scene scene = resolveScene();
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  Resolved r = resolve(scene);
  FrameSettings s = settingsFor(kW, kH);
  RayOutputs out;
  tracer->trace(scene, scene.camera, s, r.ids, out);
  std::uint64_t surfaces = 0;
  for (const glm::uvec2& id : r.ids.ids) surfaces += id.x != 0 ? 1 : 0;
  EXPECT_EQ(out.counts.primary, surfaces) << "one exact primary hit per pixel with a surface, on the solids too";
  // A pixel on the sphere: its trace's primary hit lies on the exact sphere, not on its 8 × 4 proxy.
  for (const ResolvedPixel& rec : r.records) {
    if (rec.id != glm::uvec2(3u, kExactTriangle)) continue;
    const PixelTrace t = tracer->tracePixel(scene, scene.camera, s, r.ids, static_cast<int>(rec.pixel.x),
                                            static_cast<int>(rec.pixel.y));
    ASSERT_FALSE(t.roots.empty());
    const TraceNode& primary = t.nodes[static_cast<std::size_t>(t.roots.front())];
    ASSERT_TRUE(primary.hit);
    EXPECT_EQ(primary.triangle, kExactTriangle);
    EXPECT_NEAR(glm::length(primary.positionW - glm::vec3(0.3f, 0.6f, 0.3f)), 0.6f, 1e-4f);
    break;
  }
}

TEST(ResolveExact, HybridShadowMapsNeverTakeAProxyForItsSolid) {
  // A flat ring over a floor, the light straight above: the floor under the hole is lit, though its shadow
  // rays cross the ring's proxy box. The light-space maps may answer only what the rays would.
  Scene s;
  addInstance(s, addMesh(s, makePlane({8.0f, 8.0f}, 4)), addMaterial(s, diffuse(glm::vec3(0.7f))), glm::mat4(1.0f));
  addInstance(s, addMesh(s, exactMesh(leaf(solid::Shape::Torus, {1.0, 0.2, 0.0}))),
              addMaterial(s, diffuse(glm::vec3(0.4f))), translate({0.0f, 1.0f, 0.0f}));
  s.lights.push_back(directional({0.0f, -1.0f, 0.0f}));
  s.camera.posW = {0.0f, 6.0f, 1.0f};
  s.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto tracer = makeTracer(s);
  ASSERT_TRUE(tracer);
  FrameSettings rays = settingsFor(kW, kH);
  rays.reflections = rays.refraction = EffectMode::Off;
  FrameSettings maps = rays;
  maps.hybridShadows = true;
  VisibilityBuffer ids;
  tracer->castVisibility(s.camera, kW, kH, ids);
  std::vector<ResolvedPixel> records;
  RayCounts counts;
  tracer->resolveExact(s, s.camera, ids, records, counts);
  RayOutputs byRays, byMaps;
  tracer->trace(s, s.camera, rays, ids, byRays);
  tracer->trace(s, s.camera, maps, ids, byMaps);
  ASSERT_EQ(byRays.lightMask.size(), byMaps.lightMask.size());
  EXPECT_EQ(byRays.lightMask, byMaps.lightMask);
  EXPECT_GT(byMaps.counts.shadowByMap, 0u) << "the maps answered some";
  // The floor straight under the ring's centre is lit (the light comes through the hole).
  const glm::mat4 clip = s.camera.clipFromView(glm::ivec2(kW, kH)) * s.camera.viewFromWorld();
  const glm::vec4 c = clip * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  const int px = static_cast<int>((c.x / c.w * 0.5f + 0.5f) * kW), py = static_cast<int>((0.5f - c.y / c.w * 0.5f) * kH);
  const std::size_t g = static_cast<std::size_t>(py) * kW + static_cast<std::size_t>(px);
  EXPECT_EQ(ids.ids[g].x, 1u) << "the floor";
  EXPECT_EQ(byMaps.lightMask[g] & 1u, 1u) << "lit through the hole";
}

}  // namespace
}  // namespace tandem::rt
