// glTF material extras in GL and the CPU twin (docs/gltf.md): normal maps (GL against rt::resolveHit +
// rt::shadeLocal, the same formula tdPerturbNormal), emissive textures, MASK cut-outs in the visibility
// pass, BLEND coverage as thin transmission through the raster refraction path, single-sided faces culled in
// views and in the lights' maps as the rays pass them.
#include <gtest/gtest.h>

#include <cmath>

#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "gl/GpuScene.h"
#include "gl/VisibilityPass.h"
#include "rt/SurfaceShading.h"

namespace tandem {
namespace {

constexpr int kW = 160, kH = 120;

// A unit quad in the z = 0 plane facing +Z, uvs over [0, 1]², tangent +X (w = 1).
Mesh quadMesh(float half, float z = 0.0f) {
  Mesh m;
  m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.tangents.assign(4, glm::vec4(1, 0, 0, 1));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

Texture solidTexture(int w, int h, bool srgb, auto texelAt) {
  Texture t;
  t.width = w;
  t.height = h;
  t.srgb = srgb;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::u8vec4 c = texelAt(x, y);
      for (int k = 0; k < 4; ++k) t.rgba8.push_back(c[k]);
    }
  return t;
}

Scene baseScene() {
  Scene s;
  s.camera.posW = {0, 0, 3};
  s.camera.targetW = {0, 0, 0};
  s.camera.upW = {0, 1, 0};
  s.camera.yFovDeg = 40.0f;
  s.background = glm::vec3(0.0f);
  return s;
}

struct Shaded {
  ImageF gl;
  std::vector<glm::uvec2> ids;
};

Shaded renderGl(GlContext& context, const Scene& scene, const FrameSettings& settings) {
  Shaded out;
  auto renderer = gltest::makeRenderer(context);
  if (!renderer) return out;
  EXPECT_TRUE(renderer->setScene(scene).ok());
  renderer->render(scene.camera, settings);
  out.gl = renderer->readLinear();
  gl::GpuScene gpu;
  gpu.upload(scene, std::nullopt);
  auto pass = gl::VisibilityPass::create();
  EXPECT_TRUE(pass.ok());
  EXPECT_TRUE(pass->resize(settings.width, settings.height).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));  // the GL copy is in render space
  pass->readIds(out.ids);
  return out;
}

glm::vec3 cpuLocal(const Scene& scene, glm::uvec2 id, int x, int y) {
  rt::FrameShading frame(scene, std::nullopt);
  rt::InstanceTransform t = rt::makeInstanceTransform(scene.instances[id.x - 1].worldFromObject);
  Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {kW, kH});
  rt::SurfaceHit hit = rt::resolveHit(scene, t, id.x - 1, id.y, ray);
  return rt::shadeLocal(scene, frame, t, hit, ~0u);
}

TEST(GltfMaterialsGLTest, NormalMapMatchesCpuTwin) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = baseScene();
  scene.meshes.push_back(quadMesh(1.0f));
  // A smooth bump field (8×8 texels over a quad ~100 pixels wide: magnified, so GL samples level 0
  // bilinearly like the CPU).
  scene.textures.push_back(solidTexture(8, 8, false, [](int x, int y) {
    // Gentle steps between texels: llvmpipe filters 8-bit texels with 8-bit weights, an error that
    // grows with the step between neighbours.
    glm::vec3 n = glm::normalize(glm::vec3(0.5f * std::sin(0.8f * float(x)), 0.5f * std::cos(0.7f * float(y)), 1.0f));
    glm::vec3 e = (n * 0.5f + 0.5f) * 255.0f;
    return glm::u8vec4(std::lround(e.x), std::lround(e.y), std::lround(e.z), 255);
  }));
  Material m = gltest::plainMaterial(glm::vec3(0.7f));
  m.ks = glm::vec3(0.3f);
  m.ns = 20.0f;
  m.normalTexture = 0;
  m.normalScale = 0.8f;
  scene.materials.push_back(m);
  scene.instances.push_back({"quad", 0, 0, glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0, 1, 0)), false});
  Light l;
  l.type = LightType::Point;
  l.posW = {1.0f, 1.5f, 2.0f};
  l.intensity = 4.0f;
  l.attenuation = {0, 0, 1};
  scene.lights.push_back(l);
  Shaded out = renderGl(*glContext_, scene, gltest::rasterOnly(kW, kH));
  ASSERT_EQ(out.ids.size(), std::size_t(kW * kH));
  int compared = 0, mismatched = 0;
  double worst = 0.0, spread = 0.0;
  glm::vec3 first(-1.0f);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      glm::uvec2 id = out.ids[std::size_t(y) * kW + x];
      if (id.x == 0) continue;
      glm::vec3 want = cpuLocal(scene, id, x, y), got = out.gl.at(x, y);
      if (first.x < 0.0f) first = want;
      spread = std::max(spread, double(glm::length(want - first)));
      float err = glm::length(got - want);
      worst = std::max(worst, double(err));
      // 8-bit texels filtered in GL's fixed point vs the CPU's float: a few 1e-3 of the normal.
      if (err > 5e-3f + 1e-2f * glm::length(want)) ++mismatched;
      ++compared;
    }
  EXPECT_GT(compared, kW * kH / 4);
  EXPECT_EQ(mismatched, 0) << "worst " << worst;
  EXPECT_GT(spread, 0.1) << "the normal map should vary the shading across the quad";
}

