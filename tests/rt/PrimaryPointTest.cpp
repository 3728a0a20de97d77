// The ray pass's lean primary point (resolvePrimaryPoint) against the whole hit it stands in for
// (resolvePrimary): every field a shadow ray reads must be the same to the bit, or the pass's masks would
// depend on which of the two a pixel took.
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rt/EmbreeScene.h"
#include "rt/RtTestScenes.h"
#include "rt/ShadowScenes.h"
#include "rt/SurfaceShading.h"
#include "rt/Whitted.h"
#include "support/TestSupport.h"
#include "tandem/Primitives.h"
#include "tandem/SceneFile.h"

namespace tandem::rt::test {
namespace {

bool sameBits(glm::vec3 a, glm::vec3 b) {
  return std::bit_cast<std::uint32_t>(a.x) == std::bit_cast<std::uint32_t>(b.x) &&
         std::bit_cast<std::uint32_t>(a.y) == std::bit_cast<std::uint32_t>(b.y) &&
         std::bit_cast<std::uint32_t>(a.z) == std::bit_cast<std::uint32_t>(b.z);
}

// Every visible pixel of `scene` whose instance the pass would give the lean point, with its own triangle and
// with the next triangle of the mesh (a ray that passes outside it: the clamped barycentrics). Returns the
// number of points compared.
int comparePoints(const Scene& scene, int w, int h, const std::string& name) {
  auto tracer = makeTracer(scene, 2);
  EXPECT_TRUE(tracer) << name;
  if (!tracer) return 0;
  auto embree = EmbreeScene::build(sharedTestDevice(), scene);
  EXPECT_TRUE(embree.ok()) << name;
  if (!embree.ok()) return 0;
  VisibilityBuffer vis;
  tracer->castVisibility(scene.camera, w, h, vis);
  const FrameShading frame(scene, std::nullopt, (*embree)->anchor());
  const Camera cam = toRenderSpace(scene.camera, (*embree)->anchor());
  const CameraRays rays(cam, {w, h});
  int compared = 0, differing = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::uvec2 id = vis.ids[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
      if (id.x == 0) continue;
      const std::uint32_t instance = id.x - 1;
      // The geometry is the same whether or not the material spawns rays; the test covers both.
      if (primaryNeedsWholeHit(scene, frame, instance, false)) continue;
      const Ray ray = rays.through(glm::vec2(x, y) + 0.5f);
      const auto triangles = static_cast<std::uint32_t>(scene.meshes[scene.instances[instance].mesh].triangleCount());
      for (std::uint32_t triangle : {id.y, (id.y + 1) % triangles}) {
        const InstanceTransform& transform = (*embree)->transform(instance);
        const SurfaceHit whole = resolvePrimary(scene, transform, cam, {id.x, triangle}, ray);
        const ShadowPoint lean = resolvePrimaryPoint(scene, transform, {id.x, triangle}, ray);
        ++compared;
        const bool same = lean.instance == whole.instance && lean.triangle == whole.triangle &&
                          lean.material == whole.material && sameBits(lean.posW, whole.posW) &&
                          sameBits(lean.posMagnitude, whole.posMagnitude) &&
                          sameBits(lean.geomNormalW, whole.geomNormalW) && sameBits(lean.normalW, whole.normalW);
        if (!same && ++differing <= 3)
          ADD_FAILURE() << name << ": pixel (" << x << ", " << y << ") triangle " << triangle << " differs";
      }
    }
  EXPECT_EQ(differing, 0) << name;
  return compared;
}

// A scene to test on, and its name.
struct Case {
  std::string name;
  Scene scene;
};

// The project's scene files by name (assets/scenes), each one that loads.
std::vector<Case> sceneFiles(std::initializer_list<const char*> files) {
  std::vector<Case> cases;
  for (const char* file : files) {
    auto loaded = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/" + file);
    EXPECT_TRUE(loaded.ok()) << file;
    if (loaded) cases.push_back({file, std::move(*loaded)});
  }
  return cases;
}

TEST(PrimaryPointTest, IsTheWholeHitsPointToTheBit) {
  std::vector<Case> cases = sceneFiles({"whitted.json", "cornell-mirror.json"});
  ASSERT_EQ(cases.size(), 2u);
  cases.push_back({"objects on a floor", objectsOnAFloor()});
  cases.push_back({"at 1e-4", objectsOnAFloor(1e-4f)});
  cases.push_back({"at 1e4", objectsOnAFloor(1e4f)});
  cases.push_back({"1e6 from the origin", objectsOnAFloor(1.0f, glm::vec3(1e6f, 0.0f, -1e6f))});
  cases.push_back({"grazing light, no vertex normals", grazingLight()});
  cases.push_back({"thin slabs", thinSlabsAndContacts()});
  // Seen from below the floor: every hit a back face, its normals flipped to the viewer.
  Scene below = objectsOnAFloor();
  below.camera.posW = {0.5f, -3.0f, 6.0f};
  cases.push_back({"back faces", below});
  for (const Case& c : cases) EXPECT_GT(comparePoints(c.scene, 96, 54, c.name), 1000) << c.name;
}

TEST(PrimaryPointTest, ZeroAreaTriangleFacesTheRay) {
  Scene scene;
  Mesh needle;
  needle.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}};  // collinear
  needle.indices = {0, 1, 2};
  const std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.5f)));
  addInstance(scene, addMesh(scene, needle), mat, translate({0.0f, 1.0f, 0.0f}));
  auto embree = EmbreeScene::build(sharedTestDevice(), scene);
  ASSERT_TRUE(embree.ok());
  const FrameShading frame(scene, std::nullopt, (*embree)->anchor());
  ASSERT_FALSE(primaryNeedsWholeHit(scene, frame, 0, true));
  const Ray ray{glm::vec3(1.0f, 3.0f, 2.0f) - (*embree)->anchor(), glm::normalize(glm::vec3(0.0f, -1.0f, -1.0f))};
  const SurfaceHit whole = resolveHit(scene, (*embree)->transform(0), 0, 0, ray);
  const ShadowPoint lean = resolvePrimaryPoint(scene, (*embree)->transform(0), {1u, 0u}, ray);
  EXPECT_TRUE(sameBits(lean.posW, whole.posW));
  EXPECT_TRUE(sameBits(lean.geomNormalW, whole.geomNormalW));
  EXPECT_TRUE(sameBits(lean.geomNormalW, -ray.dir));  // no plane: faces the ray
  EXPECT_TRUE(sameBits(lean.normalW, whole.normalW));
}

