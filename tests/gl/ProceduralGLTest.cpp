// Procedural 3D textures and bump maps (docs/procedural.md) in the frame: the GL shade pass (procedural.glsl as
// GLSL) and the ray pass's CPU twin (as C++) shade every pattern alike, in object and world space, on triangles
// and on exact solids; an object-space pattern moves with its object and a world-space one stays; bumps bend the
// shading and the rays alike, so the hybrid frame meets the reference.
#include <gtest/gtest.h>

#include <cmath>

#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "gl/GpuScene.h"
#include "gl/VisibilityPass.h"
#include "rt/RayTracer.h"
#include "rt/SurfaceShading.h"
#include "tandem/SceneFile.h"

namespace tandem {
namespace {

constexpr int kW = 240, kH = 120;

Material patterned(Pattern type, bool world, float scale, float turbulence, float bump, glm::vec3 kd, glm::vec3 kd2) {
  Material m;
  m.kd = m.ka = kd;
  m.kd2 = kd2;
  m.ks = glm::vec3(0.4f);
  m.ns = 30.0f;
  m.procedural = {type, world, scale, turbulence, 4, bump};
  return m;
}

// A row of six balls, one pattern each (some in world space, some bumped), over a marble floor; every other
// ball an exact sphere. Far from the origin on x, so world-space points are large numbers.
Scene patternScene(glm::vec3 offset = glm::vec3(0.0f)) {
  Scene s;
  s.meshes.push_back(makePlane(glm::vec2(9.0f, 5.0f), 6));
  s.meshes.push_back(makeSphere(0.45f, 48, 24));
  Mesh exact = makeSphere(0.45f * 1.01f / (std::cos(3.14159265f / 48) * std::cos(3.14159265f / 48)), 48, 24);
  solid::Solid ball;
  ball.nodes.push_back({});
  ball.nodes[0].primitive = {solid::Shape::Sphere, glm::dvec3(0.45)};
  exact.exact = ball;
  s.meshes.push_back(exact);
  const glm::vec3 cream(0.9f, 0.85f, 0.75f), dark(0.15f, 0.12f, 0.2f);
  s.materials.push_back(patterned(Pattern::Marble, true, 1.5f, 1.5f, 0.0f, cream, dark));
  s.materials.push_back(patterned(Pattern::Noise, false, 4.0f, 0.0f, 0.02f, cream, dark));
  s.materials.push_back(patterned(Pattern::Fbm, true, 3.0f, 0.0f, 0.0f, cream, dark));
  s.materials.push_back(patterned(Pattern::Turbulence, false, 3.0f, 0.0f, 0.01f, cream, dark));
  s.materials.push_back(patterned(Pattern::Marble, false, 2.5f, 1.0f, 0.0f, cream, dark));
  s.materials.push_back(patterned(Pattern::Wood, false, 6.0f, 0.4f, 0.005f, {0.6f, 0.35f, 0.15f}, {0.3f, 0.15f, 0.05f}));
  s.materials.push_back(patterned(Pattern::Granite, true, 12.0f, 0.0f, 0.002f, {0.6f, 0.6f, 0.6f}, dark));
  Instance floor;
  floor.worldFromObject = glm::translate(glm::mat4(1.0f), offset);
  s.instances.push_back(floor);
  for (int i = 0; i < 6; ++i) {
    Instance inst;
    inst.mesh = i % 2 == 0 ? 1 : 2;
    inst.material = static_cast<std::uint32_t>(1 + i);
    const float fi = static_cast<float>(i);
    inst.worldFromObject = glm::rotate(glm::translate(glm::mat4(1.0f), offset + glm::vec3(-3.0f + 1.2f * fi, 0.45f, 0.0f)),
                                       0.3f * fi, glm::vec3(0.2f, 1.0f, 0.1f));
    s.instances.push_back(inst);
  }
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.intensity = 0.3f;
  Light key;
  key.posW = offset + glm::vec3(-2.0f, 4.0f, 3.0f);
  key.intensity = 1.2f;
  s.lights = {ambient, key};
  s.camera.posW = offset + glm::vec3(0.0f, 1.6f, 4.2f);
  s.camera.targetW = offset + glm::vec3(0.0f, 0.3f, 0.0f);
  s.background = {0.1f, 0.1f, 0.15f};
  return s;
}

void checkParity(const Scene& scene, ShadingModel model) {
  TD_REQUIRE_GL_CONTEXT();
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings settings = gltest::rasterOnly(kW, kH);
  settings.shadingOverride = model;
  renderer->render(scene.camera, settings);
  const ImageF gl = renderer->readLinear();
  gltest::savePng("procedural-" + std::string(toString(model)) + ".png", renderer->readImage());

  // The ids the frame shaded: the raster's, the exact spheres' pixels resolved as the frame resolves them.
  gl::GpuScene gpu;
  gpu.upload(scene, model);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok());
  ASSERT_TRUE(pass->resize(kW, kH).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));
  rt::VisibilityBuffer ids;
  ids.width = kW;
  ids.height = kH;
  pass->readIds(ids.ids);
  auto tracer = rt::RayTracer::create(2);
  ASSERT_TRUE(tracer.ok());
  ASSERT_TRUE((*tracer)->setScene(scene).ok());
  std::vector<ResolvedPixel> records;
  RayCounts counts;
  (*tracer)->resolveExact(scene, scene.camera, ids, records, counts);
  ASSERT_GT(records.size(), 1000u);