TEST(GltfMaterialsGLTest, EmissiveTextureMultipliesEmission) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = baseScene();
  scene.meshes.push_back(quadMesh(1.0f));
  // Left half black, right half sRGB (255, 128, 0): emission (2, 2, 2) × decoded texel.
  scene.textures.push_back(solidTexture(2, 1, true, [](int x, int) {
    return x == 0 ? glm::u8vec4(0, 0, 0, 255) : glm::u8vec4(255, 128, 0, 255);
  }));
  Material m = gltest::plainMaterial(glm::vec3(0.0f));
  m.ka = glm::vec3(0.0f);
  m.emission = glm::vec3(2.0f);
  m.emissiveTexture = 0;
  scene.materials.push_back(m);
  scene.instances.push_back({"quad", 0, 0, glm::mat4(1.0f), false});
  Shaded out = renderGl(*glContext_, scene, gltest::rasterOnly(kW, kH));
  ASSERT_EQ(out.ids.size(), std::size_t(kW * kH));
  const float g = shading::tdSrgbDecode1(128.0f / 255.0f);
  // Texel centres: u = 0.25 black, u = 0.75 orange; the quad spans about x ∈ [24, 136] at this fov.
  const int y = kH / 2;
  for (int x : {kW / 2 - 25, kW / 2 + 25}) {
    glm::uvec2 id = out.ids[std::size_t(y) * kW + x];
    ASSERT_NE(id.x, 0u);
    glm::vec3 got = out.gl.at(x, y), want = cpuLocal(scene, id, x, y);
    EXPECT_LT(glm::length(got - want), 1e-2f) << x;
  }
  EXPECT_LT(glm::length(out.gl.at(kW / 2 - 25, y)), 0.3f);  // mostly black, some bilinear bleed
  // Bilinear with repeat blends the orange texel with black ones, so the colour's ratio is what is exact:
  // green / red = the sRGB-decoded 128 (decoded before filtering), blue 0.
  glm::vec3 right = out.gl.at(kW / 2 + 25, y);
  EXPECT_GT(right.x, 1.0f);
  EXPECT_NEAR(right.y / right.x, g, 5e-3f);
  EXPECT_NEAR(right.z, 0.0f, 1e-4f);
}