// The pass's light masks against the whole hit's: each pixel's mask and area-light sample bits from
// Whitted::lightMask on resolvePrimary's SurfaceHit (one ray at a time, no lean point), and the same number of
// shadow rays. Scenes with every kind of primary hit: plain (lean), mirror, glass, BLEND, a procedural bump, a
// normal map, exact solids (csg.json), and an area light.
TEST(PrimaryPointTest, ThePassMasksAreTheWholeHitsMasks) {
  Scene mixed = objectsOnAFloor();
  Texture wavy;
  wavy.width = wavy.height = 2;
  wavy.srgb = false;
  wavy.rgba8 = {200, 128, 230, 255, 60, 128, 230, 255, 128, 200, 230, 255, 128, 60, 230, 255};
  mixed.textures.push_back(wavy);
  Material bumped = diffuse(glm::vec3(0.7f));
  bumped.procedural.type = Pattern::Noise;
  bumped.procedural.scale = 4.0f;
  bumped.procedural.bump = 0.8f;
  Material mapped = diffuse(glm::vec3(0.6f));
  mapped.normalTexture = 0;
  Material mirror = diffuse(glm::vec3(0.2f));
  mirror.kr = 0.7f;
  Material blend = diffuse(glm::vec3(0.5f));
  blend.alphaMode = AlphaMode::Blend;
  Mesh box = makeBox({1.0f, 1.0f, 1.0f});
  box.tangents.assign(box.positions.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  mixed.instances[1].material = addMaterial(mixed, bumped);  // the sphere
  mixed.instances[2].material = addMaterial(mixed, mapped);  // the box, with tangents
  mixed.instances[2].mesh = addMesh(mixed, box);
  addInstance(mixed, addMesh(mixed, makeSphere(0.6f, 32, 16)), addMaterial(mixed, mirror), translate({0.0f, 0.6f, 2.0f}));
  addInstance(mixed, addMesh(mixed, makeBox({0.8f, 0.8f, 0.8f})), addMaterial(mixed, blend), translate({-0.5f, 0.4f, 3.0f}));
  Light lamp = pointLight({1.0f, 4.0f, 2.0f});
  lamp.type = LightType::Sphere;
  lamp.radius = 0.4f;
  mixed.lights.push_back(lamp);
  std::vector<Case> cases = sceneFiles({"whitted.json", "csg.json"});
  ASSERT_EQ(cases.size(), 2u);
  cases.push_back({"every kind of primary hit", mixed});
  const int w = 96, h = 54;
  for (const Case& c : cases) {
    const Scene& scene = c.scene;
    auto tracer = makeTracer(scene, 2);
    ASSERT_TRUE(tracer) << c.name;
    auto embree = EmbreeScene::build(sharedTestDevice(), scene);
    ASSERT_TRUE(embree.ok()) << c.name;
    // With secondary rays (mirrors, glass and BLEND take the whole hit) and without (they too take the lean
    // point; the pass's shadow rays are then the primary hits' alone, and counted as the whole hits' are).
    for (const int depth : {FrameSettings{}.maxDepth, 0}) {
      FrameSettings s = settingsFor(w, h);
      s.shadows = s.reflections = s.refraction = EffectMode::Ray;
      s.lightSamples = 4;
      s.maxDepth = depth;
      VisibilityBuffer vis;
      tracer->castVisibility(scene.camera, w, h, vis);
      RayOutputs out;
      tracer->trace(scene, scene.camera, s, vis, out);
      const FrameShading frame = FrameShading::forFrame(scene, s, scene.camera.sampleIndex, (*embree)->anchor(), nullptr);
      const Whitted whitted(scene, **embree, frame, TraceModes::hybrid(s));
      const Camera cam = toRenderSpace(scene.camera, (*embree)->anchor());
      const CameraRays rays(cam, {w, h});
      RayCounts counts;
      int differing = 0, lean = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
          const glm::uvec2 id = vis.ids[i];
          if (id.x == 0) continue;
          lean += primaryNeedsWholeHit(scene, frame, id.x - 1, depth > 0) ? 0 : 1;
          SurfaceHit hit =
              resolvePrimary(scene, (*embree)->transform(id.x - 1), cam, id, rays.through(glm::vec2(x, y) + 0.5f));
          hit.time = rays.time();
          hit.lightSeed = shading::tdPixelSeed(x, y, 0u);
          AreaSampleBits area{};
          const std::uint32_t mask = whitted.lightMask(hit, counts, &area);
          bool same = mask == out.lightMask[i];
          for (int a = 0; a < out.areaLights; ++a)
            same = same && area[static_cast<std::size_t>(a)] ==
                               out.areaSamples[static_cast<std::size_t>(a) * out.lightMask.size() + i];
          if (!same && ++differing <= 3)
            ADD_FAILURE() << c.name << " depth " << depth << ": pixel (" << x << ", " << y << ") differs";
        }
      EXPECT_EQ(differing, 0) << c.name << " depth " << depth;
      if (depth == 0) {
        EXPECT_EQ(counts.shadow, out.counts.shadow) << c.name;
      }
      EXPECT_GT(lean, 500) << c.name << " depth " << depth << ": the lean path was not taken";
    }
  }
}

