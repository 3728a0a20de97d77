// Model tests after pbrt-v4's shapes_test.cpp, through the engine's own path (EmbreeScene, resolveHit,
// spawnOrigin): random triangles with vertex coordinates log-uniform over 1e-8..1e8, many rays spawned
// from every hit, zero re-intersections; rays from inside a closed jittered sphere always hit.
#include <cmath>
#include <limits>
#include <random>

#include "numerics/NumericsSupport.h"
#include "rt/EmbreeScene.h"
#include "rt/SurfaceShading.h"

namespace tandem::numerics {
namespace {

struct Embree {
  std::unique_ptr<EmbreeDevice> device;
  Embree() {
    auto d = EmbreeDevice::create();
    EXPECT_TRUE(d.ok());
    if (d) device = std::move(*d);
  }
};

bool hits(const EmbreeScene& scene, glm::vec3 o, glm::vec3 d, std::uint32_t* primOut = nullptr) {
  RTCRayHit rh{};
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(scene.top(), &ctx, &rh);
  if (primOut) *primOut = rh.hit.primID;
  return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

Scene oneTriangle(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::mat4 worldFromObject = glm::mat4(1.0f)) {
  Scene s;
  Mesh m;
  m.positions = {p0, p1, p2};
  m.indices = {0, 1, 2};
  addInstance(s, addMesh(s, m), addMaterial(s, diffuse(glm::vec3(0.5f))), worldFromObject);
  s.camera.posW = glm::vec3(0.0f);  // render space = world space here: the test is about raw magnitudes
  return s;
}

glm::vec3 uniformDirection(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (;;) {
    glm::vec3 v(n(rng), n(rng), n(rng));
    float l = glm::length(v);
    if (l > 1e-3f) return v / l;
  }
}

// Triangles that pbrt-v4 generates: every coordinate log-uniform over 16 decades with a random sign, so
// most are huge needles spanning many scales; from random points on each, rays in every direction of
// both hemispheres leave from the engine's offset origin and must not find the triangle again.
TEST(ModelTriangles, SpawnedRaysNeverReintersectLogUniformTriangles) {
  Embree e;
  ASSERT_TRUE(e.device);
  std::mt19937 rng(20240607);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  auto coord = [&] {
    float mag = std::pow(10.0f, -8.0f + 16.0f * u01(rng));
    return u01(rng) < 0.5f ? -mag : mag;
  };
  int triangles = 0, rays = 0, reHits = 0, degenerate = 0;
  for (int t = 0; t < 300; ++t) {
    glm::vec3 p0(coord(), coord(), coord()), p1(coord(), coord(), coord()), p2(coord(), coord(), coord());
    // Half of them instanced with a scale and a translation, as scenes place meshes.
    glm::mat4 m(1.0f);
    if (t % 2) m = translate(glm::vec3(coord(), coord(), coord()) * 1e-2f) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f + u01(rng)));
    Scene s = oneTriangle(p0, p1, p2, m);
    auto built = EmbreeScene::build(*e.device, s);
    ASSERT_TRUE(built.ok());
    const EmbreeScene& scene = **built;
    ++triangles;
    for (int h = 0; h < 20; ++h) {
      // A ray at a random point of the triangle (pbrt: origin off the surface, aimed at the point).
      float a = u01(rng), b = u01(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      glm::vec3 w[3];
      for (int i = 0; i < 3; ++i) w[i] = glm::vec3(m * glm::vec4(s.meshes[0].positions[static_cast<std::size_t>(i)], 1.0f));
      glm::vec3 target = (1.0f - a - b) * w[0] + a * w[1] + b * w[2];
      glm::vec3 dir = uniformDirection(rng);
      float dist = std::max(1.0f, glm::length(target)) * (0.5f + u01(rng));
      Ray ray{target - dir * dist, dir};
      if (!rt::isFinite(ray.origin)) continue;
      SurfaceHit hit = resolveHit(s, scene.transform(0), 0, 0, ray);
      ASSERT_TRUE(rt::isFinite(hit.posW) && rt::isFinite(hit.geomNormalW));
      glm::dvec3 ngD = glm::cross(glm::dvec3(w[1]) - glm::dvec3(w[0]), glm::dvec3(w[2]) - glm::dvec3(w[0]));
      if (!(glm::length(ngD) > 0.0)) {
        ++degenerate;  // zero area in float: Embree never reports it, nothing to re-hit
        continue;
      }
      for (int k = 0; k < 50; ++k) {
        glm::vec3 d = uniformDirection(rng);
        glm::vec3 side = glm::dot(d, hit.geomNormalW) >= 0.0f ? hit.geomNormalW : -hit.geomNormalW;
        glm::vec3 o = spawnOrigin(hit, side);
        ASSERT_TRUE(rt::isFinite(o));
        ++rays;
        reHits += hits(scene, o, d);
      }
    }
  }
  std::printf("%d triangles, %d rays, %d re-hits, %d degenerate hit points\n", triangles, rays, reHits, degenerate);
  EXPECT_GT(rays, 200000);
  EXPECT_EQ(reHits, 0);
}

// The same at the scales of the extremes: compact triangles of size 1e-4..1e4 centred anywhere in
// ±1e6, the case a fixed epsilon or a fixed near-origin offset gets wrong at one end.
TEST(ModelTriangles, SpawnedRaysNeverReintersectCompactTrianglesAtEveryScale) {
  Embree e;
  ASSERT_TRUE(e.device);
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int rays = 0, reHits = 0;
  for (int t = 0; t < 200; ++t) {
    float size = std::pow(10.0f, -4.0f + 8.0f * u01(rng));
    float far = std::pow(10.0f, -6.0f + 12.0f * u01(rng));
    glm::vec3 c = far * (glm::vec3(u01(rng), u01(rng), u01(rng)) - 0.5f);
    glm::vec3 p[3];
    for (auto& v : p) v = c + size * (glm::vec3(u01(rng), u01(rng), u01(rng)) - 0.5f);
    Scene s = oneTriangle(p[0], p[1], p[2]);
    auto built = EmbreeScene::build(*e.device, s);
    ASSERT_TRUE(built.ok());
    for (int h = 0; h < 20; ++h) {
      float a = u01(rng), b = u01(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      glm::vec3 target = (1.0f - a - b) * p[0] + a * p[1] + b * p[2];
      glm::vec3 dir = uniformDirection(rng);
      Ray ray{target - dir * (size + glm::length(target) * 1e-3f), dir};
      SurfaceHit hit = resolveHit(s, (*built)->transform(0), 0, 0, ray);
      glm::dvec3 ngD = glm::cross(glm::dvec3(p[1]) - glm::dvec3(p[0]), glm::dvec3(p[2]) - glm::dvec3(p[0]));
      if (!(glm::length(ngD) > 0.0)) continue;
      for (int k = 0; k < 50; ++k) {
        glm::vec3 d = uniformDirection(rng);
        glm::vec3 side = glm::dot(d, hit.geomNormalW) >= 0.0f ? hit.geomNormalW : -hit.geomNormalW;
        ++rays;
        reHits += hits(**built, spawnOrigin(hit, side), d);
      }
    }
  }
  EXPECT_GT(rays, 150000);
  EXPECT_EQ(reHits, 0);
}

// A closed sphere whose vertices are jittered radially (by a hash of their position, so the seam's
// duplicated vertices move together and the mesh stays closed): every ray from inside hits it.
TEST(ModelTriangles, RaysFromInsideAClosedJitteredSphereAlwaysHit) {
  Embree e;
  ASSERT_TRUE(e.device);
  for (float radius : {1e-4f, 1.0f, 1e4f}) {
    Scene s;
    Mesh m = makeSphere(1.0f, 40, 20);
    for (glm::vec3& p : m.positions) {
      auto hx = static_cast<std::uint32_t>(std::lround(p.x * 1e5f)), hy = static_cast<std::uint32_t>(std::lround(p.y * 1e5f)),
           hz = static_cast<std::uint32_t>(std::lround(p.z * 1e5f));
      float j = 0.8f + 0.4f * random01(hx, hy, hz, 0);
      p *= j;
    }
    m.normals.clear();
    addInstance(s, addMesh(s, m), addMaterial(s, diffuse(glm::vec3(0.5f))),
                translate(glm::vec3(0.3f, -0.2f, 0.1f) * radius) * glm::scale(glm::mat4(1.0f), glm::vec3(radius)));
    s.camera.posW = glm::vec3(0.0f);
    auto built = EmbreeScene::build(*e.device, s);
    ASSERT_TRUE(built.ok());
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    int misses = 0, rays = 0;
    for (int i = 0; i < 20000; ++i) {
      // Inside the smallest jittered radius (0.8) around the sphere's centre.
      glm::vec3 o = (glm::vec3(0.3f, -0.2f, 0.1f) + glm::vec3(u(rng), u(rng), u(rng)) * 0.9f) * radius;
      ++rays;
      misses += !hits(**built, o, uniformDirection(rng));
    }
    EXPECT_EQ(misses, 0) << "radius " << radius << ", of " << rays;
    // And from points on the inside of the surface (random points of each face, hit by a ray from the
    // centre), leaving into the solid with the engine's offset: the origin is strictly inside a closed
    // surface, so the ray must hit it again; an escape means the offset pushed it through its own face.
    int escaped = 0, spawned = 0;
    const InstanceTransform& tf = (*built)->transform(0);
    glm::vec3 c = glm::vec3(tf.worldFromObject * glm::vec4(0, 0, 0, 1));
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    for (std::uint32_t tri = 0; tri < m.triangleCount(); ++tri) {
      glm::vec3 w[3];
      for (int k = 0; k < 3; ++k) w[k] = glm::vec3(tf.worldFromObject * glm::vec4(m.positions[m.indices[3 * tri + static_cast<std::uint32_t>(k)]], 1.0f));
      if (!(glm::length(glm::cross(glm::dvec3(w[1]) - glm::dvec3(w[0]), glm::dvec3(w[2]) - glm::dvec3(w[0]))) > 0.0)) continue;
      for (int k = 0; k < 4; ++k) {
        float a = 0.05f + 0.9f * u01(rng), b = 0.05f + 0.9f * u01(rng);
        if (a + b > 0.95f) a = 0.95f - a * 0.5f, b = (0.95f - a) * 0.5f;
        glm::vec3 target = (1.0f - a - b) * w[0] + a * w[1] + b * w[2];
        SurfaceHit hit = resolveHit(s, tf, 0, tri, Ray{c, glm::normalize(target - c)});
        glm::vec3 d = uniformDirection(rng);
        if (glm::dot(d, hit.geomNormalW) < 0.0f) d = -d;  // Ng faces the centre: leave into the solid
        ++spawned;
        escaped += !hits(**built, spawnOrigin(hit, hit.geomNormalW), d);
      }
    }
    EXPECT_GT(spawned, 5000);
    EXPECT_EQ(escaped, 0) << "radius " << radius;
  }
}

}  // namespace
}  // namespace tandem::numerics
