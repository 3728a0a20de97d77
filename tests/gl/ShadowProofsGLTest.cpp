// Hybrid shadows proved in the GL (gl/ShadowProofPass.h, shaders/shadow_proof.frag; docs/shadows.md): every
// answer the GL gives is the one Embree gives the CPU's own shadow ray, and a frame that takes them is the
// all-rays frame to the bit. The scenes are the CPU proofs' hostile ones (thin slabs, contacts, grazing
// light, lights at surfaces, extreme scales, far from the origin); each also checks that the GL decided most
// rays, so none passes by deciding none.
#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <utility>

#include "../rt/ShadowScenes.h"
#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "gl/GpuScene.h"
#include "gl/ShadowProofPass.h"
#include "gl/VisibilityPass.h"
#include "render/ShadowProofs.h"
#include "rt/RayMath.h"
#include "rt/ShadowCertainty.h"

namespace tandem {
namespace {

using namespace rt::test;

struct Outcome {
  std::size_t decided = 0;      // (pixel, light) pairs the GL answered
  std::size_t checked = 0;      // of them, those whose ray the CPU would trace (the others ask no ray)
  std::size_t wrong = 0;        // answers that differ from Embree's
  std::size_t rays = 0;         // (pixel, light) pairs whose shadow ray the CPU would trace
  std::size_t geometry = 0;     // pixels on geometry
  std::size_t complete = 0;     // of them, those whose whole light mask the GL gave (TD_PROOF_COMPLETE)
  std::size_t maskDiffers = 0;  // pixels whose frame light mask differs from the all-rays frame's
  std::uint64_t tracedWithProofs = 0, tracedAll = 0, answered = 0;
};

// The GL's proofs of `scene` at w × h (every pixel, or with `rayScale` > 1 each grid pixel's stand-in), with
// the ids they were drawn for and the tracer whose maps they copy; no tracer where a step failed.
struct Drawn {
  rt::VisibilityBuffer visibility;  // ids and proofs
  std::unique_ptr<rt::RayTracer> tracer;
};
Drawn drawProofs(const Scene& scene, const FrameSettings& s, int rayScale = 1) {
  Drawn d;
  const int w = s.width, h = s.height;
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto vis = gl::VisibilityPass::create();
  auto pass = gl::ShadowProofPass::create();
  EXPECT_TRUE(vis.ok() && pass.ok()) << (pass.ok() ? "" : pass.error().message);
  if (!vis.ok() || !pass.ok() || !vis->resize(w, h).ok()) return d;
  const Camera glCamera = toRenderSpace(scene.camera, gpu.anchor());
  vis->render(gpu, glCamera);
  d.visibility.width = w;
  d.visibility.height = h;
  vis->readIds(d.visibility.ids);
  auto tracer = makeTracer(scene);
  if (!tracer) return d;
  const rt::ShadowCertainty* maps = tracer->shadowMapsFor(scene, scene.camera, s, gpu.anchor());
  EXPECT_NE(maps, nullptr);
  if (!maps) return d;
  pass->upload(proofSource(*maps, scene));
  pass->setInstanceFlags(proofInstanceFlags(scene, s));
  EXPECT_TRUE(pass->prove(gpu, vis->ids(), w, h, glCamera, rayScale).ok());
  pass->read(d.visibility.proofs);
  EXPECT_EQ(d.visibility.proofs.size(), d.visibility.ids.size());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  if (d.visibility.proofs.size() == d.visibility.ids.size()) d.tracer = std::move(tracer);
  return d;
}

// The GL's proofs of `scene` at w × h, checked pixel by pixel against Embree (tracePixel of the all-rays
// frame), then the ray pass with them against the all-rays pass.
Outcome prove(const Scene& scene, int w, int h, std::optional<ShadingModel> shading = std::nullopt) {
  Outcome o;
  FrameSettings s = settingsFor(w, h);
  s.shadows = s.reflections = s.refraction = EffectMode::Ray;
  s.hybridShadows = true;
  s.shadowProofs = ShadowProofs::Gl;  // the GL's answers and the maps, without the tile shafts before them
  s.shadingOverride = shading;
  Drawn d = drawProofs(scene, s);
  if (!d.tracer) return o;
  rt::VisibilityBuffer visibility;  // the ids alone: the all-rays frame's
  visibility.width = w;
  visibility.height = h;
  visibility.ids = d.visibility.ids;
  const std::vector<std::uint32_t>& proofs = d.visibility.proofs;
  auto& tracer = d.tracer;

  FrameSettings all = s;
  all.hybridShadows = false;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * w + x;
      if (visibility.ids[p].x == 0) {
        EXPECT_EQ(proofs[p], 0u) << "the sky proved at " << x << "," << y;
        continue;
      }
      const std::uint32_t decided = (proofs[p] >> 8) & 0xFFu;
      o.complete += (proofs[p] & 0x80000000u) != 0 ? 1 : 0;
      ++o.geometry;
      o.decided += static_cast<std::size_t>(std::popcount(decided));
      const PixelTrace t = tracer->tracePixel(scene, scene.camera, all, visibility, x, y);
      if (t.roots.empty()) continue;
      for (const TraceLight& l : t.nodes[static_cast<std::size_t>(t.roots[0])].lights) {
        if (l.visibility != LightVisibility::Unoccluded && l.visibility != LightVisibility::Occluded) continue;
        ++o.rays;
        if (!((decided >> l.light) & 1u)) continue;
        ++o.checked;
        const bool lit = (proofs[p] >> l.light) & 1u;
        if (lit != (l.visibility == LightVisibility::Unoccluded)) {
          ++o.wrong;
          ADD_FAILURE() << "pixel " << x << "," << y << " light " << l.light << ": the GL says "
                        << (lit ? "lit" : "shadowed") << ", Embree the opposite";
        }
      }
    }

