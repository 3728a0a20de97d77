// The single-pixel trace (rt/PixelTrace.h): its tree must be the pass's own computation for that pixel —
// the ray pass's outputs exactly, the CPU composite's colour, the reference frame's pixel — and its
// structure what the Whitted scene puts there (a glass sphere's reflection and refraction).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include <algorithm>

#include "rt/CpuComposite.h"
#include "rt/PixelTrace.h"
#include "rt/RtTestScenes.h"
#include "support/TestSupport.h"
#include "tandem/SceneFile.h"

namespace tandem::rt {
namespace {

using namespace tandem::rt::test;

std::size_t at(int x, int y, int w) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); }

std::uint32_t instanceNamed(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].name == name) return static_cast<std::uint32_t>(i);
  ADD_FAILURE() << "no instance " << name;
  return 0;
}

/// Unpolarised Fresnel reflectance of a dielectric, in double, written out here rather than taken from
/// the shading code it checks.
double fresnelDielectric(double cosI, double etaI, double etaT) {
  double sin2T = (etaI / etaT) * (etaI / etaT) * (1.0 - cosI * cosI);
  if (sin2T >= 1.0) return 1.0;
  double cosT = std::sqrt(1.0 - sin2T);
  double rs = (etaI * cosI - etaT * cosT) / (etaI * cosI + etaT * cosT);
  double rp = (etaT * cosI - etaI * cosT) / (etaT * cosI + etaI * cosT);
  return 0.5 * (rs * rs + rp * rp);
}

/// What the tree promises at every node, whatever the scene: each sum is local + wR·S + wT·T of its own
/// children's contributions, each contribution weight ⊙ radiance, and the counts are the nodes'.
void expectConsistentTree(const PixelTrace& t) {
  RayCounts counted;
  counted.primary = t.rays.primary;  // a hybrid primary hit is resolved, not traced: not a node property
  for (std::size_t i = 0; i < t.nodes.size(); ++i) {
    const TraceNode& n = t.nodes[i];
    SCOPED_TRACE("node " + std::to_string(i));
    if (n.kind == TraceRayKind::Reflection) ++counted.reflection;
    if (n.kind == TraceRayKind::Refraction) ++counted.refraction;
    for (const TraceLight& l : n.lights)
      counted.shadow += l.visibility == LightVisibility::Unoccluded || l.visibility == LightVisibility::Occluded;
    if (n.parent >= 0) {
      const TraceNode& p = t.nodes[static_cast<std::size_t>(n.parent)];
      EXPECT_EQ(n.depth, p.depth + 1);
      const std::vector<int>& siblings = n.kind == TraceRayKind::Reflection ? p.reflectionChildren : p.refractionChildren;
      EXPECT_NE(std::find(siblings.begin(), siblings.end(), static_cast<int>(i)), siblings.end());
      EXPECT_EQ(n.contribution, n.weight * n.radiance);
    }
    // Each kind's sum is its rays' contributions added from zero in order, as the recursion adds them.
    for (const std::vector<int>* kind : {&n.reflectionChildren, &n.refractionChildren}) {
      glm::vec3 sum(0.0f);
      for (int c : *kind) sum += t.nodes[static_cast<std::size_t>(c)].contribution;
      EXPECT_EQ(kind == &n.reflectionChildren ? n.reflected : n.transmitted, sum);
      EXPECT_EQ(kind->empty() ? -1 : kind->front(), kind == &n.reflectionChildren ? n.reflectionChild : n.refractionChild);
    }
    if (!n.hit) continue;
    EXPECT_EQ(n.radiance, n.local + n.reflected + n.transmitted);
    EXPECT_EQ(n.reflectionChild >= 0, n.reflection == SecondaryRay::Traced);
    EXPECT_EQ(n.refractionChild >= 0, n.refraction == SecondaryRay::Traced);
    if (n.reflectionChild < 0) {
      EXPECT_EQ(n.reflected, glm::vec3(0.0f));
    }
    if (n.refractionChild < 0) {
      EXPECT_EQ(n.transmitted, glm::vec3(0.0f));
    }
    std::uint32_t mask = 0;
    for (const TraceLight& l : n.lights) mask |= l.visible ? 1u << l.light : 0u;
    EXPECT_EQ(mask, n.lightMask & ((1u << n.lights.size()) - 1u));
  }
  EXPECT_EQ(counted.shadow, t.rays.shadow);
  EXPECT_EQ(counted.reflection, t.rays.reflection);
  EXPECT_EQ(counted.refraction, t.rays.refraction);
}

