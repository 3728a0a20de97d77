// Independent oracles (docs/testing.md): each shading and ray formula against a closed form worked out here,
// in the test, from the physics or the model's definition — never from the shared implementation it checks.
// Fresnel (exact and Schlick) at known angles and IORs from both sides, Snell's law and total internal
// reflection on either side of the critical angle, inside and outside told apart by the hit, the Phong model's
// terms at chosen geometry through the CPU twin's own material packing, and shadow rays leaving from the side
// of the surface the viewer sees.
#include <cmath>

#include "numerics/NumericsSupport.h"
#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"
#include "rt/Whitted.h"

namespace tandem::numerics {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Fresnel's equations for unpolarised light from n1 into n2 at incidence θi (radians): the mean of the s and p
// reflectances, 1 beyond the critical angle.
double fresnelOracle(double thetaI, double n1, double n2) {
  const double sinT = n1 / n2 * std::sin(thetaI);
  if (sinT >= 1.0) return 1.0;
  const double ci = std::cos(thetaI), ct = std::sqrt(1.0 - sinT * sinT);
  const double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
  const double rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct);
  return 0.5 * (rs * rs + rp * rp);
}

// Schlick's approximation R0 + (1 − R0)(1 − c)^5, with c the cosine on the less dense side (Schlick 1994).
double schlickOracle(double thetaI, double n1, double n2) {
  const double sinT = n1 / n2 * std::sin(thetaI);
  if (sinT >= 1.0) return 1.0;
  const double c = n1 <= n2 ? std::cos(thetaI) : std::sqrt(1.0 - sinT * sinT);
  const double r0 = (n1 - n2) / (n1 + n2) * ((n1 - n2) / (n1 + n2));
  const double k = 1.0 - c;
  return r0 + (1.0 - r0) * k * k * k * k * k;
}

TEST(Oracles, ExactFresnelMeetsTheTextbookValues) {
  // Normal incidence into glass: ((n − 1)/(n + 1))² = 0.04; Brewster's angle atan(1.5): the p part vanishes,
  // F = Rs/2; 45° into glass: Rs = 0.0920, Rp = 0.00847 (Hecht, Optics, table 4.1's construction).
  EXPECT_NEAR(shading::tdFresnelExact(1.0f, 1.0f, 1.5f), 0.04, 1e-6);
  const double brewster = std::atan(1.5);
  const double rs = std::pow((std::cos(brewster) - 1.5 * std::cos(kPi / 2 - brewster)) /
                                 (std::cos(brewster) + 1.5 * std::cos(kPi / 2 - brewster)),
                             2.0);
  EXPECT_NEAR(shading::tdFresnelExact(static_cast<float>(std::cos(brewster)), 1.0f, 1.5f), 0.5 * rs, 1e-6);
  EXPECT_NEAR(shading::tdFresnelExact(static_cast<float>(std::cos(kPi / 4)), 1.0f, 1.5f), 0.5 * (0.0920 + 0.00847), 2e-4);
  for (double n : {1.33, 1.5, 2.4})
    for (double deg = 0.0; deg < 89.9; deg += 0.5) {
      const double t = deg * kPi / 180.0;
      EXPECT_NEAR(shading::tdFresnelExact(static_cast<float>(std::cos(t)), 1.0f, static_cast<float>(n)),
                  fresnelOracle(t, 1.0, n), 2e-6)
          << "outside, n " << n << " at " << deg << "°";
      EXPECT_NEAR(shading::tdFresnelExact(static_cast<float>(std::cos(t)), static_cast<float>(n), 1.0f),
                  fresnelOracle(t, n, 1.0), 2e-5)
          << "inside, n " << n << " at " << deg << "°";
    }
}

