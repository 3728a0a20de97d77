#pragma once
// Ray math of the CPU pass: robust origin offsets, the watertight ray/triangle test that gives the
// exact primary hit, refraction with Fresnel and total internal reflection, per-pixel random numbers.
// Header-only and Embree-free so tests can hold each routine to its numbers directly.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

#include "core/Shading.h"
#include "tandem/Settings.h"

namespace tandem::rt {

inline bool isFinite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The largest magnitude of the coordinates (the scale the rounding of bounds and margins follows).
inline double maxAbs(glm::dvec3 v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

/// How far offsetRayOrigin may move a point at `posW` with error scale `magnitude`: at most ~130 ulps of the
/// scale, then a ulp per coordinate; 2e-5 is ~170 ulps of the larger of the two.
inline float offsetLift(glm::vec3 posW, glm::vec3 magnitude) {
  const glm::vec3 a = glm::max(glm::abs(posW), magnitude);
  return 2e-5f * std::max({a.x, a.y, a.z});
}

/// std::nextafter(x, +inf) by integer arithmetic on the bits: the same result for every input (zeros,
/// infinities and NaN included), without the libm call, which showed in the ray pass's profile (every
/// spawned ray rounds three components).
inline float nextFloatUp(float x) {
  if (!(x < std::numeric_limits<float>::infinity())) return x;         // +inf stays, NaN stays NaN
  if (x == 0.0f) return std::numeric_limits<float>::denorm_min();     // from either zero
  auto bits = std::bit_cast<std::int32_t>(x);
  return std::bit_cast<float>(x > 0.0f ? bits + 1 : bits - 1);        // sign-magnitude: -x moves to 0
}
/// std::nextafter(x, -inf), likewise.
inline float nextFloatDown(float x) { return -nextFloatUp(-x); }

/// Bound on the magnitudes that went into an interpolated hit position, per component (pbrt-v4's
/// Σ|bj·pj|, with the transform's terms when the vertices were transformed): the rounding error of the
/// position is a few ULPs of this, not of the position itself, which can be far smaller (a point near
/// the origin on a large triangle, or a triangle spanning -1e8..1e8).
inline glm::vec3 interpolationMagnitude(glm::vec3 bary, glm::vec3 m0, glm::vec3 m1, glm::vec3 m2) {
  return std::abs(bary.x) * glm::abs(m0) + std::abs(bary.y) * glm::abs(m1) + std::abs(bary.z) * glm::abs(m2);
}

/// Scale-aware origin offset (pbrt-v4's error-bound offset, with margins sized for Embree): moves posW
/// along the unit geometric normal `normalW` (on the side the new ray leaves from) by
///   d = 2^-23 · (kErrUlps · dot(|n|, magnitude) + kMinUlps · max(magnitude)),
/// the position's rounding error projected on the normal plus a floor for Embree's own rounding (relative
/// to the triangle, so a surface through the origin still gets a real offset), then rounds each moved
/// component one more ULP away so the addition can never round back onto the surface. Unlike a fixed
/// epsilon or W&B's fixed near-origin offset it is invariant under scaling the scene (1e-4 .. 1e4), and it
/// stays correct when one component of the position is small but carries a large error.
inline glm::vec3 offsetRayOrigin(glm::vec3 posW, glm::vec3 normalW, glm::vec3 magnitude) {
  constexpr float kUlp = 1.0f / 8388608.0f;  // 2^-23
  constexpr float kErrUlps = 64.0f;
  constexpr float kMinUlps = 16.0f;
  glm::vec3 an = glm::abs(normalW);
  float maxMag = std::max(magnitude.x, std::max(magnitude.y, magnitude.z));
  float d = kUlp * (kErrUlps * glm::dot(an, magnitude) + kMinUlps * maxMag);
  // A triangle entirely at 0 (all its coordinates zero, i.e. degenerate at the origin): the smallest
  // normal float keeps the ray off it.
  d = std::max(d, std::numeric_limits<float>::min());
  glm::vec3 out = posW + d * normalW;
  for (int i = 0; i < 3; ++i) {
    if (normalW[i] > 0.0f) out[i] = nextFloatUp(out[i]);
    else if (normalW[i] < 0.0f) out[i] = nextFloatDown(out[i]);
  }
  return out;
}

/// Barycentrics (of p0, p1, p2) of the point of triangle (p0, p1, p2) closest to q (Ericson,
/// Real-Time Collision Detection 5.1.5), in double so needle triangles do not lose the answer.
inline glm::dvec3 closestPointBarycentrics(glm::dvec3 q, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  glm::dvec3 ab = b - a, ac = c - a, ap = q - a;
  double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1, 0, 0};
  glm::dvec3 bp = q - b;
  double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {0, 1, 0};
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    double v = d1 / (d1 - d3);
    return {1.0 - v, v, 0};
  }
  glm::dvec3 cp = q - c;
  double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {0, 0, 1};
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    double w = d2 / (d2 - d6);
    return {1.0 - w, 0, w};
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1.0 - w, w};
  }
  double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) return {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};  // zero-area triangle
  double v = vb / denom, w = vc / denom;
  return {1.0 - v - w, v, w};
}

