// Angle extremes: Fresnel and refraction at the critical angle ± 1e-6 rad, IOR 1, 1.0001, 4 and below 1,
// glass 1e-4 thick, nested dielectrics (a furnace test), grazing view and grazing light, a light on the
// surface.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "numerics/NumericsSupport.h"
#include "rt/EmbreeScene.h"
#include "rt/RayMath.h"
#include "rt/Whitted.h"

namespace tandem::numerics {
namespace {

glm::vec3 toEyeAt(double theta) {
  return glm::vec3(static_cast<float>(std::sin(theta)), static_cast<float>(std::cos(theta)), 0.0f);
}

// Ground truth for the float input the routine actually sees, in double.
double sin2TOf(glm::vec3 toEye, double etaI, double etaT) {
  double c = static_cast<double>(toEye.y);
  double s2 = static_cast<double>(toEye.x) * toEye.x;  // sin² from the tangential part: no cancellation
  (void)c;
  return (etaI / etaT) * (etaI / etaT) * s2 / (static_cast<double>(toEye.x) * toEye.x + c * c);
}

double fresnelExactDouble(double cosI, double etaI, double etaT) {
  double sin2T = (etaI / etaT) * (etaI / etaT) * (1.0 - cosI * cosI);
  if (sin2T >= 1.0) return 1.0;
  double cosT = std::sqrt(1.0 - sin2T);
  double rPar = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
  double rPerp = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
  return 0.5 * (rPar * rPar + rPerp * rPerp);
}

TEST(CriticalAngle, TirDecidedCorrectlyOneMicroradianEitherSide) {
  const glm::vec3 n(0, 1, 0);
  for (float ior : {1.0001f, 1.33f, 1.5f, 2.4f, 4.0f}) {
    const double critical = std::asin(1.0 / static_cast<double>(ior));
    for (FresnelMode mode : {FresnelMode::Exact, FresnelMode::Schlick}) {
      for (double delta : {-1e-6, 1e-6}) {
        glm::vec3 v = toEyeAt(critical + delta);
        bool tir = sin2TOf(v, ior, 1.0) >= 1.0;
        EXPECT_EQ(tir, delta > 0.0) << "the float input itself must still be on its side: ior " << ior;
        Refraction r = refractDielectric(v, n, ior, 1.0f, mode);
        EXPECT_EQ(r.totalInternal, tir) << "ior " << ior << " delta " << delta;
        EXPECT_TRUE(std::isfinite(r.fresnel));
        EXPECT_GE(r.fresnel, 0.0f);
        EXPECT_LE(r.fresnel, 1.0f);
        if (r.totalInternal) {
          EXPECT_EQ(r.fresnel, 1.0f);
          continue;
        }
        // Just before the critical angle the transmitted ray runs almost along the surface, unit length,
        // on the far side, and F is continuous with 1 (the exact curve has a sqrt there: 1−F ~ sqrt(δ)).
        EXPECT_TRUE(rt::isFinite(r.dirW));
        EXPECT_NEAR(glm::length(r.dirW), 1.0f, 1e-6f);
        EXPECT_LE(r.dirW.y, 0.0f);
        EXPECT_GT(r.fresnel, 0.9f) << "ior " << ior;
        if (mode == FresnelMode::Exact) {
          EXPECT_NEAR(r.fresnel, fresnelExactDouble(static_cast<double>(v.y), ior, 1.0), 2e-3) << "ior " << ior;
        }
      }
    }
  }
}

TEST(Ior, OneIsIdentityAndNearOneIsSmooth) {
  const glm::vec3 n(0, 1, 0);
  for (double theta : {0.0, 0.5, 1.2, 1.5707}) {
    glm::vec3 v = toEyeAt(theta);
    Refraction one = refractDielectric(v, n, 1.0f, 1.0f, FresnelMode::Exact);
    EXPECT_EQ(one.fresnel, 0.0f);
    EXPECT_EQ(one.dirW, -v);
    for (auto [etaI, etaT] : {std::pair{1.0f, 1.0001f}, std::pair{1.0001f, 1.0f}}) {
      Refraction r = refractDielectric(v, n, etaI, etaT, FresnelMode::Exact);
      if (r.totalInternal) {
        EXPECT_GT(theta, std::asin(1.0 / 1.0001) - 1e-3);  // only in the last 0.8° of grazing
        continue;
      }
      // Snell in double, and F small except at grazing.
      double sinT = etaI / etaT * std::sin(theta);
      EXPECT_NEAR(std::sqrt(double(r.dirW.x) * r.dirW.x + double(r.dirW.z) * r.dirW.z), sinT, 2e-6);
      if (theta < 1.2) {
        EXPECT_LT(r.fresnel, 1e-6f);
      }
    }
  }
}

TEST(Ior, FourAndBelowOneGiveBoundedFresnelAndCorrectTir) {
  const glm::vec3 n(0, 1, 0);
  for (float ior : {4.0f, 0.75f, 0.5f}) {
    for (bool leaving : {false, true}) {
      float etaI = leaving ? ior : 1.0f, etaT = leaving ? 1.0f : ior;
      for (double theta = 0.0; theta < 1.5707; theta += 1e-3) {
        glm::vec3 v = toEyeAt(theta);
        Refraction r = refractDielectric(v, n, etaI, etaT, FresnelMode::Exact);
        bool tir = sin2TOf(v, etaI, etaT) >= 1.0;
        ASSERT_EQ(r.totalInternal, tir) << etaI << " -> " << etaT << " at " << theta;
        ASSERT_TRUE(std::isfinite(r.fresnel) && r.fresnel >= 0.0f && r.fresnel <= 1.0f);
        if (!tir) {
          ASSERT_NEAR(glm::length(r.dirW), 1.0f, 1e-5f);
          ASSERT_NEAR(r.fresnel, fresnelExactDouble(static_cast<double>(v.y), etaI, etaT), 1e-4);
        }
      }
    }
  }
}

// R + T = 1 in the Whitted weights: Whitted::weights gives wR + wT = kr + kt (= 1 here) for both Fresnel
// modes, every incidence, both sides and IORs 0.5 .. 4.
TEST(FresnelWeights, ReflectedPlusTransmittedIsKrPlusKt) {
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  for (float ior : {0.5f, 1.0f, 1.0001f, 1.5f, 4.0f}) {
    Scene scene;
    Material glass = diffuse(glm::vec3(0.0f));
    glass.kr = 0.25f;
    glass.kt = 0.75f;
    glass.ior = ior;
    addInstance(scene, addMesh(scene, makeBox(glm::vec3(1.0f))), addMaterial(scene, glass), glm::mat4(1.0f));
    auto embree = EmbreeScene::build(**device, scene);
    ASSERT_TRUE(embree.ok());
    FrameShading frame(scene, std::nullopt);
    for (FresnelMode mode : {FresnelMode::Exact, FresnelMode::Schlick}) {
      FrameSettings fs;
      fs.fresnel = mode;
      Whitted whitted(scene, **embree, frame, TraceModes::hybrid(fs));
      for (bool back : {false, true})
        for (double theta = 0.0; theta < 1.5708; theta += 0.005) {
          SurfaceHit hit;
          hit.material = 0;
          hit.backFace = back;
          hit.toEyeW = toEyeAt(theta);
          hit.normalW = hit.geomNormalW = glm::vec3(0, 1, 0);
          WhittedWeights wt = whitted.weights(hit);
          ASSERT_TRUE(std::isfinite(wt.reflect) && std::isfinite(wt.transmit.x));
          ASSERT_GE(wt.transmit.x, 0.0f);
          ASSERT_NEAR(wt.reflect + wt.transmit.x, 1.0f, 1e-6f) << ior << " " << theta;
          if (wt.refraction.totalInternal) {
            ASSERT_EQ(wt.transmit.x, 0.0f);
          }
        }
    }
  }
}

// The directions of Whitted::weights against the facet (docs/numerics.md, "Directions over the facet"):
// for shading normals N tilted up to 0.6 rad from the facet normal Ng, views from 1e-4 above the facet to
// straight on, both sides and IORs from 2/3 to 2.4, the reflected direction leaves over the facet and the
// refracted one crosses it. A direction the rule corrects keeps its azimuth about Ng (the tangential part
// of the mirror or Snell direction about N) and is lifted no further than the margin 0.01; one that is
// already on its side by the margin is kept bit for bit, and so is every direction of a flat facet
// (N = Ng), at grazing view and 1e-6 rad either side of the critical angle too.
TEST(FresnelWeights, ReflectedRaysLeaveOverTheFacetAndRefractedRaysCrossIt) {
  auto device = EmbreeDevice::create();
  ASSERT_TRUE(device.ok());
  const glm::vec3 ng(0.0f, 1.0f, 0.0f);
  auto onFacet = [&](float elevation, float azimuth) {  // unit, Ng·result = sin(elevation)
    return glm::vec3(std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth));
  };
  auto tangential = [&](glm::vec3 d) { return d - glm::dot(d, ng) * ng; };
  auto sameAzimuth = [&](glm::vec3 a, glm::vec3 b) {
    glm::vec3 ta = tangential(a), tb = tangential(b);
    float la = glm::length(ta), lb = glm::length(tb);
    if (la < 1e-4f || lb < 1e-4f) return true;  // straight along ±Ng: no azimuth to keep
    return glm::dot(ta / la, tb / lb) > 1.0f - 1e-5f;
  };
  int bentReflections = 0, bentRefractions = 0, checked = 0;
  for (float ior : {1.5f, 2.0f / 3.0f, 1.0001f, 2.4f}) {
    Scene scene;
    Material glass = diffuse(glm::vec3(0.0f));
    glass.kr = 0.25f;
    glass.kt = 0.75f;
    glass.ior = ior;
    addInstance(scene, addMesh(scene, makeBox(glm::vec3(1.0f))), addMaterial(scene, glass), glm::mat4(1.0f));
    auto embree = EmbreeScene::build(**device, scene);
    ASSERT_TRUE(embree.ok());
    FrameShading frame(scene, std::nullopt);
    Whitted whitted(scene, **embree, frame, TraceModes::hybrid(FrameSettings{}));
    // Views from the plane up, and 1e-6 rad either side of the critical angle (on the denser side).
    const double critical = std::asin(1.0 / std::max(double(ior), 1.0 / double(ior)));
    std::vector<float> elevations = {1e-4f, 3e-3f, 0.02f, 0.1f, 0.4f, 0.9f, 1.5707964f};
    for (double delta : {-1e-6, 1e-6}) elevations.push_back(static_cast<float>(std::acos(-1.0) / 2.0 - critical + delta));
    for (bool back : {false, true})
      for (float tilt : {0.0f, 1e-3f, 0.05f, 0.2f, 0.6f})
        for (float tiltAzimuth : {0.0f, 1.3f, 2.9f, 4.4f})
          for (float elevation : elevations)
            for (float viewAzimuth : {0.0f, 0.7f, 2.0f, 3.1f, 4.5f}) {
              SurfaceHit hit;
              hit.material = 0;
              hit.backFace = back;
              hit.geomNormalW = ng;
              hit.normalW = tilt == 0.0f ? ng : onFacet(1.5707964f - tilt, tiltAzimuth);
              hit.toEyeW = onFacet(elevation, viewAzimuth);
              const glm::vec3 n = hit.normalW, v = hit.toEyeW;
              WhittedWeights wt = whitted.weights(hit);
              ++checked;
              const std::string at = "ior " + std::to_string(ior) + (back ? " back" : " front") + " tilt " +
                                     std::to_string(tilt) + "/" + std::to_string(tiltAzimuth) + " view " +
                                     std::to_string(elevation) + "/" + std::to_string(viewAzimuth);
              // Reflection: the mirror direction about N (−V where N faces away: cosθ is clamped to 0).
              const glm::vec3 r = wt.reflectDirW, rawR = glm::dot(n, v) > 0.0f ? glm::reflect(-v, n) : -v;
              ASSERT_TRUE(rt::isFinite(r)) << at;
              ASSERT_NEAR(glm::length(r), 1.0f, 1e-5f) << at;
              ASSERT_GT(glm::dot(r, ng), 0.0f) << "reflected into the facet, " << at;
              if (tilt == 0.0f || glm::dot(rawR, ng) >= 0.01f) {
                ASSERT_EQ(r, glm::reflect(-v, n)) << "a valid mirror direction must be kept, " << at;
              } else {
                ++bentReflections;
                ASSERT_TRUE(sameAzimuth(r, rawR)) << at;
                ASSERT_LE(glm::dot(r, ng), 0.01f + 1e-6f) << "lifted past the margin, " << at;
              }
              // Refraction: Snell about N.
              const float etaI = back ? ior : 1.0f, etaT = back ? 1.0f : ior;
              Refraction raw = refractDielectric(v, n, etaI, etaT, FresnelMode::Exact);
              ASSERT_EQ(wt.refraction.totalInternal, raw.totalInternal) << at;
              if (raw.totalInternal) continue;
              const glm::vec3 t = wt.refraction.dirW;
              ASSERT_TRUE(rt::isFinite(t)) << at;
              ASSERT_NEAR(glm::length(t), 1.0f, 1e-5f) << at;
              ASSERT_LT(glm::dot(t, ng), 0.0f) << "refracted back out of the facet, " << at;
              if (tilt == 0.0f || glm::dot(raw.dirW, ng) <= -0.01f) {
                ASSERT_EQ(t, raw.dirW) << "a valid Snell direction must be kept, " << at;
              } else {
                ++bentRefractions;
                ASSERT_TRUE(sameAzimuth(t, raw.dirW)) << at;
                ASSERT_GE(glm::dot(t, ng), -0.01f - 1e-6f) << "pushed past the margin, " << at;
              }
            }
  }
  std::printf("%d hits: %d reflected and %d refracted directions corrected\n", checked, bentReflections, bentRefractions);
  EXPECT_GT(bentReflections, 100);
  EXPECT_GT(bentRefractions, 20);
}

// A furnace: lossless dielectrics (no local term, kr = 0, kt = 1, Fresnel-weighted) inside a uniform
// environment are invisible; every pixel sums to the background. Nested spheres (glass in water in
// glass) must track inside/outside by the geometric normal at each of up to 6 interfaces. Energy can
// only be lost to the depth and contribution cut-offs.
TEST(Dielectrics, NestedSpheresInAUniformEnvironmentAreInvisible) {
  Scene scene;
  scene.background = glm::vec3(0.5f, 0.5f, 0.5f);
  std::uint32_t sphere = addMesh(scene, makeSphere(1.0f, 96, 48));
  for (auto [r, ior] : {std::pair{1.0f, 1.5f}, std::pair{0.7f, 1.33f}, std::pair{0.4f, 2.4f}}) {
    Material m = diffuse(glm::vec3(0.0f));
    m.ka = m.ks = glm::vec3(0.0f);
    m.kt = 1.0f;
    m.ior = ior;
    addInstance(scene, sphere, addMaterial(scene, m), glm::scale(glm::mat4(1.0f), glm::vec3(r)));
  }
  scene.camera.posW = {0.3f, 0.2f, 3.5f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  scene.camera.yFovDeg = 40.0f;
  const int w = 96, h = 96;
  FrameSettings s = numericsSettings(w, h);
  s.maxDepth = 64;
  s.minContribution = 1e-4f;
  Frame f = renderFrame(scene, s);
  ASSERT_EQ(nonFiniteCount(f), 0u);
  // OPEN FINDING, pinned (docs/numerics.md, "Limits"): a few percent of the pixels lose energy, up to
  // 7.5 %, most near the outer silhouette, where the interpolated normal and the tessellated surface
  // disagree at grazing incidence. Keeping directions on their side of the facet recovered 3 of them
  // (206 → 203); the rest circle just inside the outer surface at the critical angle of the interpolated
  // normals, splitting into branches the contribution and depth limits cut. Not yet fixed: these bounds
  // pin the measured behaviour (203 of 4800 pixels off by > 1 %, worst 0.0375 of 0.5) so that it cannot
  // get worse unnoticed; energy is never created anywhere. These bounds cannot tell a wrong medium from a
  // right one (taking every hit as air → glass loses less here): the medium is held by the closed forms of
  // OraclesTest (total internal reflection from inside, none from outside at the same angle).
  int onSphere = 0, off = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < f.reference.rgb.size(); ++i) {
    if (f.vis.ids[i].x == 0) continue;
    ++onSphere;
    double v = f.reference.rgb[i].x;
    EXPECT_LE(v, 0.5 * (1.0 + 1e-5)) << "energy created at pixel " << i;
    worst = std::max(worst, std::abs(v - 0.5));
    off += std::abs(v - 0.5) > 0.005;
  }
  std::printf("furnace: worst deviation %.5f of 0.5, %d of %d pixels off by > 1%%\n", worst, off, onSphere);
  EXPECT_GT(onSphere, w * h / 4);
  EXPECT_LT(off, onSphere / 20);
  EXPECT_LT(worst, 0.04);
  // Depth 0: no secondary rays, so a purely transmissive sphere is black (no local term).
  s.maxDepth = 0;
  Frame f0 = renderFrame(scene, s);
  EXPECT_EQ(f0.rays.counts.reflection + f0.rays.counts.refraction, 0u);
  for (std::size_t i = 0; i < f0.reference.rgb.size(); ++i)
    if (f0.vis.ids[i].x != 0) {
      ASSERT_EQ(f0.reference.rgb[i], glm::vec3(0.0f));
    }
}

// Glass 1e-4 thick over a checkerboard: seen through, the floor keeps its pattern in place (the exit
// face is found; skipping it would shift the image by the refraction offset) and is dimmed by the two
// interfaces only.
TEST(Dielectrics, GlassOneTenThousandthThickIsFoundAndTransmits) {
  for (float thickness : {1e-4f, 1e-3f}) {
    Scene scene;
    scene.background = glm::vec3(0.0f);
    Material floor = diffuse({0.9f, 0.1f, 0.1f});
    floor.kd2 = {0.1f, 0.9f, 0.1f};
    floor.checkerFrequency = 4.0f;
    floor.ka = glm::vec3(0.0f);
    addInstance(scene, addMesh(scene, makePlane({4.0f, 4.0f}, 1)), addMaterial(scene, floor), glm::mat4(1.0f));
    Light sun = directional({0.1f, -1.0f, 0.2f});
    sun.castShadows = false;  // the comparison is about what is seen through the slab
    scene.lights.push_back(sun);
    scene.camera.posW = {0.0f, 2.0f, 1.2f};
    scene.camera.targetW = {0.0f, 0.0f, 0.0f};
    const int w = 96, h = 96;
    FrameSettings s = numericsSettings(w, h);
    s.maxDepth = 8;
    Frame without = renderFrame(scene, s);
    Material glass = diffuse(glm::vec3(0.0f));
    glass.ka = glass.ks = glm::vec3(0.0f);
    glass.kt = 1.0f;
    glass.ior = 1.5f;
    addInstance(scene, addMesh(scene, makeBox({1.0f, 1.0f, 1.0f})), addMaterial(scene, glass),
                translate({0.0f, 0.5f, 0.0f}) * glm::scale(glm::mat4(1.0f), glm::vec3(2.0f, thickness, 2.0f)));
    Frame with = renderFrame(scene, s);
    ASSERT_EQ(nonFiniteCount(with), 0u);
    int through = 0, wrong = 0;
    for (std::size_t i = 0; i < with.reference.rgb.size(); ++i) {
      if (with.vis.ids[i].x != 2) continue;  // the slab
      ++through;
      glm::vec3 a = with.reference.rgb[i], b = without.reference.rgb[i];
      // Two interfaces at these angles pass 0.88–0.93 of the light (exact Fresnel).
      double ratio = (a.x + a.y + a.z) / std::max(1e-6, double(b.x + b.y + b.z));
      wrong += ratio < 0.85 || ratio > 1.0;
    }
    EXPECT_GT(through, w * h / 3);
    // A checker edge may fall on the other side of a pixel centre after the 1e-4 sideways shift.
    EXPECT_LT(wrong, through / 100) << "thickness " << thickness;
  }
}

Scene planeScene(glm::vec3 lightDirOrPos, bool point) {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  addInstance(scene, addMesh(scene, makePlane({400.0f, 400.0f}, 16)), mat,
              glm::rotate(glm::mat4(1.0f), 0.013f, glm::vec3(1.0f, 0.0f, 0.4f)));
  scene.lights.push_back(point ? pointLight(lightDirOrPos) : directional(lightDirOrPos));
  return scene;
}

// Grazing light down to N·L = 1e-5, grazing view down to 0.05°, and a point light 1e-3 above a plane
// 200 units across: every plane pixel the light reaches is lit (acne fraction 0), and nothing is NaN.
TEST(Grazing, LightAndViewAtGrazingAnglesGiveNoAcne) {
  const int w = 160, h = 90;
  for (double elevation : {1e-5, 1e-4, 1e-3, 1e-2}) {
    for (double viewDeg : {0.05, 1.0, 30.0}) {
      Scene scene = planeScene(glm::vec3(0.0f), false);
      glm::vec3 up = glm::normalize(glm::vec3(scene.instances[0].worldFromObject * glm::vec4(0, 1, 0, 0)));
      glm::vec3 t = glm::normalize(glm::cross(up, glm::vec3(0.2f, 0.0f, 1.0f)));
      scene.lights[0].dirW = glm::normalize(-(static_cast<float>(std::sin(elevation)) * up + static_cast<float>(std::cos(elevation)) * t));
      scene.lights.push_back(pointLight(glm::vec3(scene.instances[0].worldFromObject * glm::vec4(5.0f, 1e-3f, -20.0f, 1.0f))));
      double v = glm::radians(viewDeg);
      glm::vec3 fwd = glm::normalize(glm::vec3(scene.instances[0].worldFromObject * glm::vec4(0.0f, static_cast<float>(-std::sin(v)), static_cast<float>(-std::cos(v)), 0.0f)));
      scene.camera.posW = glm::vec3(scene.instances[0].worldFromObject * glm::vec4(0.0f, 0.5f, 100.0f, 1.0f));
      scene.camera.targetW = scene.camera.posW + fwd;
      scene.camera.upW = up;
      Frame f = renderFrame(scene, numericsSettings(w, h));
      ASSERT_EQ(nonFiniteCount(f), 0u);
      ASSERT_FALSE(f.rays.lightMask.empty());
      int plane = 0, acne = 0;
      for (std::size_t i = 0; i < f.vis.ids.size(); ++i) {
        if (f.vis.ids[i].x == 0) continue;
        ++plane;
        acne += f.rays.lightMask[i] != 3u;
      }
      EXPECT_GT(plane, 50) << "view " << viewDeg;
      EXPECT_EQ(acne, 0) << "light elevation " << elevation << " rad, view " << viewDeg << "°, of " << plane;
    }
  }
}

// Coarse spheres at grazing views (docs/numerics.md, "Directions over the facet"): near a silhouette the
// interpolated normal N turns away from the viewer while the facet still faces it, and the mirror
// direction about N points into the facet. Off the outside of a convex object a reflected ray escapes
// after one bounce, so in a uniform environment the reflected part of every pixel is exactly wR × the
// background: kr for a mirror, F(N·V) for glass (Fresnel-weighted, kr = 0, kt = 1). The spheres emit a
// little, which marks every hit: a reflected ray started into the closed mesh hits the sphere again from
// inside and brings that emission back (and bounces on, until another wrong-side direction lets it out
// or the depth limit ends it). Both the hybrid pass (the wavefront: wR·S at the primary hit) and the
// reference (the recursion: emission + wR·S, glass with refraction off so T is absent) are held, for a
// mirror and for glass.
TEST(Grazing, ReflectionsOffCoarseSpheresLeaveOverTheFacet) {
  const glm::vec3 background(0.5f);
  Material mirror = diffuse(glm::vec3(0.0f));
  mirror.ka = mirror.ks = glm::vec3(0.0f);
  mirror.kr = 0.8f;
  mirror.emission = glm::vec3(0.125f);
  Material glass = mirror;
  glass.kr = 0.0f;
  glass.kt = 1.0f;
  glass.ior = 1.5f;
  const int w = 96, h = 96;
  for (auto [segments, rings] : {std::pair{8, 4}, std::pair{12, 6}, std::pair{24, 12}}) {
    for (glm::vec3 eye : {glm::vec3(0.3f, 0.2f, 3.5f), glm::vec3(0.4f, -1.8f, 1.9f), glm::vec3(2.2f, 0.9f, -1.7f)}) {
      for (bool isGlass : {false, true}) {
        Scene scene;
        scene.background = background;
        addInstance(scene, addMesh(scene, makeSphere(1.0f, segments, rings)), addMaterial(scene, isGlass ? glass : mirror),
                    glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0.2f, 1.0f, 0.1f)));
        scene.camera.posW = eye;
        scene.camera.targetW = glm::vec3(0.0f);
        scene.camera.yFovDeg = 45.0f;
        FrameSettings s = numericsSettings(w, h);
        s.maxDepth = 16;
        s.minContribution = 1e-4f;
        auto rt = makeTracer(scene);
        ASSERT_TRUE(rt);
        Frame f = renderFrame(*rt, scene, s);
        ASSERT_EQ(nonFiniteCount(f), 0u);
        ASSERT_FALSE(f.rays.reflected.empty());
        ImageF reflectionOnly = f.reference;
        if (isGlass) {
          FrameSettings noRefraction = s;
          noRefraction.refraction = EffectMode::Off;
          RayCounts counts;
          rt->renderReference(scene, scene.camera, noRefraction, reflectionOnly, counts);
          EXPECT_EQ(counts.refraction, 0u);
        }
        const std::string what = std::string(isGlass ? "glass" : "mirror") + " sphere " + std::to_string(segments) + "x" +
                                 std::to_string(rings) + " seen from (" + std::to_string(eye.x) + ", " +
                                 std::to_string(eye.y) + ", " + std::to_string(eye.z) + ")";
        // The primary hits as the ray pass makes them: camera-relative (anchored at the scene camera), so
        // N·V and with it F are the ones the pass computed, bit for bit.
        const glm::vec3 anchor = scene.camera.posW;
        const InstanceTransform transform = makeInstanceTransform(scene.instances[0].worldFromObject, anchor);
        const CameraRays cameraRays(toRenderSpace(scene.camera, anchor), {w, h});
        int onSphere = 0, rim = 0, offReference = 0, offHybrid = 0;
        double worst = 0.0;
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const std::size_t i = pixelIndex(x, y, w);
            if (f.vis.ids[i].x == 0) continue;
            ++onSphere;
            SurfaceHit hit = resolveHit(scene, transform, f.vis.ids[i].x - 1, f.vis.ids[i].y,
                                        cameraRays.through(glm::vec2(x, y) + 0.5f));
            // The pixels this is about: the mirror direction about N falls below the facet.
            rim += glm::dot(glm::reflect(-hit.toEyeW, hit.normalW), hit.geomNormalW) < 0.0f;
            // wR of the primary hit (a front face: air into glass).
            const float wR = isGlass ? shading::tdFresnelExact(glm::clamp(glm::dot(hit.normalW, hit.toEyeW), 0.0f, 1.0f), 1.0f, glass.ior)
                                     : mirror.kr;
            const float hybrid = f.rays.reflected[i].x, reference = reflectionOnly.at(x, y).x;
            const float expectedHybrid = wR * background.x, expectedReference = mirror.emission.x + expectedHybrid;
            offHybrid += std::abs(hybrid - expectedHybrid) > 1e-6f;
            offReference += std::abs(reference - expectedReference) > 1e-6f;
            worst = std::max({worst, double(std::abs(hybrid - expectedHybrid)), double(std::abs(reference - expectedReference))});
          }
        std::printf("%s: %d sphere pixels, %d at the rim, worst deviation from one escaping bounce %.6f\n", what.c_str(), onSphere, rim,
                    worst);
        EXPECT_GT(onSphere, w * h / 8) << what;
        EXPECT_GT(rim, 0) << what << ": the view must include pixels whose mirror direction falls below the facet";
        EXPECT_EQ(offHybrid, 0) << what << " (hybrid), of " << onSphere << " pixels, " << rim << " at the rim";
        EXPECT_EQ(offReference, 0) << what << " (reference), of " << onSphere << " pixels, " << rim << " at the rim";
      }
    }
  }
}

