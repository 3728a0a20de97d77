#include "rt/Radiosity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "core/Sampling.h"
#include "core/Shading.h"
#include "rt/Parallel.h"
#include "rt/RayMath.h"
#include "rt/SurfaceShading.h"
#include "rt/Whitted.h"
#include "tandem/ImageMetrics.h"

namespace tandem::rt {

namespace {

constexpr double kPi = 3.14159265358979323846;

float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

/// The mean linear colour of a texture (sRGB decoded where it is sRGB): a patch's share of its pattern.
glm::vec4 textureMean(const Texture& t) {
  if (t.width <= 0 || t.height <= 0 || t.rgba8.size() < static_cast<std::size_t>(t.width) * t.height * 4)
    return glm::vec4(1.0f);
  std::array<float, 256> decode{};
  for (std::size_t i = 0; i < 256; ++i) {
    const float c = static_cast<float>(i) / 255.0f;
    decode[i] = t.srgb ? colorspace::srgbToLinear(c) : c;
  }
  glm::dvec4 sum(0.0);
  const std::size_t n = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  for (std::size_t i = 0; i < n; ++i)
    sum += glm::dvec4(decode[t.rgba8[4 * i]], decode[t.rgba8[4 * i + 1]], decode[t.rgba8[4 * i + 2]],
                      t.rgba8[4 * i + 3] / 255.0);
  return glm::vec4(sum / static_cast<double>(n));
}

/// A point of the triangle (a, b, c) from u ∈ [0, 1)²: uniform in area, strata of the square kept compact.
glm::vec3 pointOnTriangle(const glm::vec3* p, glm::vec2 u) {
  const float s = std::sqrt(u.x);
  return p[0] * (1.0f - s) + p[1] * (s * (1.0f - u.y)) + p[2] * (s * u.y);
}

/// Quadrature points of a receiver patch: the degree-2 rule at barycentrics (2/3, 1/6, 1/6) and rotations
/// (Strang and Fix), inside the patch, so no receiver point sits on an edge a neighbour shares.
constexpr int kReceiverPoints = 3;
glm::vec3 receiverPoint(const RadiosityPatch& p, int k) {
  const float a = 2.0f / 3.0f, b = 1.0f / 6.0f;
  const glm::vec3 w = k == 0 ? glm::vec3(a, b, b) : k == 1 ? glm::vec3(b, a, b) : glm::vec3(b, b, a);
  return w.x * p.cornerW[0] + w.y * p.cornerW[1] + w.z * p.cornerW[2];
}

/// The magnitude bound offsetRayOrigin needs for a point of a patch: its corners' (the point interpolates them).
glm::vec3 patchMagnitude(const RadiosityPatch& p) {
  return glm::max(glm::abs(p.cornerW[0]), glm::max(glm::abs(p.cornerW[1]), glm::abs(p.cornerW[2])));
}

/// The mean over triangle (a, b, c) of the point form factor towards the shooter polygon `shooter`
/// (centre sc, normal sn): the 3-point rule where the shooter is far compared with the triangle; where it
/// is near (the 1/r² kernel varies across the triangle: neighbours across an edge, a slab against a wall)
/// the triangle is cut in 4 and each part done the same way, down to 4^4 parts.
double meanOverTriangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, glm::dvec3 n,
                        const glm::dvec3* shooter, double shooterRadius, glm::dvec3 sc, glm::dvec3 sn, int depth) {
  const glm::dvec3 centre = (a + b + c) / 3.0;
  const double size = std::max(glm::length(b - a), std::max(glm::length(c - b), glm::length(a - c)));
  const double gap = glm::length(centre - sc) - shooterRadius;
  if (depth < 4 && gap < 2.0 * size) {
    const glm::dvec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    return 0.25 * (meanOverTriangle(a, ab, ca, n, shooter, shooterRadius, sc, sn, depth + 1) +
                   meanOverTriangle(ab, b, bc, n, shooter, shooterRadius, sc, sn, depth + 1) +
                   meanOverTriangle(ca, bc, c, n, shooter, shooterRadius, sc, sn, depth + 1) +
                   meanOverTriangle(ab, bc, ca, n, shooter, shooterRadius, sc, sn, depth + 1));
  }
  const double w = 2.0 / 3.0, v = 1.0 / 6.0;
  const glm::dvec3 points[3] = {w * a + v * b + v * c, v * a + w * b + v * c, v * a + v * b + w * c};
  double sum = 0.0;
  for (const glm::dvec3& x : points)
    if (glm::dot(x - sc, sn) > 0.0) sum += pointToPolygonFormFactor(x, n, shooter, 3);
  return sum / 3.0;
}

double meanPointFormFactor(const RadiosityPatch& r, const glm::dvec3* shooter, glm::dvec3 sc, glm::dvec3 sn) {
  double radius = 0.0;
  for (int k = 0; k < 3; ++k) radius = std::max(radius, glm::length(shooter[k] - sc));
  return meanOverTriangle(glm::dvec3(r.cornerW[0]), glm::dvec3(r.cornerW[1]), glm::dvec3(r.cornerW[2]),
                          glm::dvec3(r.normalW), shooter, radius, sc, sn, 0);
}

}  // namespace

