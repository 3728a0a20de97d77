#pragma once
// A scene's environment as the frame reads it (docs/environment.md): the radiance of a direction that
// leaves the scene and the ambient light at a surface, from Scene::environment, by shading.glsl's formulas
// (the GL's shade pass reads the same record: gl/ShadePass).
#include <array>
#include <cmath>
#include <functional>
#include <memory>

#include <glm/glm.hpp>

#include "tandem/Scene.h"

namespace tandem {

class EnvironmentLookup {
 public:
  EnvironmentLookup() = default;
  /// `scene`'s environment; `lightsAmbient` false leaves the ambient term to the ambient lights (the path
  /// tracer's paths gather the environment's light themselves).
  explicit EnvironmentLookup(const Scene& scene, bool lightsAmbient = true);

  /// TD_ENV_* of shading.glsl.
  int kind() const { return kind_; }
  /// Linear radiance arriving from unit direction dirW (world or render space: they differ by a translation). A
  /// direction that is not finite (a ray Embree refused) sees the background colour.
  glm::vec3 radiance(glm::vec3 dirW) const {
    if (kind_ == kBackground || !std::isfinite(dirW.x + dirW.y + dirW.z)) return background_;
    return lookup(dirW);
  }
  /// The environment's ambient light at a surface facing unit nW; zero where it lights nothing.
  glm::vec3 ambient(glm::vec3 nW) const {
    if (!ambient_) return glm::vec3(0.0f);
    return shAmbient(nW);
  }
  bool lightsAmbient() const { return ambient_; }

  // The record as the GL's uniforms take it (gl/ShadePass).
  glm::vec2 turn() const { return turn_; }                 // cos, sin of the rotation about +Y
  float mapScale() const { return intensity_; }            // Map: the texels' scale
  const std::array<glm::vec3, 3>& sky() const { return sky_; }  // zenith, horizon, ground, scaled
  const std::array<glm::vec3, 9>& ambientSh() const { return sh_; }  // scaled; zero where none
  const EnvironmentMap* map() const { return map_.get(); }
  glm::vec3 background() const { return background_; }

 private:
  static constexpr int kBackground = 0;
  glm::vec3 lookup(glm::vec3 dirW) const;
  glm::vec3 shAmbient(glm::vec3 nW) const;

  int kind_ = kBackground;
  glm::vec3 background_{0.0f};
  glm::vec2 turn_{1.0f, 0.0f};
  float intensity_ = 1.0f;
  std::array<glm::vec3, 3> sky_{};
  std::array<glm::vec3, 9> sh_{};
  std::shared_ptr<const EnvironmentMap> map_;
  bool ambient_ = false;
};

/// The nine coefficients of tdShAmbient for `radiance(d)` over the sphere (d in the environment's frame),
/// integrated over a `width`×`height` equirectangular grid of texel centres, each weighted by its solid angle.
/// `radiance(x, y, d)`: texel (x, y)'s radiance, d its centre's unit direction.
std::array<glm::vec3, 9> projectAmbientSh(int width, int height,
                                          const std::function<glm::vec3(int x, int y, glm::vec3 d)>& radiance);

/// An image's texel at `uv` (tdEquirectUv) with bilinear filtering, as GL's LINEAR sampling of the map's
/// texture reads it: wrapping around in u, clamped at the poles in v.
glm::vec3 sampleEquirect(const EnvironmentMap& map, glm::vec2 uv);

}  // namespace tandem