struct WhittedFrame {
  Scene scene;
  FrameSettings settings;
  std::unique_ptr<RayTracer> tracer;
  VisibilityBuffer visibility;
  RayOutputs out;
  explicit WhittedFrame(int w, int h, int scale = 1, const std::string& sceneFile = "") {
    auto loaded = sceneFile.empty() ? loadDefaultScene() : loadSceneFile(tandem::test::sourceDir() + "/assets/scenes/" + sceneFile);
    EXPECT_TRUE(loaded.ok());
    if (loaded) scene = std::move(*loaded);
    settings = *presetSettings("hybrid-full", settingsFor(w, h));
    settings.rayScale = scale;
    tracer = makeTracer(scene);
    if (tracer) castAndTrace(*tracer, scene, settings, visibility, out);
  }
};

// The glass sphere of assets/scenes/whitted.json near its centre at 320x180: the pixel the CLI test traces too.
constexpr int kGlassX = 132, kGlassY = 87;

TEST(PixelTrace, GlassSpherePixelOfTheWhittedScene) {
  WhittedFrame f(320, 180);
  ASSERT_TRUE(f.tracer);
  const std::uint32_t glass = instanceNamed(f.scene, "glass-sphere");
  ASSERT_EQ(f.visibility.ids[at(kGlassX, kGlassY, 320)].x, glass + 1) << "the test pixel is not on the glass sphere";
  PixelTrace t = f.tracer->tracePixel(f.scene, f.scene.camera, f.settings, f.visibility, kGlassX, kGlassY);

  ASSERT_EQ(t.roots.size(), 1u);
  const TraceNode& primary = t.nodes[static_cast<std::size_t>(t.roots[0])];
  EXPECT_EQ(primary.kind, TraceRayKind::Primary);
  ASSERT_TRUE(primary.hit);
  EXPECT_EQ(primary.instance, glass);
  EXPECT_FALSE(primary.backFace);
  EXPECT_EQ(t.tracedX, kGlassX);
  EXPECT_EQ(t.tracedY, kGlassY);
  // The primary ray starts at the camera and reaches the sphere's surface.
  EXPECT_LT(glm::length(primary.originW - f.scene.camera.posW), 1e-5f);
  const glm::vec3 centre(-0.6f, 1.2f, 1.2f);
  EXPECT_NEAR(glm::length(primary.positionW - centre), 0.75f, 2e-3f);
  EXPECT_NEAR(glm::length(primary.positionW - primary.originW), primary.t, 1e-4f);

  // One shadow ray per direct light that can light the point (key and spot), each answered.
  const std::size_t lights = f.scene.directLights().size();
  ASSERT_EQ(lights, 2u);
  ASSERT_EQ(primary.lights.size(), lights);
  for (const TraceLight& l : primary.lights) {
    EXPECT_NE(l.visibility, LightVisibility::NotTraced) << "light " << l.light;
    if (l.visibility == LightVisibility::Unoccluded || l.visibility == LightVisibility::Occluded) {
      EXPECT_GT(l.tFar, 0.0f);
      EXPECT_NEAR(glm::length(l.dirW), 1.0f, 1e-5f);
    }
  }
  EXPECT_EQ(primary.lights[0].visibility, LightVisibility::Unoccluded) << "the key light sees the top of the glass";

  // The Whitted sum: F of air to glass at the hit's angle, wR = kr + kt·F, wT = kt·(1 − F).
  const Material& m = f.scene.materials[f.scene.instances[glass].material];
  ASSERT_TRUE(primary.sumEvaluated);
  EXPECT_FALSE(primary.totalInternal);
  const double cosI = glm::dot(glm::dvec3(primary.shadingNormalW), -glm::dvec3(primary.dirW));
  EXPECT_NEAR(primary.fresnel, fresnelDielectric(cosI, 1.0, m.ior), 1e-5);
  EXPECT_GT(primary.fresnel, 0.03f);
  EXPECT_LT(primary.fresnel, 0.2f);
  EXPECT_FLOAT_EQ(primary.reflectWeight, m.kr + m.kt * primary.fresnel);
  EXPECT_FLOAT_EQ(primary.transmitWeight.x, m.kt * (1.0f - primary.fresnel));

  // A reflection and a refraction child; the refracted ray meets the sphere again from inside.
  ASSERT_GE(primary.reflectionChild, 0);
  ASSERT_GE(primary.refractionChild, 0);
  const TraceNode& r = t.nodes[static_cast<std::size_t>(primary.reflectionChild)];
  const TraceNode& tr = t.nodes[static_cast<std::size_t>(primary.refractionChild)];
  EXPECT_EQ(r.kind, TraceRayKind::Reflection);
  EXPECT_EQ(tr.kind, TraceRayKind::Refraction);
  EXPECT_EQ(r.depth, 1);
  EXPECT_FLOAT_EQ(r.weight.x, primary.reflectWeight);
  EXPECT_EQ(tr.weight, primary.transmitWeight);
  EXPECT_GT(glm::dot(r.dirW, primary.geometricNormalW), 0.0f);
  EXPECT_LT(glm::dot(tr.dirW, primary.geometricNormalW), 0.0f);
  ASSERT_TRUE(tr.hit);
  EXPECT_EQ(tr.instance, glass);
  EXPECT_TRUE(tr.backFace);
  EXPECT_GT(tr.t, 0.1f);
  EXPECT_LT(tr.t, 1.5f + 1e-3f);  // a chord of the 0.75 sphere
  expectConsistentTree(t);

  // The pass's outputs for the pixel, exactly, and the CPU composite's colour.
  const std::size_t g = at(kGlassX, kGlassY, 320);
  ASSERT_FALSE(f.out.reflected.empty());
  ASSERT_FALSE(f.out.transmitted.empty());
  ASSERT_FALSE(f.out.lightMask.empty());
  EXPECT_EQ(glm::vec4(t.reflected, 1.0f), f.out.reflected[g]);
  EXPECT_EQ(glm::vec4(t.transmitted, 1.0f), f.out.transmitted[g]);
  EXPECT_EQ(t.lightMask, f.out.lightMask[g]);
  EXPECT_GT(glm::length(t.reflected), 0.0f);
  EXPECT_GT(glm::length(t.transmitted), 0.0f);
  ImageF composite;
  compositeOnCpu(f.scene, f.scene.camera, f.settings, f.visibility, f.out, composite);
  const glm::vec3 c = composite.rgb[g];
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.color[k], c[k], 1e-6f * (1.0f + c[k])) << k;
  EXPECT_EQ(t.color, t.local + t.reflected + t.transmitted);

  // The text names what the tree holds.
  std::string text = toText(t, f.scene);
  for (const char* part : {"primary ray", "hit glass-sphere", "reflection ray, depth 1", "refraction ray, depth 1",
                           "light 0 key: unoccluded", "light 1 spot: ", "pixel = local"})
    EXPECT_NE(text.find(part), std::string::npos) << part << "\n" << text;
  if (std::getenv("TANDEM_PRINT_TRACE")) std::printf("%s", text.c_str());
}

