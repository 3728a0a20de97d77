// Hybrid shadows (rt/ShadowCertainty.h, docs/shadows.md): the light-space maps answer shadow rays only
// where they can prove Embree's answer. The oracle is the all-rays pass itself: every frame here is
// rendered both ways and every output compared bit for bit, on scenes built to break the maps' argument
// (thin slabs, contacts, grazing light, extreme scales, far from the origin, a light at a surface,
// alpha-mask holes). Each also checks that the maps did decide most rays, so none passes by deciding none.
#include <cstring>

#include <gtest/gtest.h>

#include "RtTestScenes.h"
#include "ShadowScenes.h"
#include "core/RenderSpace.h"
#include "rt/RayMath.h"
#include "rt/ShadowCertainty.h"
#include "rt/Whitted.h"

namespace tandem::rt::test {
namespace {

struct Both {
  RayOutputs rays, hybrid;
  std::size_t maskDiffers = 0;  // pixels whose light mask differs
};

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Renders `scene` with every shadow ray traced and with hybrid shadows (two tracers, the same visibility),
// and compares the outputs.
Both renderBoth(const Scene& scene, FrameSettings s) {
  Both b;
  auto all = makeTracer(scene), hybrid = makeTracer(scene);
  if (!all || !hybrid) return b;
  VisibilityBuffer vis;
  all->castVisibility(scene.camera, s.width, s.height, vis);
  s.hybridShadows = false;
  all->trace(scene, scene.camera, s, vis, b.rays);
  s.hybridShadows = true;
  s.shadowProofs = ShadowProofs::Cpu;  // the maps alone (auto lets the tile shafts answer first)
  hybrid->trace(scene, scene.camera, s, vis, b.hybrid);
  EXPECT_EQ(b.rays.lightMask.size(), b.hybrid.lightMask.size());
  for (std::size_t i = 0; i < std::min(b.rays.lightMask.size(), b.hybrid.lightMask.size()); ++i)
    b.maskDiffers += b.rays.lightMask[i] != b.hybrid.lightMask[i];
  // Secondary hits use the maps too: what they shade must not change either.
  EXPECT_TRUE(sameBits(b.rays.reflected, b.hybrid.reflected));
  EXPECT_TRUE(sameBits(b.rays.transmitted, b.hybrid.transmitted));
  // Every shadow ray is either traced or answered by a map or a tile shaft (rt/TileShafts.h: the maps'
  // open rays are offered to the shafts).
  EXPECT_EQ(b.hybrid.counts.shadow + b.hybrid.counts.shadowByMap + b.hybrid.counts.shadowByShaft, b.rays.counts.shadow);
  EXPECT_EQ(b.rays.counts.shadowByMap, 0u);
  return b;
}

FrameSettings settings(int w, int h) {
  FrameSettings s = settingsFor(w, h);
  s.shadows = s.reflections = s.refraction = EffectMode::Ray;
  return s;
}

void expectMostDecided(const Both& b, double share) {
  const double all = static_cast<double>(b.rays.counts.shadow);
  ASSERT_GT(all, 0.0);
  EXPECT_GE(static_cast<double>(b.hybrid.counts.shadowByMap), share * all)
      << b.hybrid.counts.shadowByMap << " of " << all << " shadow rays decided by the maps";
}

TEST(HybridShadows, ObjectsOnAFloorGiveTheAllRaysMaskWithFarFewerRays) {
  Both b = renderBoth(objectsOnAFloor(), settings(320, 180));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.8);  // ≥ 5× fewer shadow rays
  EXPECT_GT(b.hybrid.counts.shadow, 0u);  // the edges and contacts are still traced
}

TEST(HybridShadows, ExtremeScalesAndFarFromTheOrigin) {
  for (float scale : {1e-4f, 1e4f}) {
    Both b = renderBoth(objectsOnAFloor(scale), settings(160, 90));
    EXPECT_EQ(b.maskDiffers, 0u) << "scale " << scale;
    expectMostDecided(b, 0.7);
  }
  // Render space is camera-relative, so a scene 1e6 from the origin keeps its precision.
  Both far = renderBoth(objectsOnAFloor(1.0f, glm::vec3(1e6f, -2e5f, 5e5f)), settings(160, 90));
  EXPECT_EQ(far.maskDiffers, 0u);
  expectMostDecided(far, 0.7);
}

// Slabs a thousandth thick over the floor, one just above it: the maps must not confuse their two faces or
// a slab with the floor under it.
TEST(HybridShadows, ThinSlabsAndContacts) {
  const Scene scene = thinSlabsAndContacts();
  Both b = renderBoth(scene, settings(320, 180));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.7);
}