double pointToPolygonFormFactor(glm::dvec3 x, glm::dvec3 n, const glm::dvec3* corners, int count) {
  // Clip to the half-space in front of x (Sutherland–Hodgman against one plane): at most count + 1 corners.
  std::array<glm::dvec3, 8> clipped{};
  int m = 0;
  for (int k = 0; k < count; ++k) {
    const glm::dvec3 a = corners[k] - x, b = corners[(k + 1) % count] - x;
    const double da = glm::dot(a, n), db = glm::dot(b, n);
    if (da > 0.0) clipped[static_cast<std::size_t>(m++)] = a;
    if ((da > 0.0) != (db > 0.0)) {
      const double t = da / (da - db);
      clipped[static_cast<std::size_t>(m++)] = a + t * (b - a);
    }
  }
  if (m < 3) return 0.0;
  // Lambert: F = (1/2π) Σ γk n·(ak × bk)/|ak × bk|, γk the angle between consecutive corners' directions.
  double sum = 0.0;
  for (int k = 0; k < m; ++k) {
    const glm::dvec3 a = clipped[static_cast<std::size_t>(k)], b = clipped[static_cast<std::size_t>((k + 1) % m)];
    const glm::dvec3 c = glm::cross(a, b);
    const double len = glm::length(c);
    if (!(len > 0.0)) continue;  // a clipped corner on x's plane repeated, or two corners in line with x
    const double gamma = std::atan2(len, glm::dot(a, b));
    sum += gamma * glm::dot(n, c) / len;
  }
  return std::abs(sum) / (2.0 * kPi);
}