TEST(Oracles, SchlickMeetsItsDefinition) {
  // 60° into glass: R0 = 0.04, (1 − cos 60°)^5 = 1/32: 0.04 + 0.96/32 = 0.07.
  EXPECT_NEAR(shading::tdFresnelSchlick(0.5f, 1.0f, 1.5f), 0.07, 1e-6);
  for (double n : {1.33, 1.5, 2.4})
    for (double deg = 0.0; deg < 89.9; deg += 0.5) {
      const double t = deg * kPi / 180.0;
      EXPECT_NEAR(shading::tdFresnelSchlick(static_cast<float>(std::cos(t)), 1.0f, static_cast<float>(n)),
                  schlickOracle(t, 1.0, n), 2e-6)
          << "outside, n " << n << " at " << deg << "°";
      EXPECT_NEAR(shading::tdFresnelSchlick(static_cast<float>(std::cos(t)), static_cast<float>(n), 1.0f),
                  schlickOracle(t, n, 1.0), 2e-5)
          << "inside, n " << n << " at " << deg << "°";
    }
}

// A glass slab (10 × 1 × 10, kr 0.1, kt 0.9, IOR 1.5) and a Whitted of its frame: weights() at hand-made hits.
struct GlassWeights {
  Scene scene;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<FrameShading> frame;
  std::unique_ptr<Whitted> whitted;
  explicit GlassWeights(FresnelMode mode = FresnelMode::Exact) {
    Material glass = diffuse(glm::vec3(0.0f));
    glass.kr = 0.1f;
    glass.kt = 0.9f;
    glass.ior = 1.5f;
    addInstance(scene, addMesh(scene, makeBox(glm::vec3(10.0f, 1.0f, 10.0f))), addMaterial(scene, glass), glm::mat4(1.0f));
    auto d = EmbreeDevice::create();
    EXPECT_TRUE(d.ok());
    device = std::move(*d);
    auto e = EmbreeScene::build(*device, scene);
    EXPECT_TRUE(e.ok());
    embree = std::move(*e);
    frame = std::make_unique<FrameShading>(scene, std::nullopt);
    FrameSettings fs;
    fs.fresnel = mode;
    whitted = std::make_unique<Whitted>(scene, *embree, *frame, TraceModes::hybrid(fs));
  }
  // A hit on the facet with normal +y seen at `deg` from it, arriving from outside (front) or inside (back).
  WhittedWeights at(double deg, bool inside) const {
    SurfaceHit hit;
    hit.material = 0;
    hit.backFace = inside;
    const double t = deg * kPi / 180.0;
    hit.toEyeW = glm::vec3(static_cast<float>(std::sin(t)), static_cast<float>(std::cos(t)), 0.0f);
    hit.normalW = hit.geomNormalW = glm::vec3(0.0f, 1.0f, 0.0f);
    return whitted->weights(hit);
  }
};

TEST(Oracles, SnellsLawAndTheCriticalAngleFromEitherSide) {
  const GlassWeights g;
  // Outside → glass at 60°: sin θt = sin 60° / 1.5, F from Fresnel's equations, wR = kr + kt·F, wT = kt·(1 − F).
  WhittedWeights w = g.at(60.0, false);
  ASSERT_FALSE(w.refraction.totalInternal);
  const glm::vec3 d = w.refraction.dirW;
  EXPECT_LT(d.y, 0.0f) << "into the glass";
  EXPECT_NEAR(std::hypot(d.x, d.z) / glm::length(d), std::sin(kPi / 3) / 1.5, 1e-6);
  EXPECT_LT(d.x, 0.0f) << "on the far side of the normal from the viewer";
  const double F = fresnelOracle(kPi / 3, 1.0, 1.5);
  EXPECT_NEAR(w.refraction.fresnel, F, 2e-6);
  EXPECT_NEAR(w.reflect, 0.1 + 0.9 * F, 2e-6);
  EXPECT_NEAR(w.transmit.x, 0.9 * (1.0 - F), 2e-6);
  // Glass → air, the critical angle asin(1/1.5) = 41.81°: below it the ray leaves, bent away from the normal.
  const double critical = std::asin(1.0 / 1.5) * 180.0 / kPi;
  w = g.at(critical - 0.1, true);
  ASSERT_FALSE(w.refraction.totalInternal);
  EXPECT_NEAR(std::hypot(w.refraction.dirW.x, w.refraction.dirW.z), 1.5 * std::sin((critical - 0.1) * kPi / 180.0), 1e-5);
  EXPECT_GT(w.transmit.x, 0.0f);
  // ... and above it, and at 60°, it cannot: total internal reflection, F = 1, all of kt reflected.
  for (double deg : {critical + 0.1, 60.0}) {
    w = g.at(deg, true);
    EXPECT_TRUE(w.refraction.totalInternal) << deg;
    EXPECT_EQ(w.refraction.fresnel, 1.0f) << deg;
    EXPECT_EQ(w.transmit.x, 0.0f) << deg;
    EXPECT_NEAR(w.reflect, 1.0f, 1e-6) << deg;
  }
  // The same 60° from outside is no TIR: the medium the ray is in decides, not the angle alone.
  EXPECT_FALSE(g.at(60.0, false).refraction.totalInternal);
  // Schlick mode takes Schlick's F with the cosine on the air side.
  const GlassWeights s(FresnelMode::Schlick);
  EXPECT_NEAR(s.at(30.0, true).refraction.fresnel, schlickOracle(kPi / 6, 1.5, 1.0), 2e-6);
}