// Light nearly parallel to a bumpy floor: long shadows, rays grazing every face.
TEST(HybridShadows, GrazingLight) {
  const Scene scene = grazingLight();
  Both b = renderBoth(scene, settings(320, 180));
  EXPECT_EQ(b.maskDiffers, 0u);
  // Grazing rays cross many faces near the plane, and the maps record the slivers these faces project to
  // conservatively: fewer rays can be proved (22 % here), but not none.
  expectMostDecided(b, 0.15);
}

// A point light a hair above a surface and another inside a box: the maps' near region.
TEST(HybridShadows, LightsAtSurfaces) {
  const Scene scene = lightsAtSurfaces();
  Both b = renderBoth(scene, settings(240, 135));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.5);
}

// An alpha-mask quad with holes: rays pass through its holes, so its triangles may only ever prove "lit".
// A 20-unit floor and a 3-unit quad of `quad` placed by `at`, a directional and a point light above, seen from
// above and to the side.
void quadOverAFloor(Scene& scene, const Material& quad, const glm::mat4& at) {
  std::uint32_t floorMat = addMaterial(scene, diffuse(glm::vec3(0.7f)));
  std::uint32_t quadMat = addMaterial(scene, quad);
  addInstance(scene, addMesh(scene, makePlane({20.0f, 20.0f}, 1)), floorMat, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, makePlane({3.0f, 3.0f}, 1)), quadMat, at);
  scene.lights.push_back(directional({0.1f, -1.0f, 0.05f}));
  scene.lights.push_back(pointLight({0.5f, 4.0f, 0.5f}));
  scene.camera.posW = {0.0f, 6.0f, 6.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
}

TEST(HybridShadows, AlphaMaskHolesAreNeverProvedShadowed) {
  Scene scene;
  Texture tex;  // columns alternate holes and solid
  tex.width = tex.height = 8;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) tex.rgba8.insert(tex.rgba8.end(), {200, 200, 200, static_cast<std::uint8_t>(x % 2 ? 0 : 255)});
  scene.textures.push_back(tex);
  Material cutout = diffuse(glm::vec3(0.8f));
  cutout.kdTexture = 0;
  cutout.alphaMode = AlphaMode::Mask;
  quadOverAFloor(scene, cutout, translate({0.0f, 1.0f, 0.0f}));
  Both b = renderBoth(scene, settings(240, 135));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.5);
  // Under the quad the hybrid pass still traces: only rays can see the holes.
  EXPECT_GT(b.hybrid.counts.shadow, 1000u);
}

// A single-sided quad turned away from the lights (its front faces the floor) lets their light through
// (docs/gltf.md, "Single-sided faces"): the maps, which prove only what Embree would answer, must never call
// the floor under it shadowed; the camera sees that floor through the quad's back.
TEST(HybridShadows, SingleSidedFacesTurnedAwayAreNeverProvedShadowed) {
  Scene scene;
  Material paper = diffuse(glm::vec3(0.8f));
  paper.doubleSided = false;
  quadOverAFloor(scene, paper, glm::rotate(translate({0.0f, 1.0f, 0.0f}), glm::pi<float>(), glm::vec3(1.0f, 0.0f, 0.0f)));
  Both b = renderBoth(scene, settings(240, 135));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.5);
}

// Mirrors and glass: the shadows at their reflected and refracted hits come from the maps too, and what
// they shade is unchanged (renderBoth compares the reflected and transmitted channels).
TEST(HybridShadows, SecondaryHitsAgreeInTheWhittedScene) {
  Scene scene = makeWhittedScene();
  Both b = renderBoth(scene, settings(320, 180));
  EXPECT_EQ(b.maskDiffers, 0u);
  expectMostDecided(b, 0.8);
  EXPECT_GT(b.rays.counts.reflection, 0u);
}

// The maps follow the geometry and the lights: a moved instance or light rebuilds them once, and the
// frame after still equals the all-rays one; an unchanged frame rebuilds nothing.
TEST(HybridShadows, MapsFollowMovesAndLightChanges) {
  Scene scene = objectsOnAFloor();
  scene.instances[1].dynamic = true;
  auto all = makeTracer(scene), hybrid = makeTracer(scene);
  ASSERT_TRUE(all && hybrid);
  FrameSettings s = settings(160, 90);
  VisibilityBuffer vis;
  auto frame = [&](std::size_t expectBuilds) {
    RayOutputs a, h;
    all->castVisibility(scene.camera, s.width, s.height, vis);
    s.hybridShadows = false;
    all->trace(scene, scene.camera, s, vis, a);
    s.hybridShadows = true;
    hybrid->trace(scene, scene.camera, s, vis, h);
    EXPECT_TRUE(sameBits(a.lightMask, h.lightMask));
    EXPECT_GT(h.counts.shadowByMap, 0u);
    EXPECT_EQ(hybrid->shadowMapBuilds(), expectBuilds);
  };
  frame(1);
  frame(1);  // nothing changed
  scene.instances[1].worldFromObject = translate({0.5f, 2.0f, 1.0f});
  all->updateTransforms(scene);
  hybrid->updateTransforms(scene);
  frame(2);
  scene.lights[0].posW = {1.0f, 4.0f, -2.0f};
  frame(3);
  frame(3);
  EXPECT_GT(hybrid->shadowMapBytes(), 0u);
}