RadiositySolver::RadiositySolver(const Scene& scene, const EmbreeScene& embree, const RadiosityOptions& options)
    : embree_(embree), options_(options) {
  // Per material: reflectance (kd, the checker's mean, the kd texture's mean, BLEND's opacity) and emission.
  std::vector<glm::vec3> reflectance(scene.materials.size()), emission(scene.materials.size());
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    const Material& mat = scene.materials[m];
    glm::vec3 kd = mat.checkerFrequency > 0.0f || mat.procedural.type != Pattern::None ? 0.5f * (mat.kd + mat.kd2) : mat.kd;
    glm::vec3 em = mat.emission;
    if (mat.kdTexture >= 0 && static_cast<std::size_t>(mat.kdTexture) < scene.textures.size()) {
      const glm::vec4 t = textureMean(scene.textures[static_cast<std::size_t>(mat.kdTexture)]);
      kd *= glm::vec3(t);
      if (mat.alphaMode == AlphaMode::Blend) kd *= std::clamp(mat.opacity * t.a, 0.0f, 1.0f);
    } else if (mat.alphaMode == AlphaMode::Blend) {
      kd *= std::clamp(mat.opacity, 0.0f, 1.0f);
    }
    if (mat.emissiveTexture >= 0 && static_cast<std::size_t>(mat.emissiveTexture) < scene.textures.size())
      em *= glm::vec3(textureMean(scene.textures[static_cast<std::size_t>(mat.emissiveTexture)]));
    // Unlit surfaces show their colour whatever reaches them: they neither reflect nor emit light here.
    reflectance[m] = mat.unlit ? glm::vec3(0.0f) : glm::clamp(kd, 0.0f, 1.0f);
    emission[m] = mat.unlit ? glm::vec3(0.0f) : glm::max(em, 0.0f);
  }

  // The patch size: the target area, or the scene's area shared out over targetPatches.
  double totalArea = 0.0;
  for (std::size_t inst = 0; inst < scene.instances.size(); ++inst) {
    const Mesh& mesh = scene.meshes[scene.instances[inst].mesh];
    if (mesh.exact) continue;  // see below
    const glm::mat4& m = embree.transform(inst).worldFromObject;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::dvec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = glm::dvec3(m * glm::vec4(mesh.positions[mesh.indices[3 * t + k]], 1.0f));
      const double a = 0.5 * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
      if (std::isfinite(a)) totalArea += a;
    }
  }
  const double patchArea = options_.patchArea > 0.0f
                               ? static_cast<double>(options_.patchArea)
                               : totalArea / std::max(1, options_.targetPatches);

  instanceFirst_.assign(scene.instances.size(), std::numeric_limits<std::size_t>::max());
  instanceTriangles_.assign(scene.instances.size(), 0);
  for (std::size_t inst = 0; inst < scene.instances.size(); ++inst) {
    const Instance& instance = scene.instances[inst];
    const Mesh& mesh = scene.meshes[instance.mesh];
    const glm::mat4& m = embree.transform(inst).worldFromObject;
    instanceFirst_[inst] = triangles_.size();
    // An exact solid (Mesh::exact) blocks light in the solve but gets no patches: its triangles are only the
    // raster's proxy, and its hits carry no triangle to look the solution up on. The ambient term lights it.
    if (mesh.exact) continue;
    instanceTriangles_[inst] = mesh.triangleCount();
    glm::vec3 tintMean(1.0f);
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      glm::vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = glm::vec3(m * glm::vec4(mesh.positions[mesh.indices[3 * t + k]], 1.0f));
      const glm::dvec3 cross = glm::cross(glm::dvec3(p[1]) - glm::dvec3(p[0]), glm::dvec3(p[2]) - glm::dvec3(p[0]));
      const double len = glm::length(cross);
      GridTriangle g;
      g.instance = static_cast<std::uint32_t>(inst);
      g.triangle = static_cast<std::uint32_t>(t);
      g.firstPatch = patches_.size();
      const double area = 0.5 * len;
      g.n = !(area > 0.0) || !std::isfinite(area) || !(patchArea > 0.0)
                ? 1
                : static_cast<int>(std::clamp(std::ceil(std::sqrt(area / patchArea)), 1.0, double(options_.maxSegments)));
      if (triangles_.size() < options_.segments.size())  // a refined solve's own grid (refinedSegments)
        g.n = std::clamp(options_.segments[triangles_.size()], 1, options_.maxSegments);
      triangles_.push_back(g);
      const glm::vec3 front = len > 0.0 && std::isfinite(len) ? glm::vec3(cross / len) : glm::vec3(0.0f, 0.0f, 1.0f);
      if (!mesh.colors.empty()) {
        tintMean = glm::vec3(0.0f);
        for (int k = 0; k < 3; ++k) tintMean += glm::vec3(mesh.colors[mesh.indices[3 * t + k]]) * (1.0f / 3.0f);
      }
      const glm::vec3 rho = glm::clamp(reflectance[instance.material] * tintMean, 0.0f, 1.0f);
      const int n = g.n;
      auto vertex = [&](int i, int j) {
        const float fn = static_cast<float>(n);
        return p[0] * (1.0f - static_cast<float>(i + j) / fn) + p[1] * (static_cast<float>(i) / fn) +
               p[2] * (static_cast<float>(j) / fn);
      };
      auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        for (int side = 0; side < 2; ++side) {
          RadiosityPatch patch;
          patch.instance = g.instance;
          patch.triangle = g.triangle;
          patch.cornerW[0] = a;
          patch.cornerW[1] = b;
          patch.cornerW[2] = c;
          patch.normalW = side == 0 ? front : -front;
          patch.area = static_cast<float>(area / (static_cast<double>(n) * n));
          patch.reflectance = rho;
          patch.emission = emission[instance.material];
          patches_.push_back(patch);
        }
      };
      for (int j = 0; j < n; ++j)
        for (int i = 0; i + j < n; ++i) {
          add(vertex(i, j), vertex(i + 1, j), vertex(i, j + 1));
          if (i + j <= n - 2) add(vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
        }
    }
  }
  radiosity_.assign(patches_.size(), glm::vec3(0.0f));
  indirect_.assign(patches_.size(), glm::vec3(0.0f));
  direct_.assign(patches_.size(), glm::vec3(0.0f));
  unshot_.assign(patches_.size(), glm::vec3(0.0f));
  rows_.resize(patches_.size());
  buildLayout(scene);
  gatherDirect(scene);
}

