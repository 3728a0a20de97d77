#include "core/Shading.h"

#include <algorithm>

namespace tandem::shading {

GpuLight packLight(const Light& l) {
  GpuLight g{};
  int type = l.type == LightType::Point ? TD_LIGHT_POINT : l.type == LightType::Spot ? TD_LIGHT_SPOT : TD_LIGHT_DIRECTIONAL;
  glm::vec3 dir = glm::dot(l.dirW, l.dirW) > 0.0f ? glm::normalize(l.dirW) : glm::vec3(0, -1, 0);
  g.posType = vec4(l.posW, float(type));
  g.dirRange = vec4(dir, l.range);
  g.radiance = vec4(l.color * l.intensity, l.castShadows ? 1.0f : 0.0f);
  g.attenCone = vec4(l.attenuation, 0.0f);
  float inner = std::min(l.innerConeDeg, l.outerConeDeg);
  g.cone = vec4(std::cos(glm::radians(inner)), std::cos(glm::radians(l.outerConeDeg)), 0.0f, 0.0f);
  return g;
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