// ---- every answer a map gives, against the ray Embree traces ----
// The all-rays comparison above sees one shadow ray per pixel and light. Here each answer is checked on its
// own, over many more rays, where Embree's rounding is largest: coordinates of 1e4–1e6 in object space or in
// the instance's translation, thin and grazing triangles, casters far larger than the receiver's own error
// bound. A wrong margin shows as a map answer that Embree's own ray contradicts.

struct Answers {
  std::size_t rays = 0, lit = 0, shadowed = 0;
};

Answers expectEveryAnswerIsEmbrees(const Scene& scene, int samplesPerSide) {
  Answers a;
  auto built = EmbreeScene::build(sharedTestDevice(), scene);
  EXPECT_TRUE(built.ok());
  if (!built.ok()) return a;
  const EmbreeScene& embree = **built;
  const FrameShading frame(scene, std::nullopt, embree.anchor());
  ShadowCertainty maps;
  maps.build(scene, embree, frame, 2);
  TraceModes modes;
  modes.primaryShadowRays = modes.secondaryShadowRays = true;
  const Whitted traced(scene, embree, frame, modes), proved(scene, embree, frame, modes, &maps);
  const Camera camera = toRenderSpace(scene.camera, embree.anchor());
  const CameraRays rays(camera, {samplesPerSide, samplesPerSide});
  std::size_t disagree = 0;
  for (int y = 0; y < samplesPerSide; ++y)
    for (int x = 0; x < samplesPerSide; ++x) {
      const glm::vec2 jitter(random01(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), 7u, 0u),
                             random01(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), 7u, 1u));
      const Ray ray = rays.through(glm::vec2(x, y) + jitter);
      float tNear, tFar;
      cameraSpan(camera, ray, tNear, tFar);
      std::uint32_t instance, triangle;
      if (!traced.intersect(ray.origin, ray.dir, tNear, tFar, instance, triangle)) continue;
      const SurfaceHit hit = resolveHit(scene, embree.transformAt(instance, 0.5f), instance, triangle, ray, tNear);
      for (std::size_t light = 0; light < frame.lights.size(); ++light) {
        SpawnOrigins fromMaps, fromRays;
        const ShadowRay m = proved.shadowRay(hit, light, fromMaps);
        if (!m.byMap) continue;
        const ShadowRay r = traced.shadowRay(hit, light, fromRays);
        EXPECT_TRUE(r.needed);
        RTCRay embreeRay;
        if (!makeEmbreeRay(embreeRay, r.originW, r.dirW, 0.0f, r.tFar, hit.time)) continue;
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(embree.top(), &ctx, &embreeRay);
        const bool lit = embreeRay.tfar >= 0.0f;
        ++a.rays;
        (m.visibleWithoutRay ? a.lit : a.shadowed) += 1;
        if (lit != m.visibleWithoutRay && ++disagree <= 5) {
          const glm::vec3 p = hit.posW + embree.anchor();
          ADD_FAILURE() << "light " << light << " at (" << p.x << ", " << p.y << ", " << p.z << "), instance " << instance
                        << ": the map says " << (m.visibleWithoutRay ? "lit" : "shadowed") << ", Embree's ray "
                        << (lit ? "reaches the light" : "is blocked");
        }
      }
    }
  EXPECT_EQ(disagree, 0u) << "of " << a.rays << " answers";
  return a;
}

// A mesh given in object space at `offset` (every vertex moved there), for an instance that moves it back:
// the same world, but Embree's object-space rounding is that of coordinates of |offset|.
Mesh movedInObjectSpace(Mesh m, glm::vec3 offset) {
  for (glm::vec3& p : m.positions) p += offset;
  return m;
}