bool RadiositySolver::visible(glm::vec3 fromW, glm::vec3 fromN, glm::vec3 toW, glm::vec3 toN) const {
  // Both ends moved off their surfaces by their own rounding error, towards each other's side.
  const glm::vec3 a = offsetRayOrigin(fromW, fromN, glm::abs(fromW));
  const glm::vec3 b = offsetRayOrigin(toW, toN, glm::abs(toW));
  const glm::vec3 d = b - a;
  const float len = glm::length(d);
  if (!(len > 0.0f)) return true;
  RTCRay ray;
  if (!makeEmbreeRay(ray, a, d / len, 0.0f, len, 0.5f)) return false;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcOccluded1(embree_.top(), &ctx, &ray);
  return ray.tfar >= 0.0f;  // Embree sets tfar to -inf when something is in the way
}

std::vector<glm::vec3> RadiositySolver::directLight(const Scene& scene) const {
  std::vector<glm::vec3> direct(patches_.size(), glm::vec3(0.0f));
  const FrameShading frame(scene, std::nullopt, embree_.anchor());
  const int samples = std::max(1, options_.lightSamples);
  parallelIndices(0, patches_.size(), [&](std::size_t p) {
    const RadiosityPatch& patch = patches_[p];
    if (!(patch.area > 0.0f) || cancelled()) return;
    glm::vec3 sum(0.0f);
    const glm::vec3 mag = patchMagnitude(patch);
    const auto seed = static_cast<std::uint32_t>(p);
    for (int k = 0; k < samples; ++k) {
      // Stratified points of the patch (the (0,2)-sequence) and, independently shuffled, of each area light.
      const auto index = static_cast<std::uint32_t>(k);
      const glm::uvec2 s = sobol02(nestedShuffle(index, shading::tdHash(seed)));
      const glm::vec3 x = pointOnTriangle(patch.cornerW, glm::vec2(s) * (1.0f / 4294967296.0f));
      for (std::size_t j = 0; j < frame.lights.size(); ++j) {
        glm::vec3 toLight;
        float dist;
        glm::vec3 e;
        if (frame.isArea(j)) {
          const glm::uvec2 l = sobol02(nestedShuffle(index, shading::tdHash(seed ^ (0x9e3779b9u * static_cast<std::uint32_t>(j + 1)))));
          e = shading::tdAreaLightSample(frame.lights[j], frame.lightType(j), x, glm::vec2(l) * (1.0f / 4294967296.0f),
                                         toLight, dist);
        } else {
          e = shading::tdLightIncident(frame.lights[j], x, toLight, dist);
        }
        const float cosine = glm::dot(patch.normalW, toLight);
        if (!(cosine > 0.0f) || !(e.x + e.y + e.z > 0.0f)) continue;
        if (frame.castsShadows(j)) {
          const glm::vec3 origin = offsetRayOrigin(x, patch.normalW, mag);
          RTCRay ray;
          const float far = dist < 0.0f ? std::numeric_limits<float>::infinity() : dist * (1.0f - 1e-4f);
          if (!makeEmbreeRay(ray, origin, toLight, 0.0f, far, 0.5f)) continue;
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          rtcOccluded1(embree_.top(), &ctx, &ray);
          if (!(ray.tfar >= 0.0f)) continue;
        }
        sum += e * cosine;
      }
    }
    direct[p] = sum * (1.0f / static_cast<float>(samples));
  });
  return direct;
}

void RadiositySolver::gatherDirect(const Scene& scene) {
  direct_ = directLight(scene);
  glm::dvec3 rhoArea(0.0);
  double area = 0.0;
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    const RadiosityPatch& patch = patches_[p];
    radiosity_[p] = patch.emission + patch.reflectance * direct_[p];
    unshot_[p] = radiosity_[p];
    rhoArea += glm::dvec3(patch.reflectance) * static_cast<double>(patch.area);
    area += patch.area;
  }
  meanReflectance_ = area > 0.0 ? glm::vec3(rhoArea / area) : glm::vec3(0.0f);
  enteredPower_ = enteredPower();
}

