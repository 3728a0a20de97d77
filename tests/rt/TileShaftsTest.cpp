// Tile shafts (rt/TileShafts.h, docs/shadows.md "Tile shafts"): a tile's shadow rays towards a light are
// answered lit together, without tracing, where nothing but their points' own plane can lie on any of them.
// The shaft's geometry is checked on its own (every segment between the boxes lies inside it); the pass is
// checked against the all-rays pass bit for bit on the scenes built to break the hybrid shadows' proofs,
// and on ones that break the shafts' own argument (a concave mesh shadowing itself, tilted, stretched and
// far-away planes, grazing and near lights, directional lights), each also required to have answered a
// real share of its rays, so that none passes by answering nothing.
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "RtTestScenes.h"
#include "ShadowScenes.h"
#include "rt/TileShafts.h"

namespace tandem::rt::test {
namespace {

// ---- the shaft ----

ShaftBox boxAround(glm::dvec3 c, glm::dvec3 half) {
  ShaftBox b;
  b.lo = c - half;
  b.hi = c + half;
  return b;
}

TEST(TileShafts, EverySegmentBetweenTheBoxesIsInsideTheShaft) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&](double scale) { return glm::dvec3(u(rng), u(rng), u(rng)) * scale; };
  int cut = 0;  // obstacles in the union box that the planes showed outside
  for (int trial = 0; trial < 2000; ++trial) {
    const ShaftBox from = boxAround(point(10.0), glm::abs(point(2.0)));
    const ShaftBox to = boxAround(point(10.0), glm::abs(point(trial % 3 == 0 ? 0.01 : 2.0)));
    // A tiny obstacle on a random segment between the boxes is never outside the shaft.
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 a = from.lo + (from.hi - from.lo) * glm::abs(glm::dvec3(u(rng), u(rng), u(rng)));
      const glm::dvec3 b = to.lo + (to.hi - to.lo) * glm::abs(glm::dvec3(u(rng), u(rng), u(rng)));
      const glm::dvec3 on = a + (b - a) * std::abs(u(rng));
      ASSERT_FALSE(shaftMisses(from, to, boxAround(on, glm::dvec3(1e-9)))) << "trial " << trial;
    }
    // A random obstacle: when the shaft says it misses, no sampled segment touches it.
    const ShaftBox obstacle = boxAround(point(10.0), glm::abs(point(1.0)));
    if (!shaftMisses(from, to, obstacle)) continue;
    bool inUnion = true;
    for (int axis = 0; axis < 3; ++axis)
      inUnion = inUnion && obstacle.hi[axis] >= std::min(from.lo[axis], to.lo[axis]) &&
                obstacle.lo[axis] <= std::max(from.hi[axis], to.hi[axis]);
    cut += inUnion ? 1 : 0;
    for (int k = 0; k < 64; ++k) {
      const glm::dvec3 a = from.lo + (from.hi - from.lo) * glm::abs(glm::dvec3(u(rng), u(rng), u(rng)));
      const glm::dvec3 b = to.lo + (to.hi - to.lo) * glm::abs(glm::dvec3(u(rng), u(rng), u(rng)));
      for (double t = 0.0; t <= 1.0; t += 1.0 / 64.0) {
        const glm::dvec3 p = a + (b - a) * t;
        ASSERT_FALSE(glm::all(glm::greaterThanEqual(p, obstacle.lo)) && glm::all(glm::lessThanEqual(p, obstacle.hi)))
            << "trial " << trial << ": a segment crosses an obstacle said to miss the shaft";
      }
    }
  }
  // The planes do cut: many obstacles inside the union box were shown outside the hull.
  EXPECT_GT(cut, 50);
}

TEST(TileShafts, ABoxBesideTheShaftMissesItAndOneAcrossItDoesNot) {
  // From a patch of floor up to a point light at (0, 10, 0): a box off to the side of the path, inside the
  // union box, misses; one on the path does not.
  const ShaftBox floor = boxAround({5.0, 0.0, 0.0}, {0.5, 1e-3, 0.5});
  const ShaftBox light = boxAround({0.0, 10.0, 0.0}, glm::dvec3(1e-6));
  EXPECT_TRUE(shaftMisses(floor, light, boxAround({4.5, 8.0, 0.0}, glm::dvec3(0.3))));
  EXPECT_FALSE(shaftMisses(floor, light, boxAround({2.5, 5.0, 0.0}, glm::dvec3(0.3))));
  EXPECT_TRUE(shaftMisses(floor, light, boxAround({20.0, 5.0, 0.0}, glm::dvec3(0.3))));
  EXPECT_TRUE(shaftMisses(floor, light, ShaftBox{}));  // empty: nothing to meet
}