// Every pixel of a small frame, at full and half ray resolution: the trace's reflected, transmitted and
// light mask are the pass's, bit for bit, and its rays add up to the frame's counts.
// glossy.json: several reflection and refraction rays per glossy hit, and an area light's samples.
TEST(PixelTrace, EveryPixelEqualsTheRayPass) {
  for (const char* sceneFile : {"", "glossy.json"})
  for (int scale : {1, 2}) {
    SCOPED_TRACE("scale " + std::to_string(scale) + " " + sceneFile);
    WhittedFrame f(96, 54, scale, sceneFile);
    ASSERT_TRUE(f.tracer);
    const int gw = f.out.width, gh = f.out.height;
    ASSERT_EQ(f.out.reflected.size(), static_cast<std::size_t>(gw * gh));
    RayCounts sum;
    int differing = 0, background = 0;
    for (int gy = 0; gy < gh; ++gy)
      for (int gx = 0; gx < gw; ++gx) {
        PixelTrace t = f.tracer->tracePixel(f.scene, f.scene.camera, f.settings, f.visibility, gx, gy);
        const std::size_t g = at(gx, gy, gw);
        differing += glm::vec3(f.out.reflected[g]) != t.reflected || glm::vec3(f.out.transmitted[g]) != t.transmitted ||
                     (f.out.lightMask[g] & 3u) != (t.lightMask & 3u);
        background += !t.nodes.front().hit;
        if (gx == gw / 2 && gy == gh / 2) expectConsistentTree(t);
        sum.primary += t.rays.primary;
        sum.shadow += t.rays.shadow;
        sum.reflection += t.rays.reflection;
        sum.refraction += t.rays.refraction;
      }
    EXPECT_EQ(differing, 0);
    if (*sceneFile == '\0') {
      EXPECT_GT(background, 0);  // the sky is in view: its pixels are traced too
    }
    EXPECT_EQ(sum.primary, f.out.counts.primary);
    EXPECT_EQ(sum.shadow, f.out.counts.shadow);
    EXPECT_EQ(sum.reflection, f.out.counts.reflection);
    EXPECT_EQ(sum.refraction, f.out.counts.refraction);
  }
}