  // The frame: the ray pass with the GL's answers gives the all-rays light mask and outputs to the bit.
  rt::RayOutputs withProofs, allRays;
  tracer->trace(scene, scene.camera, all, visibility, allRays);
  visibility.proofs = proofs;
  tracer->trace(scene, scene.camera, s, visibility, withProofs);
  EXPECT_EQ(withProofs.lightMask.size(), allRays.lightMask.size());
  for (std::size_t i = 0; i < std::min(withProofs.lightMask.size(), allRays.lightMask.size()); ++i)
    o.maskDiffers += withProofs.lightMask[i] != allRays.lightMask[i];
  EXPECT_EQ(withProofs.reflected.size(), allRays.reflected.size());
  EXPECT_TRUE(withProofs.reflected == allRays.reflected);
  EXPECT_TRUE(withProofs.transmitted == allRays.transmitted);
  EXPECT_EQ(withProofs.counts.shadow + withProofs.counts.shadowByMap + withProofs.counts.shadowByShaft,
            allRays.counts.shadow);
  o.tracedWithProofs = withProofs.counts.shadow;
  o.tracedAll = allRays.counts.shadow;
  o.answered = withProofs.counts.shadowByMap;
  return o;
}

void expectExact(const Outcome& o, double share, const char* what) {
  EXPECT_EQ(o.wrong, 0u) << what;
  EXPECT_EQ(o.maskDiffers, 0u) << what;
  ASSERT_GT(o.rays, 0u) << what;
  EXPECT_GE(static_cast<double>(o.checked), share * static_cast<double>(o.rays))
      << what << ": the GL answered " << o.checked << " of the " << o.rays << " primary shadow rays";
  std::printf("%s: the GL answered %zu of %zu primary shadow rays (%zu answers in all); %zu of %zu pixels complete\n",
              what, o.checked, o.rays, o.decided, o.complete, o.geometry);
}

TEST(ShadowProofsGLTest, ObjectsOnAFloorEveryAnswerIsEmbrees) {
  TD_REQUIRE_GL_CONTEXT();
  Outcome o = prove(objectsOnAFloor(), 160, 90);
  expectExact(o, 0.95, "objects on a floor");
  // Every surface is plain diffuse: most pixels need no resolve on the CPU at all.
  EXPECT_GT(o.complete * 10, o.geometry * 8) << o.complete << " of " << o.geometry << " pixels complete";
  // Flat and Gouraud shading test the lights on the geometric normal and the vertex normals' as Phong does.
  for (ShadingModel model : {ShadingModel::Flat, ShadingModel::Gouraud}) {
    const Outcome m = prove(objectsOnAFloor(), 160, 90, model);
    expectExact(m, 0.95, model == ShadingModel::Flat ? "flat" : "gouraud");
    EXPECT_GT(m.complete * 10, m.geometry * 8);
  }
  EXPECT_GT(o.tracedWithProofs, 0u);  // edges and contacts stay the rays'
  EXPECT_LT(o.tracedWithProofs * 5, o.tracedAll);
}

TEST(ShadowProofsGLTest, ExtremeScalesAndFarFromTheOrigin) {
  TD_REQUIRE_GL_CONTEXT();
  expectExact(prove(objectsOnAFloor(1e-4f), 120, 68), 0.95, "scale 1e-4");
  expectExact(prove(objectsOnAFloor(1e4f), 120, 68), 0.95, "scale 1e4");
  // Render space is camera-relative: a scene 1e6 from the origin keeps its precision.
  expectExact(prove(objectsOnAFloor(1.0f, glm::vec3(1e6f, -2e5f, 5e5f)), 120, 68), 0.95, "1e6 from the origin");
}

// What the two hits' rounding depends on beyond the world coordinates: object-space coordinates of 1e4 and
// 1e5 cancelled by their instances' translations (the vertices' transforms round at that scale), an
// orthographic camera 50 units wide (its rays' origins round at that scale), and a coarse sphere with smooth
// normals (the two sides' barycentrics interpolate vertex normals that differ a lot).
TEST(ShadowProofsGLTest, LargeObjectSpaceOrthographicAndCoarseSmoothNormals) {
  TD_REQUIRE_GL_CONTEXT();
  for (float magnitude : {1e4f, 1e5f}) {
    Scene scene = objectsOnAFloor();
    const glm::vec3 offset(magnitude, -0.5f * magnitude, 0.75f * magnitude);
    for (Instance& inst : scene.instances) {
      for (glm::vec3& p : scene.meshes[inst.mesh].positions) p += offset;
      inst.worldFromObject = inst.worldFromObject * translate(-offset);
    }
    // The two sides' vertices lie a few ULPs of 1e4 apart (~1e-3, a tenth of the floor's texels at the
    // directional map's 1024²): the margins outgrow the texels and the GL proves nothing here — which it must
    // do without a wrong answer (the CPU's maps, which test Embree's own ray, still prove these).
    const Outcome o = prove(scene, 120, 68);
    expectExact(o, 0.0, magnitude < 5e4f ? "object space at 1e4" : "object space at 1e5");
  }
  Scene ortho = objectsOnAFloor();
  ortho.camera.orthographic = true;
  ortho.camera.orthoHeight = 28.0f;
  expectExact(prove(ortho, 160, 90), 0.9, "orthographic 28 high");
  Scene coarse = objectsOnAFloor();
  coarse.meshes[coarse.instances[1].mesh] = makeSphere(1.0f, 8, 4);  // smooth normals on 64 faces
  const Outcome c = prove(coarse, 160, 90);
  expectExact(c, 0.9, "coarse smooth sphere");
  EXPECT_GT(c.complete * 10, c.geometry * 8);
}

// A ray grid of half the frame's size: the pass proves each grid pixel's stand-in (rt::fullPixelOfGridPixel)
// and nothing else.
TEST(ShadowProofsGLTest, ACoarseRayGridIsProvedAtItsStandIns) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = objectsOnAFloor();
  const int w = 161, h = 91, scale = 2;  // odd sizes: the last grid row and column clamp to the frame
  FrameSettings s = settingsFor(w, h);
  s.hybridShadows = true;
  const Drawn d = drawProofs(scene, s, scale);
  ASSERT_TRUE(d.tracer);
  const std::vector<glm::uvec2>& ids = d.visibility.ids;
  const std::vector<std::uint32_t>& proofs = d.visibility.proofs;
  std::vector<std::uint8_t> standIn(ids.size(), 0);
  for (int gy = 0; gy < rt::gridSize(h, scale); ++gy)
    for (int gx = 0; gx < rt::gridSize(w, scale); ++gx) {
      const glm::ivec2 p = rt::fullPixelOfGridPixel(gx, gy, scale, w, h);
      standIn[static_cast<std::size_t>(p.y) * w + p.x] = 1;
    }
  std::size_t onGeometry = 0, proved = 0, elsewhere = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (!standIn[i]) {
      elsewhere += proofs[i] != 0 ? 1 : 0;
      continue;
    }
    if (ids[i].x == 0) continue;
    ++onGeometry;
    proved += (proofs[i] >> 8) != 0 ? 1 : 0;
  }
  EXPECT_EQ(elsewhere, 0u) << "pixels no grid pixel stands for were proved";
  EXPECT_GT(proved * 10, onGeometry * 9) << proved << " of " << onGeometry << " stand-ins proved";
}