double RadiositySolver::enteredPower() const {
  double power = 0.0;
  for (std::size_t p = 0; p < patches_.size(); ++p)
    power += static_cast<double>(luminance(patches_[p].emission + patches_[p].reflectance * direct_[p])) * patches_[p].area;
  return power;
}

void RadiositySolver::relight(const Scene& scene) {
  // Incremental (Chen 1990): the change in each patch's reflected direct light becomes unshot light, negative
  // where a patch lost light; shooting it moves the solution to the new lights' with the form factors kept.
  const std::vector<glm::vec3> direct = directLight(scene);
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    const glm::vec3 change = patches_[p].reflectance * (direct[p] - direct_[p]);
    radiosity_[p] += change;
    unshot_[p] += change;
  }
  direct_ = direct;
  // Against the larger of the old and the new light: lights turned off leave only negative light to shoot,
  // which must still be shot down to the same fraction.
  enteredPower_ = std::max(enteredPower_, enteredPower());
}

float RadiositySolver::formFactor(std::size_t receiver, std::size_t shooter) const {
  const RadiosityPatch& r = patches_[receiver];
  const RadiosityPatch& s = patches_[shooter];
  if (receiver == shooter || (receiver ^ 1u) == shooter) return 0.0f;  // a patch does not see itself
  if (!(r.area > 0.0f) || !(s.area > 0.0f)) return 0.0f;
  // The shooter's side must face the receiver, and the receiver's side the shooter: decided per point below
  // (the clip), but a whole patch behind the other's plane is skipped here at no cost.
  const glm::dvec3 sc(s.centreW()), rc(r.centreW());
  const glm::dvec3 sn(s.normalW), rn(r.normalW);
  // Coplanar patches (a floor's own neighbours) see nothing of each other: "in front" means beyond the
  // corners' rounding error (relative to the patches' size and to their coordinates' magnitude).
  const float magnitude = std::max(glm::length(patchMagnitude(r)), glm::length(patchMagnitude(s)));
  const double tolerance = 1e-5 * std::sqrt(std::max(r.area, s.area)) + 4e-7 * magnitude;
  double ahead = 0.0;
  for (int k = 0; k < 3; ++k) ahead = std::max(ahead, glm::dot(glm::dvec3(r.cornerW[k]) - sc, sn));
  if (!(ahead > tolerance)) return 0.0f;
  double front = 0.0;
  for (int k = 0; k < 3; ++k) front = std::max(front, glm::dot(glm::dvec3(s.cornerW[k]) - rc, rn));
  if (!(front > tolerance)) return 0.0f;
  // The analytic part: the mean of the point form factor over the receiver; a point behind the shooter's
  // plane (the shooter's other side faces it) sees nothing of this side.
  glm::dvec3 corners[3];
  for (int k = 0; k < 3; ++k) corners[k] = glm::dvec3(s.cornerW[k]);
  const double f = meanPointFormFactor(r, corners, sc, sn);
  glm::vec3 points[kReceiverPoints];
  for (int q = 0; q < kReceiverPoints; ++q) points[q] = receiverPoint(r, q);
  if (!(f > 0.0)) return 0.0f;
  // Visibility: rays from the receiver's points to stratified points of the shooter; 4 first, all of them
  // where those disagree. A pair that carries a large share of the receiver's light (f > 1/64; at most 64
  // shooters per receiver) gets all of them at once: 4 rays that agree say little about a pair three
  // quarters hidden, and there that error would be a visible part of the receiver's light.
  const auto seed = shading::tdHash(static_cast<std::uint32_t>(receiver) * 0x9e3779b9u ^ static_cast<std::uint32_t>(shooter));
  auto ray = [&](int k) {
    const glm::uvec2 u = sobol02(nestedShuffle(static_cast<std::uint32_t>(k), seed));
    const glm::vec3 to = pointOnTriangle(s.cornerW, glm::vec2(u) * (1.0f / 4294967296.0f));
    return visible(points[k % kReceiverPoints], r.normalW, to, s.normalW) ? 1 : 0;
  };
  const int more = std::max(4, options_.visibilityRays);
  const int first = f > 1.0 / 64.0 ? more : 4;
  int seen = 0, traced = 0;
  for (; traced < first; ++traced) seen += ray(traced);
  if (seen != 0 && seen != traced)
    for (; traced < more; ++traced) seen += ray(traced);
  return static_cast<float>(f * seen / traced);
}