/// Barycentrics of where the ray meets the triangle, by the watertight test of Woop, Benthin and Wald
/// (JCGT 2013) evaluated in double (its own fallback precision, affordable once per hit). When the ray
/// passes outside the triangle (a pixel centre grazing past the edge of the triangle the rasterizer
/// picked) or runs parallel to it, the result is clamped to the triangle's nearest point, so the hit
/// always lies on the triangle. Sums to 1.
// (By reference: passed by value, each vec3 is repacked into registers from the caller's fresh
// per-component stores, a store-forwarding stall that showed in resolveHit's profile.)
inline glm::vec3 triangleBarycentrics(const glm::vec3& originW, const glm::vec3& dirW, const glm::vec3& p0,
                                      const glm::vec3& p1, const glm::vec3& p2) {
  glm::dvec3 o(originW), d(dirW);
  glm::dvec3 ad = glm::abs(d);
  int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  // Plain arrays for the permuted reads: glm's operator[] with a run-time index is a switch per read
  // (34 M instructions of the Whitted pass's 3.5 G under callgrind); same values, same operations.
  const double dArr[3] = {d.x, d.y, d.z};
  if (dArr[kz] < 0.0) std::swap(kx, ky);
  const double a[3] = {double(p0.x) - o.x, double(p0.y) - o.y, double(p0.z) - o.z};
  const double b[3] = {double(p1.x) - o.x, double(p1.y) - o.y, double(p1.z) - o.z};
  const double c[3] = {double(p2.x) - o.x, double(p2.y) - o.y, double(p2.z) - o.z};
  glm::dvec3 bary;
  if (dArr[kz] != 0.0) {
    double sx = dArr[kx] / dArr[kz], sy = dArr[ky] / dArr[kz];
    double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
    double u = cx * by - cy * bx;  // weight of p0
    double v = ax * cy - ay * cx;  // weight of p1
    double w = bx * ay - by * ax;  // weight of p2
    double det = u + v + w;
    if (det != 0.0) {
      bary = glm::dvec3(u, v, w) / det;
      if (bary.x >= 0.0 && bary.y >= 0.0 && bary.z >= 0.0) return glm::vec3(bary);
      // Outside: clamp the ray/plane point to the triangle when the plane is in front of the ray.
      glm::dvec3 onPlane = bary.x * glm::dvec3(p0) + bary.y * glm::dvec3(p1) + bary.z * glm::dvec3(p2);
      if (glm::dot(onPlane - o, d) > 0.0)
        return glm::vec3(closestPointBarycentrics(onPlane, glm::dvec3(p0), glm::dvec3(p1), glm::dvec3(p2)));
    }
  }
  // Parallel to the plane, degenerate, or behind: the triangle point nearest the ray, near its centroid.
  glm::dvec3 centroid = (glm::dvec3(p0) + glm::dvec3(p1) + glm::dvec3(p2)) / 3.0;
  glm::dvec3 onRay = o + d * std::max(0.0, glm::dot(centroid - o, d) / std::max(glm::dot(d, d), 1e-300));
  return glm::vec3(closestPointBarycentrics(onRay, glm::dvec3(p0), glm::dvec3(p1), glm::dvec3(p2)));
}

/// Fresnel reflectance and the refracted direction at a dielectric boundary.
struct Refraction {
  float fresnel = 1.0f;          // F: reflected fraction; 1 on total internal reflection
  bool totalInternal = false;    // no transmitted ray
  glm::vec3 dirW{0.0f};          // unit refracted direction (valid when !totalInternal)
};

/// Light arriving along -toEyeW at a surface with unit normal normalW on the arrival side
/// (dot(normalW, toEyeW) >= 0), passing from IOR etaI into etaT. TIR is decided by the same cos²θt
/// expression (tdCos2T) as tdFresnelExact / tdFresnelSchlick, so F = 1 exactly when there is no transmitted ray.
/// Equal IORs are an exact identity: no bending, F = 0.
inline Refraction refractDielectric(glm::vec3 toEyeW, glm::vec3 normalW, float etaI, float etaT, FresnelMode mode) {
  Refraction r;
  if (etaI == etaT) {
    r.fresnel = 0.0f;
    r.dirW = -toEyeW;
    return r;
  }
  float cosI = glm::clamp(glm::dot(normalW, toEyeW), 0.0f, 1.0f);
  float eta = etaI / etaT;
  // The same cos²θt (and so the same TIR decision) as the Fresnel formulas, without cancellation.
  float cos2T = shading::tdCos2T(cosI, eta);
  r.fresnel = mode == FresnelMode::Schlick ? shading::tdFresnelSchlick(cosI, etaI, etaT)
                                           : shading::tdFresnelExact(cosI, etaI, etaT);
  if (cos2T <= 0.0f) {
    r.totalInternal = true;
    r.fresnel = 1.0f;
    return r;
  }
  float cosT = std::sqrt(cos2T);
  glm::vec3 t = eta * -toEyeW + (eta * cosI - cosT) * normalW;
  float len = glm::length(t);
  r.dirW = len > 0.0f ? t / len : -normalW;
  return r;
}

/// The full-resolution pixel a ray-grid pixel stands for (RayTracer.h: min(g·s + s/2, size − 1)).
inline glm::ivec2 fullPixelOfGridPixel(int gx, int gy, int scale, int width, int height) {
  return {std::min(gx * scale + scale / 2, width - 1), std::min(gy * scale + scale / 2, height - 1)};
}
inline int gridSize(int size, int scale) { return (size + scale - 1) / scale; }

/// Stateless per-pixel random numbers: a hash of (pixel, sample, dimension), so results do not depend
/// on which thread draws them or in which order (no global RNG).
inline std::uint32_t hashPcg(std::uint32_t v) {
  std::uint32_t state = v * 747796405u + 2891336453u;
  std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
inline float random01(std::uint32_t x, std::uint32_t y, std::uint32_t sample, std::uint32_t dim) {
  std::uint32_t h = hashPcg(x ^ hashPcg(y ^ hashPcg(sample ^ hashPcg(dim))));
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);  // 24 bits: exactly representable, < 1
}

}  // namespace tandem::rt