// Slabs a thousandth thick, one just above the floor, and a needle thinner than a texel.
TEST(ShadowProofsGLTest, ThinSlabsAndContacts) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = thinSlabsAndContacts();
  expectExact(prove(scene, 160, 90), 0.95, "thin slabs");
}

// Light nearly parallel to a bumpy floor: rays graze every face. Few can be proved, but not none.
TEST(ShadowProofsGLTest, GrazingLight) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = grazingLight();
  expectExact(prove(scene, 160, 90), 0.15, "grazing light");
}

// A point light a hair above the floor, one inside a box, and a plate nearer a light than its maps begin.
TEST(ShadowProofsGLTest, LightsAtSurfaces) {
  TD_REQUIRE_GL_CONTEXT();
  const Scene scene = lightsAtSurfaces();
  expectExact(prove(scene, 160, 90), 0.6, "lights at surfaces");
}

// The Renderer's frame: --shadows hybrid with the GL's proofs is the --shadows ray frame to the byte, with
// most primary shadow rays answered.
TEST(ShadowProofsGLTest, TheFrameIsTheAllRaysFrame) {
  TD_REQUIRE_GL_CONTEXT();
  // csg.json: exact solids, whose proxies' pixels the resolve step may give another hit than the GL proved.
  // hybrid-fast: a ray grid of half the frame's size, whose stand-in pixels alone are proved.
  for (const auto& [name, presetName] : {std::pair{"whitted.json", "hybrid-full"},
                                         std::pair{"csg.json", "hybrid-full"},
                                         std::pair{"whitted.json", "hybrid-fast"}}) {
    const char* preset = presetName;  // a lambda may not capture a structured binding before C++20
    gltest::SceneFrame f =
        gltest::sceneFrame(*glContext_, loadSceneFile(test::sourceDir() + "/assets/scenes/" + name), 320, 180);
    ASSERT_TRUE(f.renderer);
    auto frame = [&](bool hybrid, ShadowProofs where, FrameStats& stats) {
      FrameSettings s = gltest::presetFor(f, preset);
      s.hybridShadows = hybrid;
      s.shadowProofs = where;
      gltest::drawFrame(f, s, &stats);
      return f.renderer->readLinear();
    };
    FrameStats all, gl, cpu;
    const ImageF a = frame(false, ShadowProofs::Auto, all), g = frame(true, ShadowProofs::Gl, gl),
                 c = frame(true, ShadowProofs::Cpu, cpu);
    ASSERT_EQ(a.rgb.size(), g.rgb.size());
    ASSERT_EQ(a.rgb.size(), c.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), g.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0) << name;
    EXPECT_EQ(std::memcmp(a.rgb.data(), c.rgb.data(), a.rgb.size() * sizeof(glm::vec3)), 0) << name;
    EXPECT_EQ(gl.rays.shadow + gl.rays.shadowByMap + gl.rays.shadowByShaft, all.rays.shadow) << name;
    EXPECT_EQ(cpu.rays.shadow + cpu.rays.shadowByMap + cpu.rays.shadowByShaft, all.rays.shadow) << name;
    // Whitted: 24x fewer (secondary hits by the CPU's maps); csg: its solids' pixels are the rays' (their hits
    // are the resolve step's, not the raster's triangles): 58 % still traced.
    if (std::string(name) == "whitted.json") EXPECT_LT(gl.rays.shadow * 10, all.rays.shadow) << preset;
    else EXPECT_LT(gl.rays.shadow * 3, all.rays.shadow * 2) << name;
    EXPECT_TRUE(gl.shadowsProvedInGl) << name;
    EXPECT_FALSE(cpu.shadowsProvedInGl || all.shadowsProvedInGl) << name;
  }
}

