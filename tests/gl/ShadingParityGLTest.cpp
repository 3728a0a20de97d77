// GLSL / C++ parity: the GL shade pass and the CPU twin (rt::resolveHit + rt::shadeLocal, the code the ray
// pass shades secondary hits with) give the same linear radiance for the same visible triangles, for every
// shading model, light type, checker, texture and vertex colour; and shading.glsl's secondary directions
// (the ray pass's rays, the raster probes' lookups) evaluated by GLSL match their C++ twin.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "GlTestUtil.h"
#include "core/RenderSpace.h"
#include "core/Shading.h"
#include "gl/GlObjects.h"
#include "gl/GpuScene.h"
#include "gl/Program.h"
#include "gl/VisibilityPass.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"

namespace tandem {
namespace {

Scene parityScene() {
  Scene s;
  s.name = "parity";
  Mesh box = makeBox(glm::vec3(1.0f));
  for (std::size_t i = 0; i < box.positions.size(); ++i)
    box.colors.push_back(glm::vec4(0.5f + 0.5f * glm::abs(box.normals[i]), 1.0f));
  s.meshes = {makePlane(glm::vec2(8.0f), 8), box, makeSphere(0.7f, 48, 24)};
  // A small texture, magnified: GL samples level 0 bilinearly, as the CPU does.
  Texture tex;
  tex.width = tex.height = 4;
  for (int i = 0; i < 16; ++i) {
    std::uint8_t v = static_cast<std::uint8_t>(40 + 13 * i);
    tex.rgba8.insert(tex.rgba8.end(), {v, static_cast<std::uint8_t>(255 - v), 128, 255});
  }
  s.textures = {tex};
  Material floor;
  floor.kd = {0.8f, 0.7f, 0.6f};
  floor.kd2 = {0.1f, 0.2f, 0.3f};
  floor.checkerFrequency = 1.0f;
  floor.ks = glm::vec3(0.2f);
  floor.ns = 8.0f;
  floor.ka = glm::vec3(0.3f);
  Material textured;
  textured.kd = glm::vec3(1.0f);
  textured.kdTexture = 0;
  textured.ks = glm::vec3(0.3f);
  textured.ns = 16.0f;
  Material shiny;
  shiny.kd = {0.6f, 0.2f, 0.2f};
  shiny.ks = glm::vec3(0.6f);
  shiny.ns = 40.0f;
  shiny.emission = {0.02f, 0.0f, 0.0f};
  s.materials = {floor, textured, shiny};
  Instance plane, cube, ball;
  cube.mesh = 1;
  cube.material = 1;
  cube.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(-0.9f, 0.5f, 0.0f)) *
                         glm::rotate(glm::mat4(1.0f), 0.6f, glm::vec3(0, 1, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.3f, 0.8f));
  ball.mesh = 2;
  ball.material = 2;
  ball.worldFromObject = glm::translate(glm::mat4(1.0f), glm::vec3(0.9f, 0.7f, 0.3f));
  s.instances = {plane, cube, ball};
  Light ambient;
  ambient.type = LightType::Ambient;
  ambient.color = {0.2f, 0.25f, 0.3f};
  Light point;
  point.posW = {2.0f, 3.0f, 2.0f};
  point.attenuation = {1.0f, 0.1f, 0.02f};
  point.intensity = 2.0f;
  Light spot;
  spot.type = LightType::Spot;
  spot.posW = {-2.0f, 4.0f, 1.0f};
  spot.dirW = glm::normalize(glm::vec3(0.5f, -1.0f, -0.2f));
  spot.color = {0.4f, 0.6f, 1.0f};
  spot.innerConeDeg = 15.0f;
  spot.outerConeDeg = 35.0f;
  Light sun;
  sun.type = LightType::Directional;
  sun.dirW = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.5f));
  sun.intensity = 0.4f;
  s.lights = {ambient, point, spot, sun};
  s.camera.posW = {0.3f, 2.5f, 4.5f};
  s.camera.targetW = {0.0f, 0.4f, 0.0f};
  s.background = {0.05f, 0.05f, 0.1f};
  return s;
}