// A point light exactly on the surface: N·L = 0 at every point of the plane (no light, no ray, no NaN),
// including the pixel the light sits in (distance 0).
TEST(Grazing, PointLightOnTheSurfaceIsFiniteAndGivesNothing) {
  Scene scene;
  std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  addInstance(scene, addMesh(scene, makePlane({10.0f, 10.0f}, 2)), mat, glm::mat4(1.0f));
  scene.lights.push_back(pointLight({0.0f, 0.0f, 0.0f}, 5.0f));  // on a vertex of the plane, too
  scene.camera.posW = {0.0f, 3.0f, 0.0001f};
  scene.camera.targetW = {0.0f, 0.0f, 0.0f};
  const int w = 65, h = 65;  // the centre pixel looks straight at the light
  Frame f = renderFrame(scene, numericsSettings(w, h));
  ASSERT_EQ(nonFiniteCount(f), 0u);
  for (std::size_t i = 0; i < f.reference.rgb.size(); ++i) {
    ASSERT_NE(f.vis.ids[i].x, 0u);
    // Ambient is 0 and the light is in the plane: at most the one point where it sits lights up.
    EXPECT_LE(f.reference.rgb[i].x, 5.0f * 0.8f + 1e-4f);
  }
  // Away from the light's own pixel N·L is 0 up to the rounding of the (camera-relative) hit position:
  // nothing visible.
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (std::abs(x - w / 2) <= 1 && std::abs(y - h / 2) <= 1) continue;
      ASSERT_LT(f.reference.rgb[pixelIndex(x, y, w)].x, 1e-4f) << x << "," << y;
    }
}

}  // namespace
}  // namespace tandem::numerics
