#include "core/Shading.h"


#include <algorithm>
#include <cassert>

namespace tandem::shading {

namespace {
int lightTypeCode(LightType t) {
  switch (t) {
    case LightType::Point: return TD_LIGHT_POINT;
    case LightType::Spot: return TD_LIGHT_SPOT;
    case LightType::Directional: return TD_LIGHT_DIRECTIONAL;
    case LightType::Rect: return TD_LIGHT_RECT;
    case LightType::Disk: return TD_LIGHT_DISK;
    case LightType::Sphere: return TD_LIGHT_SPHERE;
    case LightType::Ambient: break;
  }
  assert(false && "packLight: an ambient light is not a direct light");
  return TD_LIGHT_POINT;
}
}  // namespace

GpuLight packLight(const Light& l, int areaSlot) {
  GpuLight g{};
  const int type = lightTypeCode(l.type);
  glm::vec3 dir = glm::dot(l.dirW, l.dirW) > 0.0f ? glm::normalize(l.dirW) : glm::vec3(0, -1, 0);
  g.posType = vec4(l.posW, float(type));
  g.dirRange = vec4(dir, l.range);
  g.radiance = vec4(l.color * l.intensity, l.castShadows ? 1.0f : 0.0f);
  g.attenCone = vec4(l.attenuation, 0.0f);
  float inner = std::min(l.innerConeDeg, l.outerConeDeg);
  g.cone = vec4(std::cos(glm::radians(inner)), std::cos(glm::radians(l.outerConeDeg)), 0.0f, 0.0f);
  if (l.type == LightType::Rect || l.type == LightType::Disk) {
    // The surface's axes: its height along upW projected onto the plane (any perpendicular when upW is
    // along the normal), its width completing a right-handed frame with the normal.
    glm::vec3 up = l.upW - glm::dot(l.upW, dir) * dir;
    if (!(glm::dot(up, up) > 1e-12f)) up = std::abs(dir.y) < 0.9f ? glm::vec3(0, 1, 0) - dir.y * dir : glm::vec3(1, 0, 0) - dir.x * dir;
    up = glm::normalize(up);
    const glm::vec3 across = glm::cross(up, dir);
    const glm::vec2 half = l.type == LightType::Rect ? 0.5f * l.size : glm::vec2(l.radius);
    g.shapeU = vec4(across * half.x, float(areaSlot));
    g.shapeV = vec4(up * half.y, 0.0f);
  } else if (l.type == LightType::Sphere) {
    g.shapeU = vec4(0.0f, 0.0f, 0.0f, float(areaSlot));
    g.shapeV = vec4(0.0f, 0.0f, 0.0f, l.radius);
  }
  return g;
}

float areaLightReach(const Light& l) {
  switch (l.type) {
    case LightType::Rect: return 0.5f * (l.size.x + l.size.y);
    case LightType::Disk: return 2.0f * l.radius;
    case LightType::Sphere: return l.radius;
    default: return 0.0f;
  }
}

GpuMaterial packMaterial(const Material& m, int index, std::optional<ShadingModel> override) {
  GpuMaterial g{};
  ShadingModel model = override ? *override : m.shading;
  g.kaToon = vec4(m.ka, float(index));
  g.kdTex = vec4(m.kd, float(m.kdTexture));
  g.ksNs = vec4(m.ks, m.ns);
  g.krKtIorModel = vec4(m.kr, m.kt, m.ior, float(static_cast<int>(model)));
  g.kd2Checker = vec4(m.kd2, m.checkerFrequency);
  g.emissionFlags = vec4(m.emission, m.unlit ? 1.0f : 0.0f);
  // Alpha code of tdCoverage (shaders/shading.glsl): one float for mode, cutoff and base alpha.
  float opacity = std::clamp(m.opacity, 0.0f, 1.0f);
  float alphaCode = 0.0f;
  if (m.alphaMode == AlphaMode::Mask && m.alphaCutoff > 0.0f)
    alphaCode = opacity > 0.0f ? std::min(m.alphaCutoff / opacity, 2.0f) : 2.0f;
  else if (m.alphaMode == AlphaMode::Blend)
    alphaCode = -1.0f - opacity;
  g.texAlpha = vec4(float(m.emissiveTexture), float(m.normalTexture), m.normalScale, alphaCode);
  const ProceduralTexture& t = m.procedural;
  g.pattern = vec4(float(static_cast<int>(t.type)), t.scale, t.turbulence, float(t.octaves));
  g.patternSpace = vec4(t.worldSpace ? 1.0f : 0.0f, t.bump, 0.0f, 0.0f);
  return g;
}

void bakeToonRamp(const Material& m, float* out) {
  for (int i = 0; i < TD_TOON_RAMP_SIZE; ++i) {
    // N·L at the texel centre, the value nearest filtering stands for.
    float nl = (float(i) + 0.5f) / TD_TOON_RAMP_SIZE * 2.0f - 1.0f;
    float level = 0.0f;
    float best = -2.0f;
    for (const ToonStep& s : m.toonRamp)
      if (nl >= s.threshold && s.threshold >= best) {
        best = s.threshold;
        level = s.level;
      }
    out[i] = level;
  }
}

}  // namespace tandem::shading