  // The CPU twin in the frame's render space (the same anchor as the GL copy's).
  const glm::vec3 anchor = gpu.anchor();
  const Camera cam = toRenderSpace(scene.camera, anchor);
  rt::FrameShading frame(scene, model, anchor);
  int compared = 0, onSolids = 0, mismatched = 0;
  double worst = 0.0;
  std::string examples;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const glm::uvec2 id = ids.ids[static_cast<std::size_t>(y) * kW + x];
      if (id.x == 0) continue;
      const rt::InstanceTransform t = rt::makeInstanceTransform(scene.instances[id.x - 1].worldFromObject, anchor);
      const Ray ray = cam.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {kW, kH});
      const rt::SurfaceHit hit = rt::resolvePrimary(scene, t, cam, id, ray);
      const glm::vec3 want = rt::shadeLocal(scene, frame, t, hit, ~0u);
      const glm::vec3 got = gl.at(x, y);
      const float err = glm::length(got - want);
      worst = std::max(worst, double(err));
      ++compared;
      onSolids += id.y == kExactTriangle ? 1 : 0;
      // Float evaluation order (fused multiply-adds, sin and cos) differs a little between the GL and the CPU;
      // noise at these scales turns that into errors far below what a pattern or bump difference makes.
      // Turbulence's creases (|noise| at 0) can put a bumped pixel's two evaluations on either side of one.
      if (err > 3e-3f + 3e-3f * glm::length(want)) {
        if (++mismatched <= 8)
          examples += std::string(" pixel ") + std::to_string(x) + "," + std::to_string(y) + " id " +
                      std::to_string(id.x) + "/" + std::to_string(id.y) + " error " + std::to_string(err) + ";";
      }
    }
  EXPECT_GT(onSolids, 1000);
  EXPECT_LE(mismatched, compared / 2000) << toString(model) << ": worst " << worst << " of " << compared << ":" << examples;
}

TEST(ProceduralGL, ShadePassMatchesItsCppTwinForEveryPattern) {
  for (ShadingModel model : {ShadingModel::Phong, ShadingModel::Gouraud}) checkParity(patternScene(), model);
}

TEST(ProceduralGL, ParityHoldsFarFromTheOrigin) {
  // World-space patterns at 1e4: render space keeps the shading's numbers small, the patterns see world points.
  checkParity(patternScene(glm::vec3(1e4f, 0.0f, -2e3f)), ShadingModel::Phong);
}