int RadiositySolver::shoot(int maxShots, float residualTarget) {
  int taken = 0;
  while (taken < maxShots && residual() > residualTarget) {
    // The patch with the most unshot power, gained or (after relight) lost.
    std::size_t best = 0;
    float bestPower = 0.0f;
    for (std::size_t p = 0; p < patches_.size(); ++p) {
      const float power = luminance(glm::abs(unshot_[p])) * patches_[p].area;
      if (power > bestPower) {
        bestPower = power;
        best = p;
      }
    }
    if (!(bestPower > 0.0f)) break;
    const glm::vec3 shot = unshot_[best];
    unshot_[best] = glm::vec3(0.0f);
    // Receiver j gets H += F(j→i)·ΔB_i (reciprocity turned the shooter's power into the receiver's
    // irradiance), reflects ρj of it and keeps that to shoot. The receivers together get at most the power
    // shot (Σj Aj·F(j→i) <= Ai): where the quadrature overshoots, the shot is scaled down to conserve it.
    // A patch is shot again and again as light keeps arriving (about 4 times each in the Cornell box): its
    // form factors are kept from the first time, within the cache's budget.
    std::vector<float>& row = rows_[best];
    const bool made = row.empty();
    if (made) {
      row.resize(patches_.size());
      parallelIndices(0, patches_.size(), [&](std::size_t j) {
        row[j] = j == best || cancelled() ? 0.0f : formFactor(j, best);
      });
      double received = 0.0;
      for (std::size_t j = 0; j < patches_.size(); ++j) received += static_cast<double>(row[j]) * patches_[j].area;
      if (received > patches_[best].area) {
        const auto scale = static_cast<float>(patches_[best].area / received);
        for (float& f : row) f *= scale;
      }
    }
    for (std::size_t j = 0; j < patches_.size(); ++j) {
      const float f = row[j];
      if (!(f > 0.0f)) continue;
      const glm::vec3 h = f * shot;
      indirect_[j] += h;
      const glm::vec3 reflected = patches_[j].reflectance * h;
      radiosity_[j] += reflected;
      unshot_[j] += reflected;
    }
    ++shots_;
    ++taken;
    if (made) {
      const std::size_t rowBytes = patches_.size() * sizeof(float);
      if (cachedBytes_ + rowBytes <= options_.cacheBytes) cachedBytes_ += rowBytes;
      else std::vector<float>().swap(row);  // over budget: this row is made again the next time
    }
  }
  return taken;
}

float RadiositySolver::residual() const {
  if (!(enteredPower_ > 0.0)) return 0.0f;
  double left = 0.0;
  for (std::size_t p = 0; p < patches_.size(); ++p)
    left += static_cast<double>(luminance(glm::abs(unshot_[p]))) * patches_[p].area;
  return static_cast<float>(left / enteredPower_);
}