// `environment`: the scene's (docs/environment.md), which the background pixels show and the ambient term
// takes the light of; `name` tells the saved images apart.
void checkParity(ShadingModel model, const Environment& environment = {}, const std::string& name = "") {
  TD_REQUIRE_GL_CONTEXT();
  Scene scene = parityScene();
  scene.environment = environment;
  const int w = 192, h = 108;
  auto renderer = gltest::makeRenderer(*glContext_);
  ASSERT_TRUE(renderer);
  ASSERT_TRUE(renderer->setScene(scene).ok());
  FrameSettings settings = gltest::rasterOnly(w, h);
  settings.shadingOverride = model;
  renderer->render(scene.camera, settings);
  ImageF gl = renderer->readLinear();
  gltest::savePng("parity-" + std::string(toString(model)) + name + ".png", renderer->readImage());

  // The same visible triangles the renderer shaded.
  gl::GpuScene gpu;
  gpu.upload(scene, model);
  auto pass = gl::VisibilityPass::create();
  ASSERT_TRUE(pass.ok());
  EXPECT_TRUE(pass->resize(w, h).ok());
  pass->render(gpu, toRenderSpace(scene.camera, gpu.anchor()));  // the GL copy is in render space
  std::vector<glm::uvec2> ids;
  pass->readIds(ids);

  rt::FrameShading frame(scene, model);
  std::vector<rt::InstanceTransform> transforms;
  for (const Instance& inst : scene.instances) transforms.push_back(rt::makeInstanceTransform(inst.worldFromObject));
  int compared = 0, mismatched = 0, outlined = 0, onChecker = 0;
  double worst = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::uvec2 id = ids[static_cast<std::size_t>(y) * w + x];
      glm::vec3 got = gl.at(x, y);
      const Ray ray = scene.camera.rayThroughPixel({float(x) + 0.5f, float(y) + 0.5f}, {w, h});
      glm::vec3 want = frame.environment.radiance(ray.dir);
      // What GL may do differently from the CPU and still be right (the GL spec leaves it to the
      // implementation): filter textures with fixed-point weights (8 bits on NVIDIA: 1/512 of a texel's
      // contrast, which this texture's sRGB steps make up to ~0.35 in linear), and contract a·b + c into
      // fused multiply-adds. The latter moves a uv by an ulp, which only matters where the shading is
      // discontinuous in uv: on a checker square's edge either colour is the exact answer for some
      // rounding. Such pixels are counted, not compared, and must stay rare.
      float tolerance = 2e-3f;
      // An environment image, filtered by those weights: this test's image steps by at most 0.1 a texel.
      if (id.x == 0 && scene.environment.kind == Environment::Kind::Map) tolerance += 0.1f / 256.0f;
      if (id.x != 0) {
        rt::SurfaceHit hit = rt::resolveHit(scene, transforms[id.x - 1], id.x - 1, id.y, ray);
        want = rt::shadeLocal(scene, frame, transforms[id.x - 1], hit, ~0u);
        const Material& mat = scene.materials[hit.material];
        if (mat.checkerFrequency > 0.0f) {
          const glm::vec2 c = hit.uv * mat.checkerFrequency;
          const glm::vec2 edge = glm::abs(c - glm::round(c));
          if (std::min(edge.x, edge.y) < 1e-5f * std::max(1.0f, std::max(std::abs(c.x), std::abs(c.y)))) {
            ++onChecker;
            ++compared;
            continue;
          }
        }
        if (mat.kdTexture >= 0) tolerance += 1.0f / 512.0f;
      }
      if (model == ShadingModel::Toon && id.x != 0 && got == glm::vec3(0.0f) && want != glm::vec3(0.0f)) {
        ++outlined;  // silhouette outline: a GL-only screen-space step (docs/shading.md)
        continue;
      }
      float err = glm::length(got - want);
      worst = std::max(worst, double(err));
      if (err > tolerance + 2e-3f * glm::length(want)) {
        ++mismatched;
        if (model != ShadingModel::Toon && mismatched < 10)
          ADD_FAILURE() << toString(model) << " pixel " << x << "," << y << " id " << id.x << "/" << id.y << " GL ("
                        << got.x << ", " << got.y << ", " << got.z << ") CPU (" << want.x << ", " << want.y << ", "
                        << want.z << ")";
      }
      ++compared;
    }
  EXPECT_EQ(compared + outlined, w * h);
  EXPECT_LT(onChecker, compared / 200) << "pixels on a checker edge are the exception, not the frame";
  if (model == ShadingModel::Toon) {
    // Hard bands: a pixel whose N·L sits on a ramp step may land on either side in float.
    EXPECT_LT(mismatched, compared / 200) << "worst " << worst;
    EXPECT_GT(outlined, 50);
    EXPECT_LT(outlined, w * h / 8);
  } else {
    EXPECT_EQ(mismatched, 0) << "worst " << worst;
  }
}

