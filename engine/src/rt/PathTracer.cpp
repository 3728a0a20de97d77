#include "rt/PathTracer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/Shading.h"
#include "rt/RayMath.h"

namespace tandem::rt {

using namespace tandem::shading;

namespace {

float largest(glm::vec3 v) { return std::max(v.x, std::max(v.y, v.z)); }

}  // namespace

glm::vec3 cosineDirection(glm::vec3 n, glm::vec2 u) {
  // Malley's method: a uniform point on the unit disk lifted onto the hemisphere.
  const float r = std::sqrt(u.x), phi = 6.28318530718f * u.y;
  const glm::vec3 helper = std::abs(n.x) > 0.5f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t = glm::normalize(glm::cross(helper, n));
  const glm::vec3 b = glm::cross(n, t);
  const float z = std::sqrt(std::max(0.0f, 1.0f - u.x));
  return glm::normalize(t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * z);
}

glm::vec3 PathTracer::radiance(SurfaceHit hit, int x, int y, std::uint32_t sample, RayCounts& counts) const {
  const Scene& scene = w_.scene();
  const EmbreeScene& embree = w_.embree();
  const FrameShading& frame = w_.frame();
  const TraceModes& modes = w_.modes();
  const auto ux = static_cast<std::uint32_t>(x), uy = static_cast<std::uint32_t>(y);
  // Dimensions 0..15 belong to the pixel sample (sub-pixel offset, lens, time): each bounce draws its own 4.
  auto random = [&](int bounce, int k) {
    return random01(ux, uy, sample, 16u + 4u * static_cast<std::uint32_t>(bounce) + static_cast<std::uint32_t>(k));
  };
  glm::vec3 radiance(0.0f), beta(1.0f);
  for (int bounce = 0;; ++bounce) {
    // Next-event estimation: the local term, each light behind its shadow rays (Whitted::shade's).
    const bool shadowRays = bounce == 0 ? modes.primaryShadowRays : modes.secondaryShadowRays;
    AreaSampleBits area{};
    const std::uint32_t mask = shadowRays ? w_.lightMask(hit, counts, NoRecorder{}, &area, bounce) : ~0u;
    radiance += beta * shadeLocal(scene, frame, embree.transformAt(hit.instance, hit.time), hit, mask,
                                  shadowRays ? &area : nullptr, bounce);
    if (bounce >= kMaxBounces) break;

    // The continuation's weights: diffuse (unlit materials have none), reflection, refraction.
    const GpuMaterial& m = frame.materials[hit.material];
    const WhittedWeights w = w_.weights(hit);
    const glm::vec3 diffuse =
        m.emissionFlags.w > 0.5f ? glm::vec3(0.0f) : hit.coverage * tdSurfaceColor(m, hit.uv, hit.pattern, hit.tint);
    const float reflect = modes.reflections ? w.reflect : 0.0f;
    const glm::vec3 transmit = modes.refraction ? w.transmit : glm::vec3(0.0f);
    const float pd = largest(diffuse), pr = reflect, pt = largest(transmit);
    const float total = pd + pr + pt;
    if (!(total > 0.0f) || !std::isfinite(total)) break;
    // Russian roulette: a path whose weights add up to less than 1 goes on with that probability.
    const float survive = bounce < kMinBounces ? 1.0f : std::min(1.0f, total);
    if (random(bounce, 0) >= survive) break;
    const float pick = random(bounce, 1) * total;
    const glm::vec2 u(random(bounce, 2), random(bounce, 3));
    glm::vec3 dir, weight, side;
    const float rough = frame.roughness[hit.material];
    if (pick < pd) {
      dir = cosineDirection(hit.normalW, u);
      // A shading normal tilted off the facet can send a diffuse ray under it: that part of the lobe is dark.
      if (!(glm::dot(dir, hit.geomNormalW) > 0.0f)) break;
      weight = diffuse * (total / pd);
      side = hit.geomNormalW;
      ++counts.reflection;
    } else if (pick < pd + pr) {
      dir = glossyDirection(w.reflectDirW, rough, u, hit.geomNormalW);
      weight = glm::vec3(reflect * (total / pr));
      side = hit.geomNormalW;
      ++counts.reflection;
    } else {
      dir = glossyDirection(w.refraction.dirW, w.passThrough ? 0.0f : rough, u, -hit.geomNormalW);
      weight = transmit * (total / pt);
      side = -hit.geomNormalW;
      ++counts.refraction;
    }
    beta *= weight / survive;
    if (!std::isfinite(beta.x + beta.y + beta.z)) break;
    const glm::vec3 origin = spawnOrigin(hit, side);
    std::uint32_t instance = 0, triangle = 0;
    if (!w_.intersect(origin, dir, 0.0f, std::numeric_limits<float>::infinity(), hit.time, instance, triangle,
                      NoRecorder{})) {
      radiance += beta * frame.environment.radiance(dir);
      break;
    }
    const float time = hit.time;
    hit = resolveHit(scene, embree.transformAt(instance, time), instance, triangle, Ray{origin, dir});
    hit.time = time;
  }
  return radiance;
}

}  // namespace tandem::rt
