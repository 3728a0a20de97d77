// Single-sided materials (Material::doubleSided false, glTF's default; docs/gltf.md): a ray passes an opaque
// single-sided face it meets from behind and stops at its front; a shadow ray is the light's, so a face stops
// it when the face's front is towards the light (a shadow map drawn with back faces culled); a transmissive
// face and a double-sided one are met from both sides. A quad at height 1 between a floor and a ceiling,
// asked from above and below, in Embree's single-ray and packet queries, and under a mirroring transform as
// the glTF importer makes it (the mesh's winding reversed, so its front is still counter-clockwise in world
// space: NegativeScaleTest's case).
#include <gtest/gtest.h>

#include "rt/EmbreeScene.h"
#include "rt/RtTestScenes.h"
#include "rt/Wavefront.h"
#include "rt/Whitted.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

enum class Quad { SingleSided, Transmissive, DoubleSided, SingleSidedMirrored, None };

struct QuadBetweenFloorAndCeiling {
  Scene scene;
  std::uint32_t floor = 0, ceiling = 0, quad = 0;
  explicit QuadBetweenFloorAndCeiling(Quad kind) {
    const std::uint32_t plain = addMaterial(scene, diffuse(glm::vec3(0.7f)));  // double-sided: the default
    Material m = diffuse(glm::vec3(0.8f));
    m.doubleSided = kind == Quad::DoubleSided;
    if (kind == Quad::Transmissive) m.kt = 0.5f, m.ior = 1.5f;
    const std::uint32_t quadMaterial = addMaterial(scene, m);
    const std::uint32_t plane = addMesh(scene, makePlane({20.0f, 20.0f}, 1));
    floor = addInstance(scene, plane, plain, glm::mat4(1.0f));
    ceiling = addInstance(scene, plane, plain, translate({0.0f, 3.0f, 0.0f}));
    Mesh q = makePlane({2.0f, 2.0f}, 1);  // +Y is its counter-clockwise front
    glm::mat4 at = translate({0.0f, 1.0f, 0.0f});
    if (kind == Quad::SingleSidedMirrored) {
      // What the importer does for a node of negative determinant: the winding reversed in a copy.
      for (std::size_t t = 0; t + 2 < q.indices.size(); t += 3) std::swap(q.indices[t + 1], q.indices[t + 2]);
      at = at * glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
    }
    if (kind != Quad::None) quad = addInstance(scene, addMesh(scene, q), quadMaterial, at);
    scene.camera.posW = {0.0f, 2.0f, 6.0f};
    scene.camera.targetW = {0.0f, 1.0f, 0.0f};
  }
};

struct Traced {
  std::uint32_t upFromTheFloor = ~0u, downFromAbove = ~0u;  // the instance each ray meets first
  LightMask floorLitFromAbove = 0, ceilingLitFromBelow = 0;  // one ray each, as Whitted traces them
  LightMask floorLitFromAbovePacket = 0;                      // the same shadow ray in an rtcOccluded8 packet
};

Traced trace(Quad kind) {
  QuadBetweenFloorAndCeiling q(kind);
  Traced out;
  auto device = EmbreeDevice::create();
  EXPECT_TRUE(device.ok());
  if (!device.ok()) return out;
  auto embree = EmbreeScene::build(**device, q.scene);
  EXPECT_TRUE(embree.ok());
  if (!embree.ok()) return out;
  const EmbreeScene& e = **embree;
  const glm::vec3 anchor = e.anchor();
  const glm::vec3 under(-0.3f, 0.0f, -0.2f);  // under the quad (and on the planes' triangle 0: x + z < 0)
  auto first = [&](glm::vec3 fromW, glm::vec3 dir) {
    std::uint32_t instance = ~0u, triangle = 0;
    FrameSettings s = settingsFor(8, 8);
    FrameShading frame(q.scene, s.shadingOverride, anchor);
    Whitted whitted(q.scene, e, frame, TraceModes::reference(s));
    whitted.intersect(toRenderSpace(fromW, anchor), dir, 0.0f, 100.0f, instance, triangle);
    return instance;
  };
  out.upFromTheFloor = first(under + glm::vec3(0.0f, 0.5f, 0.0f), {0.0f, 1.0f, 0.0f});
  out.downFromAbove = first(under + glm::vec3(0.0f, 2.5f, 0.0f), {0.0f, -1.0f, 0.0f});

  // A point light between the quad and the other plane (a directional one would be behind that plane).
  auto lit = [&](std::uint32_t surface, float y, float lightY, bool packet) -> LightMask {
    Scene lightScene = q.scene;
    lightScene.lights.push_back(pointLight(glm::vec3(under.x + 0.1f, lightY, under.z)));
    FrameSettings s = settingsFor(8, 8);
    FrameShading frame(lightScene, s.shadingOverride, anchor);
    Whitted whitted(lightScene, e, frame, TraceModes::reference(s));
    // A ray down onto the surface's point (the ceiling is seen from below: a ray up).
    const float from = y > 1.5f ? y - 1.0f : y + 0.5f;
    Ray ray{toRenderSpace(glm::vec3(under.x, from, under.z), anchor), glm::vec3(0.0f, y > from ? 1.0f : -1.0f, 0.0f)};
    const SurfaceHit hit = resolveHit(lightScene, e.transform(surface), surface, 0, ray);
    RayCounts counts;
    if (!packet) return static_cast<LightMask>(whitted.lightMask(hit, counts));
    ShadowBatch batch;
    LightMask mask = 0;
    mask = static_cast<LightMask>(mask | batch.add(whitted, 1, hit, 0));
    batch.trace(e.top(), &mask, counts);
    return mask;
  };
  // A light above the quad: the quad's front faces it, and shades the floor.
  out.floorLitFromAbove = lit(q.floor, 0.0f, 2.0f, false);
  out.floorLitFromAbovePacket = lit(q.floor, 0.0f, 2.0f, true);
  // A light below it: the quad's back faces it, and lets its light up to the ceiling.
  out.ceilingLitFromBelow = lit(q.ceiling, 3.0f, 0.5f, false);
  return out;
}