TEST(Oracles, ARayLeavingGlassAtSixtyDegreesReflectsTotally) {
  // End to end: a ray inside a glass slab meets its top face at 60° from the normal. The hit the ray pass
  // resolves is a back face (the ray is inside), and its weights reflect everything.
  const GlassWeights g;
  const glm::vec3 origin = -g.embree->anchor();  // the slab's centre, in render space
  const glm::vec3 dir = glm::normalize(glm::vec3(std::sin(kPi / 3), std::cos(kPi / 3), 0.0f));
  std::uint32_t instance = 0, triangle = 0;
  ASSERT_TRUE(g.whitted->intersect(origin, dir, 0.0f, 10.0f, instance, triangle));
  const SurfaceHit hit = resolveHit(g.scene, g.embree->transform(instance), instance, triangle, Ray{origin, dir});
  ASSERT_TRUE(hit.backFace) << "seen from inside";
  ASSERT_NEAR(glm::dot(hit.geomNormalW, -dir), 0.5f, 1e-5f) << "60° from the normal";
  const WhittedWeights w = g.whitted->weights(hit);
  EXPECT_TRUE(w.refraction.totalInternal);
  EXPECT_EQ(w.transmit.x, 0.0f);
  // And entering through the bottom face from below at 60°: no TIR, F as Fresnel's equations give it.
  const glm::vec3 below = glm::vec3(-0.2f, -2.0f, 0.0f) - g.embree->anchor();
  const glm::vec3 up = glm::normalize(glm::vec3(std::sin(kPi / 3), std::cos(kPi / 3), 0.0f));
  ASSERT_TRUE(g.whitted->intersect(below, up, 0.0f, 10.0f, instance, triangle));
  const SurfaceHit in = resolveHit(g.scene, g.embree->transform(instance), instance, triangle, Ray{below, up});
  EXPECT_FALSE(in.backFace);
  const WhittedWeights wi = g.whitted->weights(in);
  EXPECT_FALSE(wi.refraction.totalInternal);
  EXPECT_NEAR(wi.refraction.fresnel, fresnelOracle(kPi / 3, 1.0, 1.5), 1e-5);
}

