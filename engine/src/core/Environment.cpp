#include "core/Environment.h"

#include <cassert>
#include <cmath>
#include <vector>

#include "core/Shading.h"

namespace tandem {

namespace {
constexpr double kPi = 3.14159265358979323846;
// The sky's coefficients come from its gradient on this grid, once per process (the gradient varies with the
// height alone, smoothly but for the horizon's square root).
constexpr int kSkyGridWidth = 128, kSkyGridHeight = 64;
}  // namespace

std::array<glm::vec3, 9> projectAmbientSh(int width, int height,
                                          const std::function<glm::vec3(int x, int y, glm::vec3 d)>& radiance) {
  assert(width > 0 && height > 0);
  // Each band's cosine-lobe factor over π (Ramamoorthi and Hanrahan 2001: Â0 = π, Â1 = 2π/3, Â2 = π/4),
  // so that tdShAmbient gives irradiance over π.
  constexpr double kBand[9] = {1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25, 0.25, 0.25, 0.25, 0.25};
  std::array<glm::dvec3, 9> sum{};
  const double dPhi = 2.0 * kPi / width, dTheta = kPi / height;
  // The inverse of tdEquirectUv at the texels' centres: each column's azimuth, each row's height.
  std::vector<glm::dvec2> column(static_cast<std::size_t>(width));
  for (int x = 0; x < width; ++x) {
    const double phi = ((x + 0.5) / width - 0.5) * 2.0 * kPi;
    column[std::size_t(x)] = glm::dvec2(std::sin(phi), -std::cos(phi));
  }
  for (int y = 0; y < height; ++y) {
    const double theta = (y + 0.5) * dTheta, sinTheta = std::sin(theta), cosTheta = std::cos(theta);
    // The texel's own solid angle (its row's band of the sphere over the columns): the constant term of a
    // uniform image comes out exact, however few its rows.
    const double solidAngle = dPhi * (std::cos(y * dTheta) - std::cos((y + 1) * dTheta));
    for (int x = 0; x < width; ++x) {
      const glm::dvec2 c = column[std::size_t(x)];
      const glm::vec3 d(float(sinTheta * c.x), float(cosTheta), float(sinTheta * c.y));
      const glm::dvec3 l = glm::dvec3(radiance(x, y, d)) * solidAngle;
      for (int i = 0; i < 9; ++i) sum[std::size_t(i)] += l * double(shading::tdShBasis(i, d));
    }
  }
  std::array<glm::vec3, 9> out;
  for (std::size_t i = 0; i < 9; ++i) out[i] = glm::vec3(sum[i] * kBand[i]);
  return out;
}

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<glm::vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
  assert(width > 0 && height > 0 && texels_.size() == std::size_t(width) * std::size_t(height));
  ambientSh_ = projectAmbientSh(width_, height_, [&](int x, int y, glm::vec3) {
    return texels_[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
  });
}

glm::vec3 sampleEquirect(const EnvironmentMap& map, glm::vec2 uv) {
  const int w = map.width(), h = map.height();
  // Texel centres at (i + 0.5) / size, as GL's: u wraps (GL_REPEAT), v is clamped to the edge rows.
  const float fx = uv.x * float(w) - 0.5f, fy = uv.y * float(h) - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float ax = fx - x0f, ay = fy - y0f;
  auto wrap = [w](long x) { return int(((x % w) + w) % w); };
  auto clampY = [h](long y) { return int(std::clamp(y, 0L, long(h - 1))); };
  const long x0 = long(x0f), y0 = long(y0f);
  const int xa = wrap(x0), xb = wrap(x0 + 1), ya = clampY(y0), yb = clampY(y0 + 1);
  const auto& t = map.texels();
  auto at = [&](int x, int y) { return t[std::size_t(y) * std::size_t(w) + std::size_t(x)]; };
  return glm::mix(glm::mix(at(xa, ya), at(xb, ya), ax), glm::mix(at(xa, yb), at(xb, yb), ax), ay);
}

EnvironmentLookup::EnvironmentLookup(const Scene& scene, bool lightsAmbient) {
  const Environment& e = scene.environment;
  background_ = scene.background;
  switch (e.kind) {
    case Environment::Kind::Background: kind_ = TD_ENV_BACKGROUND; return;
    case Environment::Kind::Sky: kind_ = TD_ENV_SKY; break;
    case Environment::Kind::Map:
      // (validateScene refuses a Map without an image; an unchecked scene shows its background)
      if (!e.map) return;
      kind_ = TD_ENV_MAP;
      map_ = e.map;
      break;
  }
  const double angle = double(e.rotationDeg) * kPi / 180.0;
  turn_ = glm::vec2(float(std::cos(angle)), float(std::sin(angle)));
  intensity_ = e.intensity;
  sky_ = {e.zenith * e.intensity, e.horizon * e.intensity, e.ground * e.intensity};
  ambient_ = lightsAmbient && e.lightsAmbient;
  if (!ambient_) return;
  if (kind_ == TD_ENV_MAP) {
    for (std::size_t i = 0; i < 9; ++i) sh_[i] = map_->ambientSh()[i] * e.intensity;
  } else {
    // The sky is linear in its three colours: its coefficients are theirs weighted by the gradient's, which
    // are projected once (the gradient with zenith, horizon and ground as the unit axes) rather than per frame.
    static const std::array<glm::vec3, 9> weights =
        projectAmbientSh(kSkyGridWidth, kSkyGridHeight, [](int, int, glm::vec3 d) {
          return shading::tdSkyRadiance(d, glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1));
        });
    for (std::size_t i = 0; i < 9; ++i)
      sh_[i] = sky_[0] * weights[i].x + sky_[1] * weights[i].y + sky_[2] * weights[i].z;
  }
}

glm::vec3 EnvironmentLookup::lookup(glm::vec3 dirW) const {
  const glm::vec3 d = shading::tdEnvironmentFrame(dirW, turn_);
  if (kind_ == TD_ENV_SKY) return shading::tdEnvironmentClamp(shading::tdSkyRadiance(d, sky_[0], sky_[1], sky_[2]));
  return shading::tdEnvironmentClamp(intensity_ * sampleEquirect(*map_, shading::tdEquirectUv(d)));
}

glm::vec3 EnvironmentLookup::shAmbient(glm::vec3 nW) const {
  // (shading.glsl's array parameter is a pointer in C++; the formula only reads it)
  return shading::tdShAmbient(shading::tdEnvironmentFrame(nW, turn_), const_cast<glm::vec3*>(sh_.data()));
}

}  // namespace tandem