TEST(HybridShadows, EveryAnswerIsEmbreesWithLargeObjectSpaceCoordinates) {
  for (float magnitude : {1e4f, 1e5f}) {
    SCOPED_TRACE(magnitude);
    // objectsOnAFloor, each mesh written at a large object-space offset and placed back by its instance: the
    // camera, the lights and the world stay near the origin.
    Scene scene = objectsOnAFloor();
    const glm::vec3 offset(magnitude, -0.5f * magnitude, 0.75f * magnitude);
    for (Instance& inst : scene.instances) {
      Mesh& mesh = scene.meshes[inst.mesh];
      mesh = movedInObjectSpace(mesh, offset);
      inst.worldFromObject = inst.worldFromObject * translate(-offset);
    }
    const Answers a = expectEveryAnswerIsEmbrees(scene, 400);
    std::printf("object space at %g: %zu map answers (%zu lit, %zu shadowed)\n", magnitude, a.rays, a.lit, a.shadowed);
    // The margin grows with the coordinates: the maps prove less the larger they are (at 1e5 a unit), but
    // they still prove what is far from every edge.
    EXPECT_GT(a.lit, 10000u);
  }
}

TEST(HybridShadows, EveryAnswerIsEmbreesUnderFarCasters) {
  // A small floor by the camera under a low directional light, and between them, 1e4–1e6 away along the
  // light: (a) a box of ordinary size, whose render-space translation (not its coordinates, nor the rays'
  // origins) sets Embree's rounding; (b) a wall about that size, whose top edge crosses the floor. Their
  // shadows' edges cross the floor, where the rays pass them closer than Embree's rounding there, thousands
  // of times the floor's own error bound.
  const glm::vec3 toLight = glm::normalize(glm::vec3(std::cos(glm::radians(30.0f)), std::sin(glm::radians(30.0f)), -0.05f));
  for (float distance : {1e4f, 1e5f, 1e6f})
    for (bool wall : {false, true}) {
      SCOPED_TRACE(std::to_string(distance) + (wall ? " wall" : " box"));
      Scene scene;
      const std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
      addInstance(scene, addMesh(scene, makePlane({4.0f, 4.0f}, 8)), mat, glm::mat4(1.0f));
      const glm::vec3 at = toLight * distance;
      if (wall) {
        // Its front face across the light's path, its top edge level with the floor's centre line.
        const float thick = 0.01f * distance;
        addInstance(scene, addMesh(scene, makeBox({1.0f, 1.0f, 1.0f})), mat,
                    translate(at + glm::vec3(0.5f * thick, -0.5f * distance, 0.0f)) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(thick, distance, 2.0f * distance)));
      } else {
        addInstance(scene, addMesh(scene, makeBox({2.5f, 2.5f, 2.5f})), mat, translate(at + glm::vec3(0.7f, 0.3f, -0.4f)));
      }
      // A thin sliver near the floor, crossed at small angles.
      addInstance(scene, addMesh(scene, makeBox({0.02f, 0.004f, 3.0f})), mat, translate({-1.0f, 0.3f, 0.0f}));
      scene.lights.push_back(directional(-toLight));
      scene.camera.posW = {0.0f, 3.0f, 4.0f};
      scene.camera.targetW = {0.0f, 0.0f, 0.0f};
      const Answers a = expectEveryAnswerIsEmbrees(scene, 400);
      std::printf("%s at %g: %zu map answers (%zu lit, %zu shadowed)\n", wall ? "wall" : "box", distance, a.rays, a.lit,
                  a.shadowed);
      // Beyond 1e4 the margins (a unit and more) swallow the floor: little or nothing is provable, and the
      // maps must say so rather than answer.
      if (distance <= 1e4f) {
        EXPECT_GT(a.rays, 10000u);
      }
    }
}

TEST(HybridShadows, EveryAnswerIsEmbreesSeenFromFarAway) {
  // The scene and its lights 1e3–1e5 from the camera, seen through a long lens: render space is anchored at
  // the camera, so every point the maps judge, and every light, is far from its origin, while the rays are
  // short. The maps' depth margins must grow with that distance (contacts, the box on the floor).
  for (float distance : {1e3f, 1e4f, 1e5f}) {
    SCOPED_TRACE(distance);
    const glm::vec3 offset(0.6f * distance, 0.0f, -0.8f * distance);
    Scene scene = objectsOnAFloor(1.0f, offset);
    const glm::vec3 target = offset + glm::vec3(0.0f, 0.5f, 0.0f);
    scene.camera.posW = {0.0f, 0.3f * distance, 0.0f};
    scene.camera.targetW = target;
    scene.camera.yFovDeg = glm::degrees(2.0f * std::atan(6.0f / glm::length(target - scene.camera.posW)));
    scene.camera.nearZ = 0.5f * distance;
    const Answers a = expectEveryAnswerIsEmbrees(scene, 400);
    std::printf("seen from %g: %zu map answers (%zu lit, %zu shadowed)\n", distance, a.rays, a.lit, a.shadowed);
    EXPECT_GT(a.lit, 1000u);
  }
}

}  // namespace
}  // namespace tandem::rt::test