TEST(TileShafts, OnlyExactAxisPlanesAreOwnPlanes) {
  EXPECT_EQ(axisPlane(makePlane({4.0f, 4.0f}, 8)), 1);
  EXPECT_EQ(axisPlane(makeBox({1.0f, 1.0f, 1.0f})), -1);
  EXPECT_EQ(axisPlane(makeSphere(1.0f, 8, 4)), -1);
  Mesh bent = makePlane({4.0f, 4.0f}, 8);
  bent.positions[bent.indices[40]].y = std::nextafter(bent.positions[bent.indices[40]].y, 1.0f);
  EXPECT_EQ(axisPlane(bent), -1);  // one vertex an ulp off
  Mesh wall = makePlane({4.0f, 4.0f}, 2);
  for (glm::vec3& p : wall.positions) p = glm::vec3(3.0f, p.z, p.x);
  EXPECT_EQ(axisPlane(wall), 0);
  Mesh broken = makePlane({4.0f, 4.0f}, 2);
  broken.indices.back() = static_cast<std::uint32_t>(broken.positions.size());
  EXPECT_EQ(axisPlane(broken), -1);  // an index out of range: no claim
  EXPECT_EQ(axisPlane(Mesh{}), -1);
}

// The plane a joining instance lies in, in render space, from its object-space axis plane and its transform;
// and the instances that may not join.
TEST(TileShafts, PlanesFollowTheirTransformsAndIllConditionedOnesDoNotJoin) {
  Scene scene;
  const std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  const glm::mat4 placed = translate({3.0f, -2.0f, 5.0f}) *
                           glm::rotate(glm::mat4(1.0f), glm::radians(40.0f), glm::normalize(glm::vec3(1.0f, 0.5f, -0.2f))) *
                           glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, 2.0f, 2.0f));
  Mesh floor = makePlane({4.0f, 4.0f}, 2);
  for (glm::vec3& p : floor.positions) p.y = 0.75f;  // the plane y = 0.75 of object space
  addInstance(scene, addMesh(scene, floor), mat, placed);
  addInstance(scene, addMesh(scene, makePlane({4.0f, 4.0f}, 2)), mat,
              glm::scale(glm::mat4(1.0f), glm::vec3(40.0f, 1.0f, 0.5f)));  // condition ~80: does not join
  addInstance(scene, addMesh(scene, makeSphere(1.0f, 8, 4)), mat, translate({0.0f, 3.0f, 0.0f}));
  auto built = EmbreeScene::build(sharedTestDevice(), scene);
  ASSERT_TRUE(built.ok());
  std::vector<int> planes;
  for (const Mesh& m : scene.meshes) planes.push_back(axisPlane(m));
  TileShafts shafts;
  shafts.build(scene, **built, reuseMeshBounds(scene), planes, 0.5f);
  ASSERT_TRUE(shafts.active());
  EXPECT_TRUE(shafts.joins(0));
  EXPECT_FALSE(shafts.joins(1));
  EXPECT_FALSE(shafts.joins(2));
  // Render space is world space less the anchor (the camera's position at build).
  const glm::dvec3 anchor((*built)->anchor());
  const glm::dvec3 normal = glm::normalize(glm::dvec3(glm::transpose(glm::inverse(glm::mat3(placed))) * glm::vec3(0, 1, 0)));
  EXPECT_NEAR(std::abs(glm::dot(shafts.planeNormal(0), normal)), 1.0, 1e-6);
  for (const glm::vec3& p : floor.positions) {
    const glm::dvec3 onPlane = glm::dvec3(placed * glm::vec4(p, 1.0f)) - anchor;
    EXPECT_NEAR(glm::dot(shafts.planeNormal(0), onPlane), shafts.planeOffset(0), 1e-5);
  }
}

// ---- the pass, against every ray traced ----

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

struct Both {
  RayOutputs rays, shafts;
};

// `scene` traced with every shadow ray and with the shafts alone (no maps; or `proofs`), on the same
// visibility: the outputs must be the same to the bit, every ray either traced or answered by a proof.
Both renderBoth(const Scene& scene, int w, int h, ShadowProofs proofs = ShadowProofs::Shafts) {
  Both b;
  auto all = makeTracer(scene), shafted = makeTracer(scene);
  if (!all || !shafted) return b;
  FrameSettings s = settingsFor(w, h);
  s.shadows = s.reflections = s.refraction = EffectMode::Ray;
  VisibilityBuffer vis;
  all->castVisibility(scene.camera, s.width, s.height, vis);
  s.hybridShadows = false;
  all->trace(scene, scene.camera, s, vis, b.rays);
  s.hybridShadows = true;
  s.shadowProofs = proofs;
  shafted->trace(scene, scene.camera, s, vis, b.shafts);
  EXPECT_TRUE(sameBits(b.rays.lightMask, b.shafts.lightMask));
  EXPECT_TRUE(sameBits(b.rays.areaSamples, b.shafts.areaSamples));
  EXPECT_TRUE(sameBits(b.rays.reflected, b.shafts.reflected));
  EXPECT_TRUE(sameBits(b.rays.transmitted, b.shafts.transmitted));
  // Every ray is traced or answered; the shafts answer a point's light without asking whether it needed a ray.
  EXPECT_LE(b.shafts.counts.shadow + b.shafts.counts.shadowByMap, b.rays.counts.shadow);
  EXPECT_GE(b.shafts.counts.shadow + b.shafts.counts.shadowByShaft + b.shafts.counts.shadowByMap, b.rays.counts.shadow);
  if (proofs == ShadowProofs::Shafts) {
    EXPECT_EQ(b.shafts.counts.shadowByMap, 0u);  // the maps are not built
  }
  EXPECT_EQ(b.rays.counts.shadowByShaft, 0u);  // and without hybrid shadows nothing is answered
  return b;
}