TEST(ProceduralGL, ObjectSpacePatternsMoveWithTheirObjectWorldSpaceOnesStay) {
  TD_REQUIRE_GL_CONTEXT();
  // The whole scene (camera included) moved by one translation: object-space patterns look the same, world-space
  // ones slide across their surfaces.
  const glm::vec3 move(0.37f, 0.0f, 0.21f);
  auto here = gltest::sceneFrame(*glContext_, patternScene(), kW, kH);
  auto there = gltest::sceneFrame(*glContext_, patternScene(move), kW, kH);
  ASSERT_TRUE(here.renderer && there.renderer);
  const FrameSettings s = gltest::rasterOnly(kW, kH);
  const Image a = gltest::drawFrame(here, s), b = gltest::drawFrame(there, s);
  // Per ball, the display values' difference inside its silhouette (the balls' materials say which space).
  const Scene scene = patternScene();
  double objectDiff = 0, worldDiff = 0;
  int objectPixels = 0, worldPixels = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const std::size_t p = 4 * (static_cast<std::size_t>(y) * kW + x);
      // Which ball covers this pixel: by its x position in the row (balls at -3 + 1.2 i).
      const Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {kW, kH});
      int ball = -1;
      for (int i = 0; i < 6; ++i) {
        const glm::vec3 c(-3.0f + 1.2f * static_cast<float>(i), 0.45f, 0.0f);
        const glm::vec3 oc = ray.origin - c;
        const float bq = glm::dot(oc, ray.dir), cq = glm::dot(oc, oc) - 0.4f * 0.4f;  // well inside the silhouette
        if (bq * bq - cq > 0.0f) ball = i;
      }
      if (ball < 0) continue;
      double d = 0;
      for (int c = 0; c < 3; ++c) d += std::abs(int(a.rgba[p + c]) - int(b.rgba[p + c]));
      const bool world = scene.materials[scene.instances[1 + ball].material].procedural.worldSpace;
      (world ? worldDiff : objectDiff) += d;
      ++(world ? worldPixels : objectPixels);
    }
  ASSERT_GT(objectPixels, 500);
  ASSERT_GT(worldPixels, 300);
  EXPECT_LT(objectDiff / objectPixels, 0.5) << "object space: the pattern rode along (rounding only)";
  EXPECT_GT(worldDiff / worldPixels, 10.0) << "world space: the pattern stayed behind";
}

TEST(ProceduralGL, BumpsBendTheRaysAsTheShadingAndTheFrameMeetsTheReference) {
  TD_REQUIRE_GL_CONTEXT();
  // The scene of assets/scenes/csg.json: marble, wood and granite, bumped, under glass and a mirror ring.
  auto f = gltest::sceneFrame(*glContext_, loadSceneFile(test::sourceDir() + "/assets/scenes/csg.json"), 256, 144);
  ASSERT_TRUE(f.renderer);
  const Image reference = gltest::drawFrame(f, gltest::presetFor(f, "reference"));
  const Image full = gltest::drawFrame(f, gltest::presetFor(f, "hybrid-full"));
  EXPECT_LT(gltest::flipMean(full, reference), 0.003);
  // Without the bumps the image changes where the grain is: the bumps do something.
  auto flat = loadSceneFile(test::sourceDir() + "/assets/scenes/csg.json");
  ASSERT_TRUE(flat.ok());
  for (Material& m : flat->materials) m.procedural.bump = 0.0f;
  auto g = gltest::sceneFrame(*glContext_, std::move(flat), 256, 144);
  ASSERT_TRUE(g.renderer);
  EXPECT_GT(gltest::flipMean(gltest::drawFrame(g, gltest::presetFor(g, "hybrid-full")), full), 0.002);
}

}  // namespace
}  // namespace tandem