TEST(GltfMaterialsGLTest, MaskCutsHolesInTheVisibilityPass) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = baseScene();
  scene.meshes.push_back(quadMesh(1.0f, 0.5f));   // front, masked
  scene.meshes.push_back(quadMesh(1.5f, -0.5f));  // back, opaque
  // Alpha 0 on the left half, 255 on the right (nearest would be exact; bilinear crosses 0.5 mid-quad).
  scene.textures.push_back(solidTexture(4, 1, true, [](int x, int) {
    return glm::u8vec4(255, 255, 255, x < 2 ? 0 : 255);
  }));
  Material front = gltest::plainMaterial(glm::vec3(0.0f));
  front.ka = glm::vec3(0.0f);
  front.emission = glm::vec3(1, 0, 0);
  front.kdTexture = 0;
  front.alphaMode = AlphaMode::Mask;
  front.alphaCutoff = 0.5f;
  Material back = front;
  back.alphaMode = AlphaMode::Opaque;
  back.kdTexture = -1;
  back.emission = glm::vec3(0, 0, 1);
  scene.materials = {front, back};
  scene.instances.push_back({"front", 0, 0, glm::mat4(1.0f), false});
  scene.instances.push_back({"back", 1, 1, glm::mat4(1.0f), false});
  Shaded out = renderGl(*glContext_, scene, gltest::rasterOnly(kW, kH));
  ASSERT_EQ(out.ids.size(), std::size_t(kW * kH));
  const int y = kH / 2;
  EXPECT_EQ(out.ids[std::size_t(y) * kW + kW / 2 - 25].x, 2u);  // hole: the back quad
  EXPECT_EQ(out.ids[std::size_t(y) * kW + kW / 2 + 25].x, 1u);  // covered: the front quad
  EXPECT_NEAR(out.gl.at(kW / 2 - 25, y).z, 1.0f, 1e-3f);
  EXPECT_NEAR(out.gl.at(kW / 2 + 25, y).x, 1.0f, 1e-3f);
  // Without MASK the same texture covers everything.
  scene.materials[0].alphaMode = AlphaMode::Opaque;
  Shaded opaque = renderGl(*glContext_, scene, gltest::rasterOnly(kW, kH));
  EXPECT_EQ(opaque.ids[std::size_t(y) * kW + kW / 2 - 25].x, 1u);
}

TEST(GltfMaterialsGLTest, BlendCoverageIsThinTransmission) {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = baseScene();
  scene.background = glm::vec3(0.2f, 0.4f, 0.8f);
  scene.meshes.push_back(quadMesh(1.0f));
  Material m = gltest::plainMaterial(glm::vec3(0.0f));
  m.ka = glm::vec3(0.0f);
  m.emission = glm::vec3(1.0f, 0.5f, 0.0f);
  m.alphaMode = AlphaMode::Blend;
  m.opacity = 0.25f;
  m.ior = 1.0f;
  // A glass object elsewhere: the Renderer makes the refraction probes only for scenes with kt > 0.
  Material glass = gltest::plainMaterial(glm::vec3(0.0f));
  glass.kt = 1.0f;
  glass.ior = 1.0f;
  scene.materials = {m, glass};
  scene.meshes.push_back(quadMesh(0.1f));
  scene.instances.push_back({"blend", 0, 0, glm::mat4(1.0f), false});
  scene.instances.push_back({"glass", 1, 1, glm::translate(glm::mat4(1.0f), glm::vec3(5, 5, 0)), false});
  FrameSettings s = gltest::rasterOnly(kW, kH);
  s.refraction = EffectMode::Raster;
  s.maxDepth = 1;
  Shaded out = renderGl(*glContext_, scene, s);
  ASSERT_EQ(out.ids.size(), std::size_t(kW * kH));
  const int x = kW / 2, y = kH / 2;
  glm::uvec2 id = out.ids[std::size_t(y) * kW + x];
  ASSERT_EQ(id.x, 1u);
  // a·local + (1 − a)·(what is behind: the background, seen through the probe in RGBA16F).
  glm::vec3 want = 0.25f * m.emission + 0.75f * scene.background;
  glm::vec3 got = out.gl.at(x, y);
  EXPECT_LT(glm::length(got - want), 5e-3f) << got.x << " " << got.y << " " << got.z;
  // The CPU twin's local term carries the same coverage.
  glm::vec3 cpu = cpuLocal(scene, id, x, y);
  EXPECT_LT(glm::length(cpu - 0.25f * m.emission), 1e-5f);
  // Transmission tint filters the material's own transmitted light, not the uncovered part.
  EXPECT_EQ(shading::tdTransmitWeight(1.0f, 0.5f, glm::vec3(1, 0, 0)), glm::vec3(0.5f, 0, 0));
  EXPECT_EQ(shading::tdTransmitWeight(0.25f, 0.0f, glm::vec3(1, 0, 0)), glm::vec3(0.75f));
}

