#include "tandem/Scene.h"

#include <cmath>
#include <string>

#include "tandem/Result.h"

#include "core/Finite.h"

namespace tandem {

glm::vec3 Scene::ambientIntensity() const {
  glm::vec3 ia(0.0f);
  for (const Light& l : lights)
    if (l.type == LightType::Ambient) ia += l.color * l.intensity;
  return ia;
}

std::vector<const Light*> Scene::directLights() const {
  std::vector<const Light*> out;
  for (const Light& l : lights)
    if (l.type != LightType::Ambient) out.push_back(&l);
  return out;
}

std::size_t Scene::triangleCount() const {
  std::size_t n = 0;
  for (const Instance& i : instances)
    if (i.mesh < meshes.size()) n += meshes[i.mesh].triangleCount();
  return n;
}


Result<void> validateLight(const Light& l, const std::string& id) {
  if (!allFinite(l.color) || !std::isfinite(l.intensity) || !allFinite(l.posW) || !allFinite(l.dirW) ||
      !std::isfinite(l.range) || !allFinite(l.attenuation) || !allFinite(l.upW) || !std::isfinite(l.size.x) ||
      !std::isfinite(l.size.y) || !std::isfinite(l.radius))
    return Error{id + ": a value is NaN or infinite"};
  if (isAreaLight(l.type) && (l.size.x < 0.0f || l.size.y < 0.0f || l.radius < 0.0f))
    return Error{id + ": negative size or radius"};
  if (l.intensity < 0.0f || l.color.x < 0.0f || l.color.y < 0.0f || l.color.z < 0.0f)
    return Error{id + ": negative colour or intensity"};
  if ((l.type == LightType::Spot || l.type == LightType::Directional || l.type == LightType::Rect ||
       l.type == LightType::Disk) &&
      glm::dot(l.dirW, l.dirW) < 1e-12f)
    return Error{id + ": zero direction"};
  return {};
}

Result<void> validateScene(const Scene& scene) {
  const std::string where = scene.name.empty() ? std::string("scene") : "scene '" + scene.name + "'";
  int direct = 0;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    std::string id = where + ": light " + std::to_string(i) + (l.name.empty() ? "" : " '" + l.name + "'");
    if (auto checked = validateLight(l, id); !checked) return checked;
    if (l.type != LightType::Ambient) ++direct;
  }
  if (direct > kMaxLights)
    return Error{where + ": " + std::to_string(direct) + " lights, more than the limit of " +
                 std::to_string(kMaxLights) + " (ambient lights do not count)"};
  {
    const Environment& e = scene.environment;
    if (!allFinite(scene.background) || !allFinite(e.zenith) || !allFinite(e.horizon) || !allFinite(e.ground) ||
        !std::isfinite(e.intensity) || !std::isfinite(e.rotationDeg))
      return Error{where + ": environment: a value is NaN or infinite"};
    auto negative = [](glm::vec3 c) { return c.x < 0.0f || c.y < 0.0f || c.z < 0.0f; };
    if (negative(scene.background) || negative(e.zenith) || negative(e.horizon) || negative(e.ground) ||
        e.intensity < 0.0f)
      return Error{where + ": environment: a negative colour or intensity"};
    if (e.intensity > 1e6f) return Error{where + ": environment: an intensity over 1e6"};
    if (e.kind == Environment::Kind::Map && !e.map) return Error{where + ": environment: a map without an image"};
  }
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    std::string id = where + ": mesh " + std::to_string(m) + (mesh.name.empty() ? "" : " '" + mesh.name + "'");
    if (mesh.indices.size() % 3 != 0) return Error{id + ": index count is not a multiple of 3"};
    for (std::uint32_t idx : mesh.indices)
      if (idx >= mesh.positions.size()) return Error{id + ": index " + std::to_string(idx) + " out of range"};
    for (const glm::vec3& p : mesh.positions)
      if (!allFinite(p)) return Error{id + ": a position is NaN or infinite"};
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
      return Error{id + ": normal count differs from position count"};
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
      return Error{id + ": uv count differs from position count"};
  }
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& mat = scene.materials[m];
    std::string id = where + ": material " + std::to_string(m) + (mat.name.empty() ? "" : " '" + mat.name + "'");
    if (!allFinite(mat.ka) || !allFinite(mat.kd) || !allFinite(mat.ks) || !std::isfinite(mat.ns) || !std::isfinite(mat.kr) ||
        !std::isfinite(mat.kt) || !std::isfinite(mat.ior) || !allFinite(mat.emission) || !std::isfinite(mat.roughness))
      return Error{id + ": a value is NaN or infinite"};
    if (mat.ior <= 0.0f) return Error{id + ": ior must be > 0"};
    if (mat.roughness < 0.0f || mat.roughness > 1.0f) return Error{id + ": roughness must be in [0, 1]"};
    if (mat.ns < 0.0f) return Error{id + ": ns must be >= 0"};
    if (const ProceduralTexture& t = mat.procedural; t.type != Pattern::None) {
      if (static_cast<int>(t.type) > static_cast<int>(Pattern::Granite)) return Error{id + ": unknown procedural pattern"};
      if (!allFinite(mat.kd2) || !(t.scale > 0.0f) || !std::isfinite(t.scale) || !(t.turbulence >= 0.0f) ||
          !std::isfinite(t.turbulence) || !(t.bump >= 0.0f) || !std::isfinite(t.bump))
        return Error{id + ": procedural texture: scale must be finite and > 0, turbulence and bump finite and >= 0"};
      if (t.octaves < 1 || t.octaves > 8) return Error{id + ": procedural texture: octaves must be in 1..8"};
      if (mat.checkerFrequency > 0.0f) return Error{id + ": a checker and a procedural texture together"};
    }
    if (mat.kdTexture >= int(scene.textures.size()) || mat.normalTexture >= int(scene.textures.size()) ||
        mat.emissiveTexture >= int(scene.textures.size()))
      return Error{id + ": texture index out of range"};
  }
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    std::string id = where + ": instance " + std::to_string(i) + (inst.name.empty() ? "" : " '" + inst.name + "'");
    if (inst.mesh >= scene.meshes.size()) return Error{id + ": mesh index out of range"};
    if (inst.material >= scene.materials.size()) return Error{id + ": material index out of range"};
    if (!allFinite(inst.worldFromObject)) return Error{id + ": transform is NaN or infinite"};
    if (!allFinite(inst.velocity) || !allFinite(inst.angularVelocity)) return Error{id + ": motion is NaN or infinite"};
  }
  const Camera& c = scene.camera;
  if (!allFinite(c.posW) || !allFinite(c.targetW) || !allFinite(c.upW) || !(c.nearZ > 0.0f) || !(c.farZ > c.nearZ) ||
      !(c.yFovDeg > 0.0f && c.yFovDeg < 180.0f) || glm::length(c.targetW - c.posW) <= 0.0f)
    return Error{where + ": camera is invalid (needs finite position, target != position, 0 < near < far, 0 < fov < 180)"};
  if (!std::isfinite(c.aperture) || c.aperture < 0.0f || std::isnan(c.focusDistance) || std::isinf(c.focusDistance))
    return Error{where + ": camera lens is invalid (needs a finite aperture >= 0 and a finite focusDistance)"};
  if (!std::isfinite(c.lensUv.x) || !std::isfinite(c.lensUv.y))
    return Error{where + ": camera lensUv is NaN or infinite"};
  if (!std::isfinite(c.shutter) || c.shutter < 0.0f || !std::isfinite(c.timeU))
    return Error{where + ": camera shutter is invalid (needs a finite shutter >= 0 and a finite timeU)"};
  if (c.aperture > 0.0f && c.orthographic)
    return Error{where + ": camera aperture needs a perspective camera (an orthographic camera has no lens)"};
  return {};
}

}  // namespace tandem