// The reference frame: each pixel's trace is its samples' trees, and its colour the frame's pixel, exactly.
TEST(PixelTrace, ReferencePixelsEqualTheReferenceFrame) {
  auto loaded = loadDefaultScene();
  ASSERT_TRUE(loaded.ok());
  const Scene& scene = *loaded;
  FrameSettings s = *presetSettings("reference", settingsFor(48, 27));
  s.referenceSpp = 2;
  auto tracer = makeTracer(scene);
  ASSERT_TRUE(tracer);
  ImageF frame;
  RayCounts counts;
  tracer->renderReference(scene, scene.camera, s, frame, counts);
  RayCounts sum;
  int differing = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      PixelTrace t = tracer->tracePixelReference(scene, scene.camera, s, x, y);
      ASSERT_EQ(t.roots.size(), 4u);
      differing += t.color != frame.at(x, y);
      sum.primary += t.rays.primary;
      sum.shadow += t.rays.shadow;
      sum.reflection += t.rays.reflection;
      sum.refraction += t.rays.refraction;
      if (x == 20 && y == 13) expectConsistentTree(t);
    }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(sum.primary, counts.primary);
  EXPECT_EQ(sum.shadow, counts.shadow);
  EXPECT_EQ(sum.reflection, counts.reflection);
  EXPECT_EQ(sum.refraction, counts.refraction);
}

// Why rays were not followed: the depth limit, an effect not by rays, and lights without a shadow ray.
TEST(PixelTrace, NamesWhyRaysWereNotTraced) {
  WhittedFrame f(320, 180);
  ASSERT_TRUE(f.tracer);
  FrameSettings s = f.settings;
  s.maxDepth = 1;
  s.refraction = EffectMode::Off;
  s.shadows = EffectMode::Raster;  // the primary hit's lights are the shadow map's; secondary hits trace
  PixelTrace t = f.tracer->tracePixel(f.scene, f.scene.camera, s, f.visibility, kGlassX, kGlassY);
  const TraceNode& primary = t.nodes[static_cast<std::size_t>(t.roots[0])];
  EXPECT_EQ(primary.refraction, SecondaryRay::NotByRays);
  EXPECT_LT(primary.refractionChild, 0);
  for (const TraceLight& l : primary.lights) EXPECT_EQ(l.visibility, LightVisibility::NotTraced);
  EXPECT_EQ(t.rays.refraction, 0u);
  ASSERT_GE(primary.reflectionChild, 0);
  const TraceNode& r = t.nodes[static_cast<std::size_t>(primary.reflectionChild)];
  if (r.hit) {
    EXPECT_FALSE(r.sumEvaluated);
    EXPECT_EQ(r.reflection, SecondaryRay::DepthLimit);
    for (const TraceLight& l : r.lights) EXPECT_NE(l.visibility, LightVisibility::NotTraced);
  }
  expectConsistentTree(t);
  // A background pixel: the primary ray escapes, nothing else is traced.
  PixelTrace sky = f.tracer->tracePixel(f.scene, f.scene.camera, f.settings, f.visibility, 160, 0);
  ASSERT_EQ(sky.nodes.size(), 1u);
  EXPECT_FALSE(sky.nodes[0].hit);
  EXPECT_EQ(sky.color, f.scene.background);
  EXPECT_EQ(sky.rays.total(), 0u);
}

}  // namespace
}  // namespace tandem::rt
