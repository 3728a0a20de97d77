#include "rt/RtTestScenes.h"

#include "core/Shading.h"

namespace tandem::rt::test {

Scene makeWhittedScene() {
  Scene s;
  s.name = "whitted-mini";
  s.background = {0.1f, 0.2f, 0.45f};
  s.camera.posW = {0.0f, 2.2f, 7.0f};
  s.camera.targetW = {0.0f, 0.8f, 0.0f};
  s.camera.yFovDeg = 45.0f;

  Material floor = diffuse({0.9f, 0.1f, 0.1f});
  floor.kd2 = {0.9f, 0.9f, 0.1f};
  floor.checkerFrequency = 1.0f;
  floor.ks = glm::vec3(0.2f);
  floor.kr = 0.15f;
  Material mirror = diffuse(glm::vec3(0.05f));
  mirror.ks = glm::vec3(0.8f);
  mirror.ns = 64.0f;
  mirror.kr = 0.85f;
  Material glass = diffuse(glm::vec3(0.0f));
  glass.ka = glm::vec3(0.0f);
  glass.ks = glm::vec3(0.9f);
  glass.ns = 128.0f;
  glass.kt = 0.9f;
  glass.ior = 1.5f;
  Material gouraud = diffuse({0.2f, 0.5f, 0.9f});
  gouraud.shading = ShadingModel::Gouraud;
  gouraud.ks = glm::vec3(0.4f);
  Material toon = diffuse({0.3f, 0.8f, 0.3f});
  toon.shading = ShadingModel::Toon;
  toon.ks = glm::vec3(0.5f);
  Material textured = diffuse(glm::vec3(1.0f));
  textured.kdTexture = 0;

  Texture tex;
  tex.width = tex.height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      auto v = static_cast<std::uint8_t>(((x + y) % 2) ? 230 : 40);
      tex.rgba8.insert(tex.rgba8.end(), {v, static_cast<std::uint8_t>(255 - v), 128, 255});
    }
  s.textures.push_back(tex);

  std::uint32_t plane = addMesh(s, makePlane({16.0f, 16.0f}, 4));
  std::uint32_t sphere = addMesh(s, makeSphere(1.0f, 48, 24));
  std::uint32_t box = addMesh(s, makeBox({1.0f, 1.0f, 1.0f}));
  Mesh quad = makePlane({1.5f, 1.5f}, 1);
  for (glm::vec2& uv : quad.uvs) uv /= 1.5f;
  quad.colors.assign(quad.positions.size(), glm::vec4(1.0f, 0.9f, 0.8f, 1.0f));
  std::uint32_t quadMesh = addMesh(s, quad);

  addInstance(s, plane, addMaterial(s, floor), glm::mat4(1.0f));
  addInstance(s, sphere, addMaterial(s, mirror), translate({-1.4f, 1.0f, -0.5f}));
  addInstance(s, sphere, addMaterial(s, glass), translate({1.2f, 1.0f, 1.0f}) * glm::scale(glm::mat4(1.0f), glm::vec3(0.8f)));
  addInstance(s, box, addMaterial(s, gouraud),
              translate({0.6f, 0.5f, -2.0f}) * glm::rotate(glm::mat4(1.0f), 0.6f, glm::vec3(0, 1, 0)));
  addInstance(s, sphere, addMaterial(s, toon), translate({2.8f, 0.6f, -1.2f}) * glm::scale(glm::mat4(1.0f), glm::vec3(0.6f)));
  addInstance(s, quadMesh, addMaterial(s, textured),
              translate({-2.8f, 1.2f, -2.5f}) * glm::rotate(glm::mat4(1.0f), 1.2f, glm::vec3(1, 0, 0)));

  s.lights.push_back(ambientLight(0.3f));
  s.lights.push_back(pointLight({3.0f, 6.0f, 4.0f}, 1.0f));
  s.lights.push_back(directional({-0.4f, -1.0f, -0.3f}, 0.5f));
  return s;
}

void writeDebugPng(const ImageF& image, const std::string& name) {
  Image out;
  out.width = image.width;
  out.height = image.height;
  out.rgba.resize(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    glm::vec3 c = shading::tdSrgbEncode(shading::tdToneMap(image.rgb[i], TD_TONEMAP_REINHARD));
    for (int k = 0; k < 3; ++k) out.rgba[4 * i + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(glm::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    out.rgba[4 * i + 3] = 255;
  }
  auto r = writePng(tandem::test::outputDir() + "/" + name, out);
  EXPECT_TRUE(r.ok());
}

}  // namespace tandem::rt::test
