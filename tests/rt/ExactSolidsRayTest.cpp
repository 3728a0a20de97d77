// Exact solids in the ray pass (Mesh::exact as Embree user geometry, docs/csg.md): the rays hit the solid,
// not its proxy triangles — on its surface, with its normal, at its silhouette — through instance
// transforms and far from the origin; shadow rays are blocked by it; a ray from inside leaves through it.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "rt/EmbreeScene.h"
#include "rt/RtTestScenes.h"
#include "rt/Whitted.h"
#include "tandem/Primitives.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

// A coarse proxy (8 × 4: far from round) around an exact sphere of radius r at `centre`.
Scene exactSphere(float r, glm::vec3 centre, float scale = 1.0f) {
  Scene s;
  Mesh mesh = makeSphere(r * 1.5f, 8, 4);
  solid::Solid solid;
  solid.nodes.push_back({});
  solid.nodes[0].primitive = {solid::Shape::Sphere, glm::dvec3(r)};
  mesh.exact = solid;
  const std::uint32_t m = addMesh(s, mesh);
  addInstance(s, m, addMaterial(s, diffuse(glm::vec3(0.8f))),
              glm::scale(translate(centre), glm::vec3(scale)));
  s.camera.posW = centre + glm::vec3(0.0f, 0.0f, 10.0f * r * scale);
  s.camera.targetW = centre;
  return s;
}

struct Traced {
  bool hit = false;
  SurfaceHit surface;
};

Traced trace(const Scene& scene, const EmbreeScene& embree, glm::vec3 originW, glm::vec3 dirW) {
  RTCRayHit rh{};
  const glm::vec3 o = originW - embree.anchor();
  EXPECT_TRUE(makeEmbreeRay(rh.ray, o, dirW, 0.0f, std::numeric_limits<float>::infinity(), 0.5f));
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(embree.top(), &ctx, &rh);
  Traced t;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return t;
  t.hit = true;
  const std::uint32_t instance = rh.hit.instID[0];
  t.surface = resolveHit(scene, embree.transform(instance), instance, rh.hit.primID, Ray{o, dirW});
  return t;  // posW in render space (relative to the anchor)
}

TEST(ExactSolidsRay, RaysHitTheSolidNotItsProxyAtAnyScaleAndFarFromTheOrigin) {
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  // Far from the origin only where floats still tell the solid's size apart there (1/128 at 1e5).
  for (auto [size, centre] : {std::pair{1e-3f, glm::vec3(0.0f)}, std::pair{1.0f, glm::vec3(0.0f)},
                              std::pair{1e3f, glm::vec3(0.0f)}, std::pair{1.0f, glm::vec3(1e5f, -1e5f, 1e5f)},
                              std::pair{1e3f, glm::vec3(1e5f, -1e5f, 1e5f)}}) {
    // The radius as placed: 0.5 scaled by the instance transform (2 size), so the transform is exercised.
    const Scene scene = exactSphere(0.5f, centre, 2.0f * size);
    const float r = size;
    auto embree = EmbreeScene::build(**device, scene);
    ASSERT_TRUE(embree.ok()) << embree.error().message;
    // Everything compared in render space (relative to the anchor), in double: the instance's centre there.
    const glm::dvec3 centreR = glm::dvec3(centre) - glm::dvec3((*embree)->anchor());
    for (float offset : {0.0f, 0.3f, 0.7f, 0.99f, 0.999f}) {
      const glm::vec3 from = centre + glm::vec3(offset * r, 0.0f, 5.0f * r);
      const Traced t = trace(scene, **embree, from, {0.0f, 0.0f, -1.0f});
      ASSERT_TRUE(t.hit) << "offset " << offset << " size " << size;
      // On the sphere (the proxy, 1.5 r out and faceted, would be far off), its normal radial.
      const glm::dvec3 local = glm::dvec3(t.surface.posW) - centreR;
      EXPECT_NEAR(glm::length(local) / r, 1.0, 1e-5) << "offset " << offset << " size " << size;
      EXPECT_GT(glm::dot(glm::dvec3(t.surface.normalW), glm::normalize(local)), 0.9999);
      const double rayX = double((from - (*embree)->anchor()).x) - centreR.x;  // where the float ray really runs
      EXPECT_NEAR(local.x / r, rayX / r, 1e-5) << "offset " << offset << " size " << size;
    }
    // Just outside the silhouette: a miss (the proxy reaches 1.5 r).
    EXPECT_FALSE(trace(scene, **embree, centre + glm::vec3(1.01f * r, 0.0f, 5.0f * r), {0.0f, 0.0f, -1.0f}).hit)
        << "size " << size;
  }
}

TEST(ExactSolidsRay, ShadowRaysAreBlockedAndRaysFromInsideLeave) {
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  const Scene scene = exactSphere(1.0f, glm::vec3(0.0f));
  auto embree = EmbreeScene::build(**device, scene);
  ASSERT_TRUE(embree.ok());
  auto occluded = [&](glm::vec3 from, glm::vec3 to) {
    RTCRay ray{};
    const glm::vec3 o = from - (*embree)->anchor();
    EXPECT_TRUE(makeEmbreeRay(ray, o, glm::normalize(to - from), 0.0f, glm::length(to - from), 0.5f));
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1((*embree)->top(), &ctx, &ray);
    return !(ray.tfar >= 0.0f);
  };
  EXPECT_TRUE(occluded({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -5.0f}));
  // Past the sphere but inside its proxy (1.5): not blocked.
  EXPECT_FALSE(occluded({1.2f, 0.0f, 5.0f}, {1.2f, 0.0f, -5.0f}));
  // From the centre outwards: it leaves at r = 1, seen from inside (the back face).
  const Traced inside = trace(scene, **embree, glm::vec3(0.0f), glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f)));
  ASSERT_TRUE(inside.hit);
  const glm::vec3 local = inside.surface.posW + (*embree)->anchor();
  EXPECT_NEAR(glm::length(local), 1.0f, 1e-6f);
  EXPECT_TRUE(inside.surface.backFace);
  EXPECT_LT(glm::dot(inside.surface.geomNormalW, glm::normalize(local)), -0.9999f);
}

}  // namespace
}  // namespace tandem::rt