// The share of the all-rays pass's shadow rays the shafts left untraced (the maps' answers apart).
void expectAnswered(const Both& b, double share) {
  const double all = static_cast<double>(b.rays.counts.shadow);
  ASSERT_GT(all, 0.0);
  const double untraced = all - static_cast<double>(b.shafts.counts.shadow + b.shafts.counts.shadowByMap);
  std::printf("shafts answered %.1f %% of %.0f shadow rays\n", 100.0 * untraced / all, all);
  EXPECT_GE(untraced, share * all) << untraced << " of " << all << " shadow rays answered by shafts";
}

TEST(TileShafts, ObjectsOnAFloorAtEveryScaleAndFarFromTheOrigin) {
  for (float scale : {1e-4f, 1.0f, 1e4f}) {
    SCOPED_TRACE(scale);
    expectAnswered(renderBoth(objectsOnAFloor(scale), 240, 135), 0.6);
  }
  expectAnswered(renderBoth(objectsOnAFloor(1.0f, glm::vec3(1e6f, -2e5f, 5e5f)), 240, 135), 0.6);
}

TEST(TileShafts, HostileScenesOfTheHybridShadows) {
  expectAnswered(renderBoth(thinSlabsAndContacts(), 240, 135), 0.6);
  // Light a hair above the floor: its rays graze the plane and are left to Embree; the others still answer.
  expectAnswered(renderBoth(lightsAtSurfaces(), 240, 135), 0.02);
  // A bumpy floor is no plane: only the flat-topped box could join, and its rays graze.
  renderBoth(grazingLight(), 240, 135);
}

TEST(TileShafts, MirrorsAndGlassOfTheWhittedScene) {
  Both b = renderBoth(makeWhittedScene(), 240, 135);
  expectAnswered(b, 0.3);
  EXPECT_GT(b.rays.counts.reflection, 0u);
}

// Auto: the shafts first, then the maps for what they leave open (in the ray pass: no GL here). Fewer rays
// than either alone, the same bits.
TEST(TileShafts, ThenTheMaps) {
  for (const Scene& scene : {objectsOnAFloor(), makeWhittedScene()}) {
    const Both b = renderBoth(scene, 240, 135, ShadowProofs::Auto);
    expectAnswered(b, 0.3);
    EXPECT_GT(b.shafts.counts.shadowByMap, 0u) << "the maps answer some of the rest";
    EXPECT_LT(b.shafts.counts.shadow, b.rays.counts.shadow / 5);
  }
}

// The planes placed by their transforms: tilted, stretched unevenly, and written far from their object
// space's origin (Embree's rounding follows those coordinates); a wall; a floor under a directional light only.
TEST(TileShafts, TiltedStretchedAndFarPlanes) {
  for (int variant = 0; variant < 4; ++variant) {
    SCOPED_TRACE(variant);
    Scene scene = objectsOnAFloor();
    Instance& floor = scene.instances[0];
    if (variant == 0) floor.worldFromObject = glm::rotate(glm::mat4(1.0f), glm::radians(17.0f), glm::vec3(1.0f, 0.2f, 0.1f));
    if (variant == 1) floor.worldFromObject = glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 0.5f, 0.2f));
    if (variant == 2) {
      const glm::vec3 offset(1e4f, -5e3f, 7.5e3f);
      Mesh& mesh = scene.meshes[floor.mesh];
      for (glm::vec3& p : mesh.positions) p += offset;
      floor.worldFromObject = translate(-offset);
    }
    if (variant == 3) {
      // A wall behind the objects, facing the camera, and only the directional light.
      addInstance(scene, addMesh(scene, makePlane({12.0f, 6.0f}, 4)), scene.instances[0].material,
                  translate({0.0f, 3.0f, -4.0f}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
      scene.lights.erase(scene.lights.begin(), scene.lights.begin() + 2);
      scene.lights[0].dirW = glm::normalize(glm::vec3(0.3f, -1.0f, -0.6f));
    }
    expectAnswered(renderBoth(scene, 240, 135), 0.3);
  }
}