TEST(SingleSided, AnOpaqueFaceStopsRaysAtItsFrontAndLightOnItsFrontSide) {
  for (Quad kind : {Quad::SingleSided, Quad::SingleSidedMirrored}) {
    SCOPED_TRACE(kind == Quad::SingleSided ? "single-sided" : "single-sided, mirrored");
    QuadBetweenFloorAndCeiling q(kind);
    const Traced t = trace(kind);
    EXPECT_EQ(t.downFromAbove, q.quad);
    EXPECT_EQ(t.upFromTheFloor, q.ceiling);
    EXPECT_EQ(t.floorLitFromAbove, 0u) << "the quad facing the light cast no shadow";
    EXPECT_EQ(t.floorLitFromAbovePacket, 0u) << "in a packet";
    EXPECT_EQ(t.ceilingLitFromBelow, 1u) << "the quad turned away from the light cast a shadow";
  }
}

// The lights reach both planes when no quad is there: what the masks above are told apart from.
TEST(SingleSided, WithoutTheQuadBothLightsReachTheirPlanes) {
  const Traced t = trace(Quad::None);
  EXPECT_EQ(t.floorLitFromAbove, 1u);
  EXPECT_EQ(t.floorLitFromAbovePacket, 1u);
  EXPECT_EQ(t.ceilingLitFromBelow, 1u);
}

TEST(SingleSided, TransmissiveAndDoubleSidedFacesAreMetFromBothSides) {
  for (Quad kind : {Quad::Transmissive, Quad::DoubleSided}) {
    SCOPED_TRACE(kind == Quad::Transmissive ? "single-sided transmissive" : "double-sided");
    QuadBetweenFloorAndCeiling q(kind);
    const Traced t = trace(kind);
    EXPECT_EQ(t.downFromAbove, q.quad);
    EXPECT_EQ(t.upFromTheFloor, q.quad);
    if (kind == Quad::DoubleSided) {  // (a transmissive face's shadow is its transmittance, not a mask bit)
      EXPECT_EQ(t.floorLitFromAbove, 0u);
      EXPECT_EQ(t.floorLitFromAbovePacket, 0u);
      EXPECT_EQ(t.ceilingLitFromBelow, 0u);
    }
  }
}

// (The hybrid shadows' maps never prove a single-sided face's shadow: HybridShadows.SingleSidedFaces...)
TEST(SingleSided, OnlyMeshesOfSingleSidedOpaqueInstancesLetRaysThrough) {
  for (Quad kind : {Quad::SingleSided, Quad::Transmissive, Quad::DoubleSided}) {
    QuadBetweenFloorAndCeiling q(kind);
    auto device = EmbreeDevice::create();
    ASSERT_TRUE(device.ok());
    auto embree = EmbreeScene::build(**device, q.scene);
    ASSERT_TRUE(embree.ok());
    EXPECT_EQ((*embree)->letsRaysThrough(q.quad), kind == Quad::SingleSided);
    EXPECT_FALSE((*embree)->letsRaysThrough(q.floor));
  }
}

}  // namespace
}  // namespace tandem::rt