TEST(Oracles, PhongTermsAtChosenGeometry) {
  // One point on a floor (normal +y) at the origin, a point light 2 units away at 60° from the normal, the eye
  // along the mirror direction turned by α: I = ka·Ia + E·(kd·cos 60° + ks·cos(α)^ns), E = I_light / (1 + d²·q).
  Scene scene;
  Material m;
  m.ka = glm::vec3(0.3f, 0.2f, 0.1f);
  m.kd = glm::vec3(0.5f, 0.6f, 0.7f);
  m.ks = glm::vec3(0.4f);
  m.ns = 40.0f;
  addInstance(scene, addMesh(scene, makePlane({4.0f, 4.0f}, 1)), addMaterial(scene, m), glm::mat4(1.0f));
  scene.lights.push_back(ambientLight(0.5f));
  const double t = kPi / 3, d = 2.0;
  Light l = pointLight(glm::vec3(static_cast<float>(-d * std::sin(t)), static_cast<float>(d * std::cos(t)), 0.0f), 3.0f);
  l.attenuation = {1.0f, 0.0f, 0.25f};
  scene.lights.push_back(l);
  const double E = 3.0 / (1.0 + 0.25 * d * d);
  for (ShadingModel model : {ShadingModel::Phong, ShadingModel::Flat})
    for (double alphaDeg : {0.0, 3.0, 10.0, 25.0}) {
      const double a = alphaDeg * kPi / 180.0;
      // The mirror of the light direction is at +60° on the other side; turn it by α towards the normal.
      const glm::vec3 toEye(static_cast<float>(std::sin(t - a)), static_cast<float>(std::cos(t - a)), 0.0f);
      SurfaceHit hit;
      hit.instance = 0;
      hit.triangle = 0;
      hit.material = 0;
      hit.posW = glm::vec3(0.0f);
      hit.vertexW[0] = hit.vertexW[1] = hit.vertexW[2] = hit.posW;
      hit.normalW = hit.geomNormalW = glm::vec3(0.0f, 1.0f, 0.0f);
      hit.toEyeW = toEye;
      hit.eyeW = toEye * 5.0f;
      const FrameShading frame(scene, model);
      const glm::vec3 got = shadeLocal(scene, frame, makeInstanceTransform(glm::mat4(1.0f)), hit, ~0u);
      for (int c = 0; c < 3; ++c) {
        const double want = m.ka[c] * 0.5 + E * (m.kd[c] * std::cos(t) + m.ks[c] * std::pow(std::cos(a), 40.0));
        EXPECT_NEAR(got[c], want, 2e-5 * want) << toString(model) << " α " << alphaDeg << "° channel " << c;
      }
    }
}

TEST(Oracles, ShadowRaysLeaveFromTheSideTheViewerSees) {
  // A room seen from inside (a box whose inner faces are its back faces) with a light inside: every point the
  // camera sees is lit. A shadow ray offset to the face's outside would start behind the wall and be blocked
  // by the wall itself — on a closed room, everywhere.
  Scene scene;
  addInstance(scene, addMesh(scene, makeBox(glm::vec3(4.0f))), addMaterial(scene, diffuse(glm::vec3(0.7f))),
              glm::mat4(1.0f));
  // A ball on curved ground: its lit side faces the light, its far side does not (no rays there at all).
  addInstance(scene, addMesh(scene, makeSphere(0.5f, 48, 24)), addMaterial(scene, diffuse(glm::vec3(0.7f))),
              translate({0.8f, -1.2f, 0.3f}));
  scene.lights.push_back(pointLight({0.0f, 1.5f, 0.0f}));
  scene.camera.posW = {0.0f, 0.5f, 1.9f};
  scene.camera.targetW = {0.0f, -0.5f, 0.0f};
  scene.camera.yFovDeg = 90.0f;
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  FrameSettings s = settingsFor(96, 64);
  s.reflections = s.refraction = EffectMode::Off;
  VisibilityBuffer ids;
  RayOutputs out;
  castAndTrace(*tracer, scene, s, ids, out);
  ASSERT_EQ(out.lightMask.size(), ids.ids.size());
  int walls = 0, litWalls = 0, ballLit = 0;
  for (std::size_t i = 0; i < ids.ids.size(); ++i) {
    if (ids.ids[i].x == 1) {
      ++walls;
      litWalls += out.lightMask[i] & 1u;
    }
    if (ids.ids[i].x == 2) ballLit += out.lightMask[i] & 1u;
  }
  ASSERT_GT(walls, 3000);
  // The walls the ball hides from the light are in its shadow; every other wall point is lit.
  EXPECT_GT(litWalls, walls * 95 / 100);
  EXPECT_GT(ballLit, 100) << "the ball's side towards the light";
}