// Which primary hits get the whole record: those that spawn rays (when the frame traces any), and those whose
// point or normal is more than the triangle's.
TEST(PrimaryPointTest, WholeHitsAreTheOnesThatNeedThem) {
  Scene scene;
  const std::uint32_t plane = addMesh(scene, makePlane({2.0f, 2.0f}, 1));
  Material mirror = diffuse(glm::vec3(0.5f));
  mirror.kr = 0.8f;
  Material glass = diffuse(glm::vec3(0.5f));
  glass.kt = 0.9f;
  Material blend = diffuse(glm::vec3(0.5f));
  blend.alphaMode = AlphaMode::Blend;
  Material bumped = diffuse(glm::vec3(0.5f));
  bumped.procedural.type = Pattern::Marble;
  bumped.procedural.bump = 0.5f;
  Material patterned = bumped;
  patterned.procedural.bump = 0.0f;  // a pattern alone changes the colour, not the point
  // A normal map changes N where the mesh has tangents and uvs to place it.
  Texture flat;
  flat.width = flat.height = 1;
  flat.rgba8 = {128, 128, 255, 255};
  scene.textures.push_back(flat);
  Material normalMapped = diffuse(glm::vec3(0.5f));
  normalMapped.normalTexture = 0;
  Mesh tangentPlane = makePlane({2.0f, 2.0f}, 1);
  tangentPlane.uvs.assign(tangentPlane.positions.size(), glm::vec2(0.5f));
  tangentPlane.tangents.assign(tangentPlane.positions.size(), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
  const std::uint32_t materials[] = {addMaterial(scene, diffuse(glm::vec3(0.5f))), addMaterial(scene, mirror),
                                     addMaterial(scene, glass), addMaterial(scene, blend),
                                     addMaterial(scene, bumped), addMaterial(scene, patterned),
                                     addMaterial(scene, normalMapped)};
  for (std::uint32_t m : materials) addInstance(scene, plane, m, glm::mat4(1.0f));
  addInstance(scene, addMesh(scene, tangentPlane), materials[6], glm::mat4(1.0f));
  const FrameShading frame(scene, std::nullopt, glm::vec3(0.0f));
  // The last but one: a normal map on a mesh without tangents, which resolveHit does not apply.
  const bool withRays[] = {false, true, true, true, true, false, false, true};
  const bool withoutRays[] = {false, false, false, false, true, false, false, true};
  for (std::uint32_t i = 0; i < 8; ++i) {
    EXPECT_EQ(primaryNeedsWholeHit(scene, frame, i, true), withRays[i]) << "instance " << i;
    EXPECT_EQ(primaryNeedsWholeHit(scene, frame, i, false), withoutRays[i]) << "instance " << i;
  }
}

}  // namespace
}  // namespace tandem::rt::test