// A single-sided quad (Material::doubleSided false) at height 1 over a floor, a point light above it, seen from
// above and to the side. Turned down, both its faces' backs are what the camera and the light meet: the
// camera sees the floor through it and the floor under it is lit as if it were not there. Turned up, it hides
// the floor's centre and shades the floor beside its foot. The raster (the views and the light's shadow maps
// culled) and the rays (hybrid-full: Embree's filter) the same; a double-sided quad turned down is seen and
// casts its shadow, as every face did before glTF's sidedness was honoured.
TEST(GltfMaterialsGLTest, SingleSidedFacesAreCulledInViewsAndLightMapsAsRaysPassThem) {
  TD_REQUIRE_GL_CONTEXT();
  enum class Quad { None, Down, Up, DownDoubleSided };
  auto sceneWith = [](Quad kind) {
    Scene s;
    s.meshes.push_back(makePlane({10.0f, 10.0f}, 1));
    s.meshes.push_back(makePlane({2.0f, 2.0f}, 1));  // counter-clockwise seen from +Y
    s.materials.push_back(gltest::plainMaterial(glm::vec3(0.8f)));
    Material quad = gltest::plainMaterial(glm::vec3(0.9f, 0.1f, 0.1f));
    quad.doubleSided = kind == Quad::DownDoubleSided;
    s.materials.push_back(quad);
    s.instances.push_back({"floor", 0, 0, glm::mat4(1.0f), false});
    glm::mat4 at = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    if (kind != Quad::Up) at = glm::rotate(at, glm::pi<float>(), glm::vec3(1.0f, 0.0f, 0.0f));  // its front down
    if (kind != Quad::None) s.instances.push_back({"quad", 1, 1, at, false});
    Light point;
    point.type = LightType::Point;
    point.posW = {0.0f, 3.0f, 0.0f};
    point.intensity = 4.0f;
    s.lights.push_back(point);
    s.camera.posW = {0.0f, 5.0f, 3.0f};
    s.camera.targetW = {0.0f, 0.0f, 0.0f};
    s.camera.yFovDeg = 50.0f;
    return s;
  };
  auto pixelOf = [](const Camera& c, glm::vec3 pW) {
    const glm::vec4 clip = c.clipFromView(float(kW) / float(kH)) * c.viewFromWorld() * glm::vec4(pW, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::ivec2(int((ndc.x * 0.5f + 0.5f) * kW), int((0.5f - ndc.y * 0.5f) * kH));
  };
  const Scene bare = sceneWith(Quad::None);
  // The floor's centre, under the quad, and a floor point the camera sees past the quad's edge but the light
  // reaches only across the quad (its ray crosses height 1 at z = 0.87).
  const glm::ivec2 centre = pixelOf(bare.camera, glm::vec3(0.0f)), shaded = pixelOf(bare.camera, {0.0f, 0.0f, 1.3f});
  for (const char* preset : {"raster", "hybrid-full"}) {
    SCOPED_TRACE(preset);
    FrameSettings s = *presetSettings(preset);
    s.width = kW;
    s.height = kH;
    s.toneMap = ToneMap::None;
    auto frame = [&](Quad kind) {
      gltest::SceneFrame f = gltest::sceneFrame(*glContext_, sceneWith(kind), kW, kH);
      gltest::drawFrame(f, s);
      return f.renderer->readLinear();
    };
    const ImageF none = frame(Quad::None), down = frame(Quad::Down), up = frame(Quad::Up),
                 twoSided = frame(Quad::DownDoubleSided);
    const glm::vec3 floorLit = none.at(centre.x, centre.y), besideLit = none.at(shaded.x, shaded.y);
    ASSERT_GT(besideLit.g, 0.2f);
    EXPECT_LT(glm::length(down.at(centre.x, centre.y) - floorLit), 0.01f) << "turned down: the floor through it";
    EXPECT_LT(glm::length(down.at(shaded.x, shaded.y) - besideLit), 0.01f) << "turned down: no shadow";
    EXPECT_GT(up.at(centre.x, centre.y).r, 3.0f * up.at(centre.x, centre.y).g) << "turned up: the quad is seen";
    EXPECT_LT(up.at(shaded.x, shaded.y).g, 0.3f * besideLit.g) << "turned up: its shadow";
    EXPECT_GT(twoSided.at(centre.x, centre.y).r, 3.0f * twoSided.at(centre.x, centre.y).g) << "double-sided: seen";
    EXPECT_LT(twoSided.at(shaded.x, shaded.y).g, 0.3f * besideLit.g) << "double-sided: its shadow";
  }
}

}  // namespace
}  // namespace tandem