TEST(Oracles, ShadowRaysLeaveFromTheSideOfTheFacetTheLightIsOn) {
  // A floor whose shading normals lean 30° towards +x, lit from +x just below the floor's plane: the shading
  // normal faces the light (N·L > 0) while the facet turns away from it (Ng·L < 0). Nothing lies below the floor,
  // so a shadow ray that leaves from the facet's side the light is on (below) reaches it; one offset to the
  // viewer's side would cross its own facet and be blocked.
  Scene scene;
  Mesh floor = makePlane({4.0f, 4.0f}, 2);
  for (glm::vec3& n : floor.normals) n = glm::normalize(glm::vec3(std::sin(kPi / 6), std::cos(kPi / 6), 0.0f));
  addInstance(scene, addMesh(scene, floor), addMaterial(scene, diffuse(glm::vec3(0.7f))), glm::mat4(1.0f));
  const glm::vec3 toLight = glm::normalize(glm::vec3(1.0f, -0.1f, 0.0f));
  scene.lights.push_back(directional(-toLight));
  scene.camera.posW = {0.0f, 3.0f, 1.0f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  FrameSettings s = settingsFor(64, 64);
  s.reflections = s.refraction = EffectMode::Off;
  VisibilityBuffer ids;
  RayOutputs out;
  castAndTrace(*tracer, scene, s, ids, out);
  ASSERT_FALSE(out.lightMask.empty());
  ASSERT_GT(out.counts.shadow, 1000u) << "a ray per floor pixel: the light reaches every shading normal";
  int floorPixels = 0, lit = 0;
  for (std::size_t i = 0; i < ids.ids.size(); ++i)
    if (ids.ids[i].x == 1) {
      ++floorPixels;
      lit += out.lightMask[i] & 1u;
    }
  EXPECT_EQ(lit, floorPixels);
}

TEST(Oracles, TheDisplayCurvesMeetTheirPublishedValues) {
  // The output pass: exposure, a tone map, then the sRGB encoding (docs/shading.md). Values worked out by hand
  // from each curve's definition: Narkowicz's ACES fit x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped;
  // Reinhard x / (1 + x); the sRGB transfer function (IEC 61966-2-1) 12.92x below 0.0031308, else
  // 1.055x^(1/2.4) − 0.055.
  using shading::tdToneMap;
  const int aces = shading::toneMapOp(ToneMap::Aces), reinhard = shading::toneMapOp(ToneMap::Reinhard),
            none = shading::toneMapOp(ToneMap::None);
  struct Point {
    float in, out;
  };
  for (const Point p : {Point{0.0f, 0.0f}, Point{0.18f, 0.086724f / 0.324932f}, Point{0.5f, 0.6425f / 1.0425f},
                        Point{1.0f, 2.54f / 3.16f}, Point{2.0f, 10.1f / 11.04f}, Point{10.0f, 1.0f}})
    EXPECT_NEAR(tdToneMap(glm::vec3(p.in), aces).x, p.out, 2e-6f) << "ACES at " << p.in;
  for (float x : {0.0f, 0.25f, 1.0f, 3.0f, 1000.0f}) EXPECT_NEAR(tdToneMap(glm::vec3(x), reinhard).x, x / (1.0f + x), 1e-6f);
  EXPECT_EQ(tdToneMap(glm::vec3(0.3f, 1.7f, -2.0f), none), glm::vec3(0.3f, 1.0f, 0.0f));
  // sRGB: the linear toe and the power segment meet at 0.0031308 (0.04045 encoded); mid-grey 0.18 is 0.4613561,
  // 0.5 is 0.7353570.
  EXPECT_NEAR(shading::tdSrgbEncode1(0.002f), 0.02584f, 1e-7f);
  EXPECT_NEAR(shading::tdSrgbEncode1(0.0031308f), 0.0404500f, 2e-6f);
  EXPECT_NEAR(shading::tdSrgbEncode1(0.18f), 0.4613561f, 2e-6f);
  EXPECT_NEAR(shading::tdSrgbEncode1(0.5f), 0.7353570f, 2e-6f);
  EXPECT_NEAR(shading::tdSrgbEncode1(1.0f), 1.0f, 2e-6f);
  // The whole output pass at exposure 2: encode(ACES(2 · 0.25)).
  EXPECT_NEAR(shading::tdDisplay(glm::vec3(0.25f), 2.0f, aces, false).x, 1.055f * std::pow(0.6425f / 1.0425f, 1.0f / 2.4f) - 0.055f,
              2e-6f);
}

}  // namespace
}  // namespace tandem::numerics