// Something moves every frame: the maps are built anew each time and a forced GL copy follows them, and a frame
// proved on the CPU between them reads no proof of the frame before; every frame stays the all-rays frame.
// (Auto leaves such frames to the ray pass: FramePlan's glProofsThisFrame.)
TEST(ShadowProofsGLTest, MovingGeometryKeepsTheAllRaysFrame) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = objectsOnAFloor();
  scene.instances[1].dynamic = true;  // the sphere
  auto make = [&] { return gltest::sceneFrame(*glContext_, Result<Scene>(scene), 160, 90); };
  gltest::SceneFrame gl = make(), all = make();
  ASSERT_TRUE(gl.renderer && all.renderer);
  FrameSettings s = gltest::presetFor(gl, "hybrid-full");
  s.reuseRays = false;
  FrameSettings g = s, a = s;
  g.hybridShadows = true;
  g.shadowProofs = ShadowProofs::Gl;
  for (int frame = 0; frame < 4; ++frame) {
    g.shadowProofs = frame == 2 ? ShadowProofs::Cpu : ShadowProofs::Gl;
    const glm::mat4 at = translate({-1.5f + 0.4f * static_cast<float>(frame), 1.2f, 0.0f});
    gl.renderer->setInstanceTransform(1, at);
    all.renderer->setInstanceTransform(1, at);
    FrameStats gs, as;
    gltest::drawFrame(gl, g, &gs);
    gltest::drawFrame(all, a, &as);
    const ImageF x = gl.renderer->readLinear(), y = all.renderer->readLinear();
    ASSERT_EQ(x.rgb.size(), y.rgb.size());
    EXPECT_EQ(std::memcmp(x.rgb.data(), y.rgb.data(), x.rgb.size() * sizeof(glm::vec3)), 0) << "frame " << frame;
    EXPECT_EQ(gs.shadowsProvedInGl, frame != 2) << "frame " << frame;
    EXPECT_GT(gs.shadowMapsMs, 0.0) << "frame " << frame << ": the maps follow the sphere";
    EXPECT_EQ(gs.rays.shadow + gs.rays.shadowByMap + gs.rays.shadowByShaft, as.rays.shadow);
  }
}

}  // namespace
}  // namespace tandem