TEST(ShadingParityGLTest, Flat) { checkParity(ShadingModel::Flat); }
TEST(ShadingParityGLTest, Gouraud) { checkParity(ShadingModel::Gouraud); }
TEST(ShadingParityGLTest, Phong) { checkParity(ShadingModel::Phong); }
TEST(ShadingParityGLTest, Toon) { checkParity(ShadingModel::Toon); }

// The environment (shading.glsl's tdSkyRadiance, tdEquirectUv, tdShAmbient; EnvironmentLookup on the CPU): the
// background pixels are the environment along their camera rays, and every surface's ambient term takes its
// light, by the GLSL as by the C++ (turned, scaled, the sky and an image).
TEST(ShadingParityGLTest, TheSkyInTheBackgroundAndTheAmbientTerm) {
  Environment sky;
  sky.kind = Environment::Kind::Sky;
  sky.intensity = 1.5f;
  sky.rotationDeg = 30.0f;
  checkParity(ShadingModel::Phong, sky, "-sky");
  checkParity(ShadingModel::Gouraud, sky, "-sky");
  checkParity(ShadingModel::Flat, sky, "-sky");  // (the ambient term at the face's own normal)
}

TEST(ShadingParityGLTest, AnEnvironmentImageInTheBackgroundAndTheAmbientTerm) {
  // 32x16 texels, smooth but different in every direction: colour by longitude, brightness by latitude.
  const int w = 32, h = 16;
  std::vector<glm::vec3> texels;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float u = (float(x) + 0.5f) / float(w), v = (float(y) + 0.5f) / float(h);
      texels.emplace_back(0.6f + 0.4f * std::sin(6.2831853f * u), 0.6f + 0.4f * std::cos(6.2831853f * u), 1.2f - v);
    }
  Environment map;
  map.kind = Environment::Kind::Map;
  map.map = std::make_shared<EnvironmentMap>(w, h, std::move(texels));
  map.intensity = 0.8f;
  map.rotationDeg = -70.0f;
  checkParity(ShadingModel::Phong, map, "-map");
}