// Rays that would leave their plane at a grazing angle, and a plane under a transform too ill-conditioned to
// trust its sign, are left to Embree: the shafts answer none of them.
TEST(TileShafts, GrazingLightsAndShearedPlanesAreLeftToEmbree) {
  Scene low;
  const std::uint32_t mat = addMaterial(low, diffuse(glm::vec3(0.8f)));
  addInstance(low, addMesh(low, makePlane({20.0f, 20.0f}, 4)), mat, glm::mat4(1.0f));
  addInstance(low, addMesh(low, makeBox({1.0f, 1.0f, 1.0f})), mat, translate({0.0f, 0.5f, -6.0f}));
  low.lights.push_back(pointLight({100.0f, 0.45f, 0.0f}));  // a sine under 0.005 everywhere on the floor
  low.lights.push_back(directional({1.0f, -0.004f, 0.0f}));
  low.camera.posW = {0.0f, 4.0f, 9.0f};
  low.camera.targetW = {0.0f, 0.0f, 0.0f};
  Both b = renderBoth(low, 160, 90);
  EXPECT_EQ(b.shafts.counts.shadowByShaft, 0u);
  EXPECT_GT(b.rays.counts.shadow, 10000u);
  Scene sheared = objectsOnAFloor();
  glm::mat4 shear(1.0f);
  shear[1][0] = 40.0f;  // x += 40 y: the floor (y = 0) stays put, its transform's condition ~1600
  sheared.instances[0].worldFromObject = shear;
  b = renderBoth(sheared, 160, 90);
  EXPECT_EQ(b.shafts.counts.shadowByShaft, 0u);
}

// Motion blur: the sphere crosses the floor's shafts while the shutter is open. The bounds are where Embree
// puts each instance at the pass's time (an early and a late sample), not where it stands mid-shutter.
TEST(TileShafts, BoundsAreAtThePassesShutterTime) {
  Scene scene = objectsOnAFloor();
  scene.instances[1].velocity = glm::vec3(6.0f, 0.0f, 0.0f);  // 3 across the 0.5 s shutter
  scene.camera.shutter = 0.5f;
  for (float timeU : {0.05f, 0.95f}) {
    SCOPED_TRACE(timeU);
    scene.camera.timeU = timeU;
    auto all = RayTracer::create(2), shafted = RayTracer::create(2);
    ASSERT_TRUE(all.ok() && shafted.ok());
    ASSERT_TRUE((*all)->setScene(scene, scene.camera.shutter).ok());
    ASSERT_TRUE((*shafted)->setScene(scene, scene.camera.shutter).ok());
    FrameSettings s = settingsFor(240, 135);
    s.shadows = s.reflections = s.refraction = EffectMode::Ray;
    VisibilityBuffer vis;
    (*all)->castVisibility(scene.camera, s.width, s.height, vis);
    RayOutputs rays, shafts;
    (*all)->trace(scene, scene.camera, s, vis, rays);
    s.hybridShadows = true;
    s.shadowProofs = ShadowProofs::Shafts;
    (*shafted)->trace(scene, scene.camera, s, vis, shafts);
    EXPECT_TRUE(sameBits(rays.lightMask, shafts.lightMask));
    EXPECT_GT(shafts.counts.shadowByShaft, 10000u);
    EXPECT_LT(shafts.counts.shadow, rays.counts.shadow);
  }
}

// A concave mesh shadows itself: only a mesh in one plane may be passed over as its points' own. Here an
// L-shaped step (one mesh) under a light that makes its riser shade its tread.
TEST(TileShafts, ConcaveMeshesAreNotTheirOwnPlane) {
  Scene scene = objectsOnAFloor();
  Mesh step = makeBox({2.0f, 0.4f, 2.0f});
  const Mesh riser = makeBox({0.4f, 1.6f, 2.0f});
  const auto base = static_cast<std::uint32_t>(step.positions.size());
  for (const glm::vec3& p : riser.positions) step.positions.push_back(p + glm::vec3(-0.8f, 0.8f, 0.0f));
  step.normals.insert(step.normals.end(), riser.normals.begin(), riser.normals.end());
  if (!step.uvs.empty()) step.uvs.insert(step.uvs.end(), riser.uvs.begin(), riser.uvs.end());
  for (std::uint32_t i : riser.indices) step.indices.push_back(base + i);
  ASSERT_EQ(axisPlane(step), -1);
  addInstance(scene, addMesh(scene, step), scene.instances[0].material, translate({0.0f, 0.2f, 2.5f}));
  scene.lights.push_back(pointLight({-4.0f, 2.5f, 2.5f}));
  expectAnswered(renderBoth(scene, 240, 135), 0.4);
}

}  // namespace
}  // namespace tandem::rt::test