std::vector<int> RadiositySolver::refinedSegments(float threshold, std::size_t maxPatches) const {
  std::vector<int> segments(triangles_.size());
  for (std::size_t k = 0; k < triangles_.size(); ++k) segments[k] = triangles_[k].n;
  // The scale: the mean indirect light over the patch sides it reached.
  double sum = 0.0, area = 0.0;
  for (std::size_t p = 0; p < patches_.size(); ++p)
    if (luminance(indirect_[p]) > 0.0f) {
      sum += static_cast<double>(luminance(indirect_[p])) * patches_[p].area;
      area += patches_[p].area;
    }
  if (!(area > 0.0) || !(sum > 0.0)) return segments;
  const double mean = sum / area;
  // Per triangle, the largest step of the shown solution across it (its grid vertices, welded to the
  // neighbours' so a single-patch triangle sees the gradient too), relative to the mean.
  const RadiosityField shown = field();
  struct Candidate {
    double step;
    std::size_t triangle;
  };
  std::vector<Candidate> candidates;
  for (std::size_t k = 0; k < triangles_.size(); ++k) {
    const GridTriangle& g = triangles_[k];
    if (g.n >= options_.maxSegments) continue;
    const std::size_t base = table_[table_[g.instance].x + g.triangle].x;
    const std::size_t vertices = static_cast<std::size_t>((g.n + 1) * (g.n + 2) / 2);
    double step = 0.0;
    for (std::size_t side = 0; side < 2; ++side) {
      float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
      for (std::size_t v = 0; v < vertices; ++v) {
        const float y = luminance(shown.values[base + 2 * v + side]);
        lo = std::min(lo, y);
        hi = std::max(hi, y);
      }
      step = std::max(step, static_cast<double>(hi - lo) / mean);
    }
    if (step > threshold) candidates.push_back({step, k});
  }
  // The steepest first, while the patches stay within the budget (doubling n makes 4 patches of each).
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.step > b.step; });
  std::size_t patches = patches_.size() / 2;
  for (const Candidate& c : candidates) {
    const int n = segments[c.triangle], refined = std::min(2 * n, options_.maxSegments);
    const std::size_t more = static_cast<std::size_t>(refined * refined - n * n);
    if (patches + more > maxPatches) continue;
    segments[c.triangle] = refined;
    patches += more;
  }
  return segments;
}

void RadiositySolver::buildLayout(const Scene& scene) {
  // The table: the instances' entries, then each covered triangle's (its first value, n), in triangles_
  // order (instance-major, triangle order).
  table_.assign(instanceFirst_.size(), glm::uvec2(RadiosityField::kNone, 0u));
  for (std::size_t inst = 0; inst < instanceFirst_.size(); ++inst) {
    if (instanceTriangles_[inst] == 0) continue;
    table_[inst] = glm::uvec2(static_cast<std::uint32_t>(table_.size()), static_cast<std::uint32_t>(instanceTriangles_[inst]));
    table_.resize(table_.size() + instanceTriangles_[inst], glm::uvec2(0u));
  }
  std::size_t values = 0;
  for (const GridTriangle& g : triangles_) {
    table_[table_[g.instance].x + g.triangle] = glm::uvec2(static_cast<std::uint32_t>(values), static_cast<std::uint32_t>(g.n));
    values += 2u * static_cast<std::size_t>((g.n + 1) * (g.n + 2) / 2);
  }
  valueCount_ = values;

  // Welding: the grid vertices on a triangle's edges and corners that other triangles of the instance share,
  // on sides whose normals agree within 25°, take one mean, so the solution is continuous across the
  // triangles of a smooth surface and not across a crease (a box's edge). A shared vertex is found by its
  // position in object space made the same way from either triangle: an edge's points are interpolated from
  // its lexicographically smaller end, so both triangles round them alike (vertices shared by index or only
  // by position, and a coarser neighbour's points where they coincide).
  struct Member {
    std::uint32_t value;
    glm::vec3 normal;
  };
  std::map<std::tuple<std::uint32_t, float, float, float>, std::vector<Member>> groups;
  auto lexLess = [](glm::vec3 a, glm::vec3 b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
  };
  for (const GridTriangle& g : triangles_) {
    const Mesh& mesh = scene.meshes[scene.instances[g.instance].mesh];
    glm::vec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.positions[mesh.indices[3 * g.triangle + static_cast<std::size_t>(k)]];
    const std::size_t base = table_[table_[g.instance].x + g.triangle].x;
    auto onEdge = [&](int a, int b, int k) {  // point k of n from corner a towards corner b
      const bool flip = lexLess(p[b], p[a]);
      const glm::vec3 from = flip ? p[b] : p[a], to = flip ? p[a] : p[b];
      const int steps = flip ? g.n - k : k;
      return from + (to - from) * (static_cast<float>(steps) / static_cast<float>(g.n));
    };
    auto add = [&](int i, int j, glm::vec3 pos) {
      const std::size_t v = base + 2u * static_cast<std::size_t>(shading::tdGridVertex(i, j, g.n));
      // Both sides in one group: the normals decide, so a neighbour wound the other way welds front to back.
      for (int side = 0; side < 2; ++side)
        groups[{g.instance, pos.x, pos.y, pos.z}].push_back(
            {static_cast<std::uint32_t>(v) + static_cast<std::uint32_t>(side),
             patches_[g.firstPatch + static_cast<std::size_t>(side)].normalW});
    };
    add(0, 0, p[0]);
    add(g.n, 0, p[1]);
    add(0, g.n, p[2]);
    for (int k = 1; k < g.n; ++k) {
      add(k, 0, onEdge(0, 1, k));          // p0 → p1: (k, 0)
      add(0, k, onEdge(0, 2, k));          // p0 → p2: (0, k)
      add(g.n - k, k, onEdge(1, 2, k));    // p1 → p2: (n − k, k)
    }
  }
  // Per value slot, the slots it takes its mean over (itself included), as offsets into weldMembers_.
  weldStart_.assign(values + 1, 0);
  std::vector<std::vector<std::uint32_t>> lists(values);
  const float cosWeld = std::cos(glm::radians(25.0f));
  for (const auto& [key, members] : groups)
    for (const Member& m : members)
      for (const Member& o : members)
        if (glm::dot(o.normal, m.normal) >= cosWeld) lists[m.value].push_back(o.value);
  weldMembers_.clear();
  for (std::size_t v = 0; v < values; ++v) {
    weldStart_[v] = static_cast<std::uint32_t>(weldMembers_.size());
    if (lists[v].empty()) weldMembers_.push_back(static_cast<std::uint32_t>(v));  // an interior vertex: itself
    else weldMembers_.insert(weldMembers_.end(), lists[v].begin(), lists[v].end());
  }
  weldStart_[values] = static_cast<std::uint32_t>(weldMembers_.size());
}