// tdReflectOverFacet and tdRefractOverFacet (docs/numerics.md, "Directions over the facet") run by GLSL in
// a compute shader over shading normals tilted up to 0.6 rad from the facet, views from grazing to head-on
// and both directions of an IOR 1.5 interface, against the C++ twin: the same directions (to float
// rounding, llvmpipe may contract into FMAs), and the GLSL ones on their side of the facet too.
TEST(ShadingParityGLTest, DirectionsOverTheFacetMatchTheCppTwin) {
  TD_REQUIRE_GL_CONTEXT();
  struct Case {
    glm::vec4 v, n, ng, tEta;  // tEta: the Snell direction about N, and eta = etaI / etaT
  };
  std::vector<Case> cases;
  const glm::vec3 ng = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  const glm::vec3 u = glm::normalize(glm::cross(ng, glm::vec3(0.0f, 0.0f, 1.0f))), w = glm::cross(ng, u);
  auto around = [&](float elevation, float azimuth) {
    return std::cos(elevation) * (std::cos(azimuth) * u + std::sin(azimuth) * w) + std::sin(elevation) * ng;
  };
  int bentR = 0, bentT = 0;
  for (float eta : {1.0f / 1.5f, 1.5f})
    for (float tilt : {0.0f, 0.02f, 0.2f, 0.6f})
      for (float tiltAzimuth : {0.0f, 1.3f, 2.9f, 4.4f})
        for (float elevation : {1e-3f, 0.02f, 0.1f, 0.4f, 1.2f})
          for (float viewAzimuth : {0.0f, 0.7f, 2.0f, 3.1f, 4.5f}) {
            glm::vec3 v = around(elevation, viewAzimuth), n = tilt == 0.0f ? ng : around(1.5707964f - tilt, tiltAzimuth);
            rt::Refraction r = rt::refractDielectric(v, n, eta, 1.0f, FresnelMode::Exact);
            glm::vec3 t = r.totalInternal ? -v : r.dirW;
            bentR += glm::dot(glm::dot(n, v) > 0.0f ? glm::reflect(-v, n) : -v, ng) < 0.01f;
            bentT += glm::dot(t, ng) > -0.01f;
            cases.push_back({glm::vec4(v, 0.0f), glm::vec4(n, 0.0f), glm::vec4(ng, 0.0f), glm::vec4(t, eta)});
          }
  ASSERT_GT(bentR, 50);
  ASSERT_GT(bentT, 20);

  std::vector<std::string> files;
  auto shading = gl::expandShaderSource("shaders/shading.glsl", {}, files);
  ASSERT_TRUE(shading.ok()) << shading.error().message;
  const std::string source = "#version 450 core\n#define TD_OUT(T) out T\n" + *shading + R"(
layout(local_size_x = 64) in;
struct Case { vec4 v, n, ng, tEta; };
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };  // reflected, refracted
uniform uint count;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  Case c = cases[i];
  results[2u * i] = vec4(tdReflectOverFacet(c.v.xyz, c.n.xyz, c.ng.xyz), 0.0);
  results[2u * i + 1u] = vec4(tdRefractOverFacet(c.tEta.xyz, c.v.xyz, c.ng.xyz, c.tEta.w), 0.0);
}
)";
  gl::Shader shader = gl::createShader("facet-directions", GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  glShaderSource(shader.id(), 1, &text, nullptr);
  glCompileShader(shader.id());
  GLint ok = 0;
  glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::string log(4096, '\0');
    glGetShaderInfoLog(shader.id(), static_cast<GLsizei>(log.size()), nullptr, log.data());
    FAIL() << "compiling the facet-direction kernel: " << log.c_str();
  }
  gl::Program program = gl::createProgram("facet-directions");
  glAttachShader(program.id(), shader.id());
  glLinkProgram(program.id());
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  ASSERT_TRUE(ok);
  const auto count = static_cast<GLuint>(cases.size());
  gl::Buffer in = gl::createBuffer("facet-cases", cases.size() * sizeof(Case), cases.data());
  gl::Buffer out = gl::createBuffer("facet-results", cases.size() * 2 * sizeof(glm::vec4), nullptr);
  glUseProgram(program.id());
  glUniform1ui(glGetUniformLocation(program.id(), "count"), count);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
  glDispatchCompute((count + 63u) / 64u, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<glm::vec4> results(cases.size() * 2);
  glGetNamedBufferSubData(out.id(), 0, static_cast<GLsizeiptr>(results.size() * sizeof(glm::vec4)), results.data());
  glUseProgram(0);

  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const glm::vec3 v(c.v), n(c.n), g(c.ng), t(c.tEta);
    const glm::vec3 wantR = shading::tdReflectOverFacet(v, n, g), wantT = shading::tdRefractOverFacet(t, v, g, c.tEta.w);
    const glm::vec3 gotR(results[2 * i]), gotT(results[2 * i + 1]);
    ASSERT_LT(glm::length(gotR - wantR), 1e-5f) << "reflected, case " << i;
    ASSERT_LT(glm::length(gotT - wantT), 1e-5f) << "refracted, case " << i;
    ASSERT_GT(glm::dot(gotR, g), 0.0f) << "GLSL reflected into the facet, case " << i;
    ASSERT_LT(glm::dot(gotT, g), 0.0f) << "GLSL refracted back out of the facet, case " << i;
  }
}

}  // namespace
}  // namespace tandem
