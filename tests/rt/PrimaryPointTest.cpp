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

TEST(PrimaryPointTest, IsTheWholeHitsPointToTheBit) {
  struct Case {
    std::string name;
    Scene scene;
  };
  std::vector<Case> cases;
  for (const char* file : {"whitted.json", "cornell-mirror.json"}) {
    auto loaded = loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/" + file);
    ASSERT_TRUE(loaded.ok()) << file;
    cases.push_back({file, std::move(*loaded)});
  }
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