RadiosityField RadiositySolver::field() const {
  RadiosityField out;
  out.instanceCount = instanceFirst_.size();
  out.table = table_;
  // Each grid vertex: the area-weighted mean of its patches within the triangle, then of the vertices it is
  // welded to.
  std::vector<glm::vec3> sum(valueCount_, glm::vec3(0.0f));
  std::vector<float> weight(valueCount_, 0.0f);
  for (const GridTriangle& g : triangles_) {
    const std::size_t base = table_[table_[g.instance].x + g.triangle].x;
    const int n = g.n;
    std::size_t p = g.firstPatch;
    auto accumulate = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
      for (int side = 0; side < 2; ++side, ++p) {
        const float a = patches_[p].area;
        for (auto [i, j] : {std::pair{i0, j0}, std::pair{i1, j1}, std::pair{i2, j2}}) {
          const std::size_t v = base + 2u * static_cast<std::size_t>(shading::tdGridVertex(i, j, n)) + side;
          sum[v] += a * indirect_[p];
          weight[v] += a;
        }
      }
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        accumulate(i, j, i + 1, j, i, j + 1);
        if (i + j <= n - 2) accumulate(i + 1, j, i + 1, j + 1, i, j + 1);
      }
  }
  out.values.assign(valueCount_, glm::vec3(0.0f));
  for (std::size_t v = 0; v < valueCount_; ++v) {
    glm::vec3 s(0.0f);
    float w = 0.0f;
    for (std::uint32_t k = weldStart_[v]; k < weldStart_[v + 1]; ++k) {
      s += sum[weldMembers_[k]];
      w += weight[weldMembers_[k]];
    }
    // Light taken back after a relight can leave a patch a little under 0 until its neighbours' shots arrive.
    out.values[v] = w > 0.0f ? glm::max(s / w, 0.0f) : glm::vec3(0.0f);
  }
  // The unshot light, spread as ambient (Cohen et al. 1988): unshot power over the area the light has
  // reached (the sides with some radiosity: a closed room's outsides never get any), times the
  // interreflection factor 1 / (1 − mean ρ).
  glm::dvec3 unshot(0.0);
  double area = 0.0;
  for (std::size_t p = 0; p < patches_.size(); ++p) {
    unshot += glm::dvec3(unshot_[p]) * static_cast<double>(patches_[p].area);
    if (radiosity_[p].x + radiosity_[p].y + radiosity_[p].z > 0.0f) area += patches_[p].area;
  }
  if (area > 0.0) {
    const glm::dvec3 rho = glm::min(glm::dvec3(meanReflectance_), glm::dvec3(0.95));
    out.ambient = glm::max(glm::vec3(unshot / area / (glm::dvec3(1.0) - rho)), 0.0f);
  }
  return out;
}

}  // namespace tandem::rt
