#include "rt/ShadowCertainty.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "rt/EmbreeScene.h"
#include "rt/Parallel.h"

// The segment test's one definition (shaders/shadow_tests.glsl), compiled as C++ with glm as GLSL's twin.
namespace tandem::rt::shadowtests {
using glm::dot;
using glm::max;
using glm::min;
using glm::vec3;
using glm::vec4;
using std::abs;
using std::isinf;
#define TD_FN inline
#include "../../../shaders/shadow_tests.glsl"
#undef TD_FN
}  // namespace tandem::rt::shadowtests

namespace tandem::rt {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Texel arithmetic is float; a projected coordinate is off by far less than this many texels.
constexpr float kTexelSlack = 1.0f / 64.0f;
// At most this many triangles near a point light are tested against each of its rays (build()).
constexpr std::size_t kNearLightMax = 64;

// The rounding itself (about 16 ulps of the magnitudes): how far the vertices build() made, and the
// geometry Embree tests in object space, may lie from each other in render space. The maps list a triangle
// wherever it may lie.
constexpr float kRelativeRounding = 1e-6f;

struct Triangle {
  glm::vec3 v[3];       // render space
  std::uint32_t id;     // global id
  float slack = 0.0f;   // where the triangle may lie beyond v, in render-space units (kRelativeRounding)
};

// Ericson, Real-Time Collision Detection 5.1.5: the point of triangle abc closest to p.
glm::vec3 closestOnTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  glm::vec3 bp = p - b;
  float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
  glm::vec3 cp = p - c;
  float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Cube faces in GL's order (+X, −X, +Y, −Y, +Z, −Z): S, T, A. Any right-handed frame would do, as long as
// build and classify use the same one.
constexpr float kFaceAxes[6][3][3] = {
    {{0, 0, -1}, {0, -1, 0}, {1, 0, 0}},  {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}}, {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},  {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
};

// Texels are stored in 16×16 blocks, row-major within a block and block-row-major within a face: the
// queries of neighbouring pixels fall in neighbouring texels, and a block shares a few memory pages
// where a row-major face would touch a page per texel row (measured: the texel fetch was a fifth of the
// classification's time before). Faces have a multiple of 16 texels per side.
constexpr int kBlock = ShadowCertainty::kBlock;
inline std::size_t texelIndex(int x, int y, int n) {
  const auto ux = static_cast<std::size_t>(x), uy = static_cast<std::size_t>(y), un = static_cast<std::size_t>(n);
  return ((uy / kBlock) * (un / kBlock) + ux / kBlock) * (kBlock * kBlock) + (uy % kBlock) * kBlock + ux % kBlock;
}

int cubeFace(glm::vec3 d) {
  glm::vec3 a = glm::abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0f ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0f ? 2 : 3;
  return d.z >= 0.0f ? 4 : 5;
}

// The tangent (cube) or world (ortho) half-range that leaves (kMarginTexels + 1) texels of guard band
// beyond [-1, 1] (cube) or the scene (ortho): a query's grown square then never leaves the map.
float withGuardBand(float halfRange, int size) {
  return halfRange / (1.0f - 2.0f * (ShadowCertainty::kMarginTexels + 1.0f) / static_cast<float>(size));
}

/// Rasterizes every triangle into rows [row0, row1) of one face of a map.
class FaceRaster {
 public:
  FaceRaster(ShadowCertainty::Map& map, int face, int row0, int row1)
      : m_(map), face_(face), row0_(row0), row1_(row1), n_(map.size),
        scale_(static_cast<float>(map.size) / (2.0f * map.extent)),
        texels_(map.texels.data() + static_cast<std::size_t>(face) * map.size * map.size) {}

  void add(const Triangle& tri) {
    const glm::vec3* axes = m_.axes[face_];
    std::array<glm::vec3, 3> q;  // face coordinates: S, T, A
    for (int k = 0; k < 3; ++k) {
      glm::vec3 d = m_.kind == ShadowCertainty::Kind::Cube ? tri.v[k] - m_.origin : tri.v[k];
      q[k] = glm::vec3(glm::dot(axes[0], d), glm::dot(axes[1], d), glm::dot(axes[2], d));
    }
    // The polygon this face sees: clipped to A ≥ near for a cube face (what lies behind the light, or
    // nearer than nearZ where build() proved nothing is, cannot block a ray the face answers).
    std::array<glm::vec3, 4> poly;
    int count = 0;
    if (m_.kind == ShadowCertainty::Kind::Cube) {
      const float nearZ = m_.nearZ;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 &a = q[k], &b = q[(k + 1) % 3];
        bool ina = a.z >= nearZ, inb = b.z >= nearZ;
        if (ina) poly[count++] = a;
        if (ina != inb) poly[count++] = a + (b - a) * ((nearZ - a.z) / (b.z - a.z));
      }
      if (count == 0) return;
    } else {
      for (int k = 0; k < 3; ++k) poly[count++] = q[k];
    }
    // Map pixels and depths of the polygon's corners.
    std::array<glm::vec2, 4> px;
    float depthLo = kInf, nearest = kInf;
    glm::vec2 lo(kInf), hi(-kInf);
    for (int k = 0; k < count; ++k) {
      px[k] = pixel(poly[k]);
      float depth = depthOf(poly[k].z);
      depthLo = std::min(depthLo, depth);
      nearest = std::min(nearest, poly[k].z);
      lo = glm::min(lo, px[k]);
      hi = glm::max(hi, px[k]);
    }
    // Where the triangle may lie beyond its corners (Triangle::slack, render-space units; rounding of far
    // vertices), as map pixels: on the orthographic map directly; on a cube face the projection s/a moves by
    // at most (|ds| + |s/a|·|da|)/a, largest at the corner nearest the light.
    float slackPx = tri.slack * scale_;
    if (m_.kind == ShadowCertainty::Kind::Cube)
      slackPx = nearest > 0.0f ? tri.slack * scale_ * (1.0f + 2.0f * m_.extent) / nearest : kInf;
    depthLo -= tri.slack;
    // Rounding scale of the pixel arithmetic: the largest pixel coordinate involved. A corner far outside
    // the map (a clip point near a small nearZ) or not finite makes the edge functions meaningless at
    // texel scale: such a polygon is recorded over its whole (clamped) bounding box, in front of
    // everything — conservative, never dropped.
    float reach = static_cast<float>(n_);
    for (int k = 0; k < count; ++k) reach = std::max(reach, std::max(std::abs(px[k].x), std::abs(px[k].y)));
    const bool wild = !(reach <= 64.0f * static_cast<float>(n_)) || !(slackPx <= static_cast<float>(n_));
    if (wild || !std::isfinite(depthLo)) {
      depthLo = -kInf;
      lo = glm::vec2(-kInf);
      hi = glm::vec2(kInf);
    }
    lo = glm::clamp(lo, glm::vec2(-4.0f), glm::vec2(static_cast<float>(n_) + 4.0f));
    hi = glm::clamp(hi, glm::vec2(-4.0f), glm::vec2(static_cast<float>(n_) + 4.0f));
    const float h = 0.5f + ShadowCertainty::kMarginTexels;  // half-side of a grown texel square
    const float slack = kTexelSlack + (wild ? 0.0f : slackPx);
    int x0 = std::max(0, static_cast<int>(std::floor(lo.x - h - slack)));
    int x1 = std::min(n_ - 1, static_cast<int>(std::floor(hi.x + h + slack)));
    int y0 = std::max(row0_, static_cast<int>(std::floor(lo.y - h - slack)));
    int y1 = std::min(row1_ - 1, static_cast<int>(std::floor(hi.y + h + slack)));
    if (x0 > x1 || y0 > y1) return;
    // Edges as inward unit normals: e(p) = n·p − c ≥ 0 inside. A polygon whose area or an edge is within
    // the rounding of the pixel arithmetic of nothing is kept by its bounding box only (conservative);
    // so is one whose orientation rounding could flip.
    // The area from corner 0 (translation-free): its rounding is a few 1e-7 of the product of the edge
    // vectors' lengths plus their own rounding (1e-7·reach each).
    float area = 0.0f, longest = 0.0f;
    for (int k = 1; k + 1 < count; ++k) {
      const glm::vec2 a = px[k] - px[0], b = px[k + 1] - px[0];
      area += a.x * b.y - a.y * b.x;
      longest = std::max(longest, std::max(glm::length(a), glm::length(b)));
    }
    std::array<glm::vec3, 4> edges;  // xy normal, z offset
    const float tiny = 1e-5f * reach;
    bool solid = !wild && std::isfinite(depthLo) && std::abs(area) > 1e-5f * longest * (longest + reach);
    for (int k = 0; solid && k < count; ++k) {
      glm::vec2 e = px[(k + 1) % count] - px[k];
      glm::vec2 nrm = area > 0.0f ? glm::vec2(-e.y, e.x) : glm::vec2(e.y, -e.x);
      float len = glm::length(nrm);
      if (!(len > tiny)) {
        // A (nearly) repeated corner: its normal is rounding noise. Leaving the edge out only widens the
        // polygon (the other edges bound it): still conservative.
        edges[k] = glm::vec3(0.0f, 0.0f, -1.0f);
        continue;
      }
      nrm /= len;
      edges[k] = glm::vec3(nrm, glm::dot(nrm, px[k]));
    }
    // The triangle's plane in face coordinates: depth along the ray through any map pixel.
    // (In double: a needle's float cross product can point far enough off to move the bound.)
    const glm::dvec3 normalD = glm::cross(glm::dvec3(q[1]) - glm::dvec3(q[0]), glm::dvec3(q[2]) - glm::dvec3(q[0]));
    glm::vec3 planeN(normalD);
    float planeC = static_cast<float>(glm::dot(normalD, glm::dvec3(q[0])));
    // As an affine function of map pixels (x, y): on a cube face, c/depth = n·(s, t, 1) with s, t affine
    // in the pixel, scaled here so that it is c'/depth with c' = |planeC| > 0; on the orthographic map,
    // the depth itself.
    glm::vec3 lin(0.0f);
    bool linValid = false;
    if (m_.kind == ShadowCertainty::Kind::Cube) {
      const float sign = planeC > 0.0f ? 1.0f : -1.0f;
      lin = sign * glm::vec3(planeN.x / scale_, planeN.y / scale_, planeN.z - m_.extent * (planeN.x + planeN.y));
      planeC = std::abs(planeC);
      linValid = planeC > 0.0f && std::isfinite(planeC) && std::isfinite(lin.x) && std::isfinite(lin.y) && std::isfinite(lin.z);
    } else if (planeN.z != 0.0f) {
      // depth = top − (c − n.x·x − n.y·y)/n.z with x = px/scale − extent + centre.x (likewise y)
      const float kx = planeN.x / planeN.z, ky = planeN.y / planeN.z;
      lin = glm::vec3(kx / scale_, ky / scale_,
                      m_.top - planeC / planeN.z + kx * (m_.centre.x - m_.extent) + ky * (m_.centre.y - m_.extent));
      linValid = std::isfinite(lin.x) && std::isfinite(lin.y) && std::isfinite(lin.z);
    }
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        glm::vec2 c(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
        if (solid) {
          bool touches = true;
          for (int k = 0; k < count && touches; ++k) {
            const float grown = h * (std::abs(edges[k].x) + std::abs(edges[k].y));
            touches = edges[k].x * c.x + edges[k].y * c.y - edges[k].z >= -grown - slack;
          }
          if (!touches) continue;
        }
        // A lower bound of the depth over the grown square: the plane's depth (or, on a cube face, its
        // reciprocal) is affine in the map's pixels, so its extreme over the square is at a corner,
        // found in closed form; over the polygon it is at one of its corners.
        float bound = depthLo;
        const float g = lin.x * c.x + lin.y * c.y + lin.z, spread = (h + slack) * (std::abs(lin.x) + std::abs(lin.y));
        if (linValid) {
          if (m_.kind == ShadowCertainty::Kind::Cube) {
            const float plane = planeC / (g + spread) - tri.slack;  // 1/depth is at most g + spread over the square
            if (g - spread > 0.0f && std::isfinite(plane)) bound = std::max(bound, plane);
          } else if (std::isfinite(g - spread)) {
            bound = std::max(bound, g - spread - tri.slack);
          }
        }
        insert(texelIndex(x, y, n_), tri.id, bound);
      }
  }

 private:
  glm::vec2 pixel(glm::vec3 q) const {
    if (m_.kind == ShadowCertainty::Kind::Cube) return (glm::vec2(q.x, q.y) / q.z + m_.extent) * scale_;
    return (glm::vec2(q.x, q.y) - m_.centre + m_.extent) * scale_;
  }
  float depthOf(float a) const { return m_.kind == ShadowCertainty::Kind::Cube ? a : m_.top - a; }
  // Keeps the texel's kCandidates nearest triangles in order of their depth bound; a triangle pushed
  // out (or never let in) lowers the bound of the rest.
  void insert(std::size_t texel, std::uint32_t id, float depth) {
    ShadowCertainty::Texel& t = texels_[texel];
    float* d = t.depths;
    constexpr int K = ShadowCertainty::kCandidates;
    if (!(depth < d[K - 1])) {
      t.restDepth = std::min(t.restDepth, depth);
      return;
    }
    if (t.triangles[K - 1] != ~0u) t.restDepth = std::min(t.restDepth, d[K - 1]);
    int k = K - 1;
    for (; k > 0 && depth < d[k - 1]; --k) {
      d[k] = d[k - 1];
      t.triangles[k] = t.triangles[k - 1];
    }
    d[k] = depth;
    t.triangles[k] = id;
  }

  ShadowCertainty::Map& m_;
  int face_, row0_, row1_, n_;
  float scale_;
  ShadowCertainty::Texel* texels_;
};

enum class Crossing { Misses = TD_SEGMENT_MISSES, Crosses = TD_SEGMENT_CROSSES, Unsure = TD_SEGMENT_UNSURE };

// The ray against one triangle: shaders/shadow_tests.glsl (the GL's proof pass runs the same text).
Crossing segmentVsTriangle(const ShadowCertainty::TriangleTest& tri, glm::vec3 o, glm::vec3 d, float tEnd, float margin) {
  if (!tri.valid) return Crossing::Unsure;
  return static_cast<Crossing>(
      shadowtests::tdSegmentVsTriangle(tri.plane, tri.edges[0], tri.edges[1], tri.edges[2], o, d, tEnd, margin));
}

ShadowCertainty::TriangleTest makeTest(const glm::vec3 v[3]) {
  ShadowCertainty::TriangleTest t;
  const glm::dvec3 a(v[0]), b(v[1]), c(v[2]);
  glm::dvec3 n = glm::cross(b - a, c - a);
  double len = glm::length(n);
  t.magnitude = std::max({std::abs(v[0].x), std::abs(v[0].y), std::abs(v[0].z), std::abs(v[1].x), std::abs(v[1].y),
                          std::abs(v[1].z), std::abs(v[2].x), std::abs(v[2].y), std::abs(v[2].z)});
  if (!(len > 0.0) || !std::isfinite(len)) return t;
  n /= len;
  t.plane = glm::vec4(glm::vec3(n), static_cast<float>(glm::dot(n, a)));
  const glm::dvec3 corners[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 e0 = corners[k], e1 = corners[(k + 1) % 3];
    glm::dvec3 in = glm::cross(n, e1 - e0);  // into the triangle (counter-clockwise about n)
    double l = glm::length(in);
    if (!(l > 0.0)) return t;
    in /= l;
    t.edges[k] = glm::vec4(glm::vec3(in), static_cast<float>(glm::dot(in, e0)));
  }
  t.valid = true;
  return t;
}

ShadowCertainty::Texel emptyTexel() {
  ShadowCertainty::Texel t;
  for (int k = 0; k < ShadowCertainty::kCandidates; ++k) t.triangles[k] = ~0u, t.depths[k] = kInf;
  t.restDepth = kInf;
  return t;
}

bool sameLight(const shading::GpuLight& a, const shading::GpuLight& b) {
  return std::memcmp(&a, &b, sizeof(a)) == 0;
}

}  // namespace

void ShadowCertainty::clear() {
  ++generation_;
  maps_.clear();
  triangleBase_.clear();
  tests_.clear();
  blocksAll_.clear();
}

bool ShadowCertainty::builtFor(const FrameShading& frame) const {
  if (maps_.size() != frame.lights.size()) return false;
  for (std::size_t j = 0; j < maps_.size(); ++j)
    if (!sameLight(maps_[j].light, frame.lights[j])) return false;
  return true;
}

std::size_t ShadowCertainty::bytes() const {
  std::size_t b = triangleBase_.size() * sizeof(std::uint32_t) + tests_.size() * sizeof(TriangleTest) + blocksAll_.size();
  for (const Map& m : maps_) b += m.texels.size() * sizeof(Texel);
  return b;
}

void ShadowCertainty::build(const Scene& scene, const EmbreeScene& embree, const FrameShading& frame, int threads) {
  // The arrays keep their memory from build to build: a scene whose instances move every frame
  // rebuilds the maps every frame, and fresh pages would cost as much as the rasterization.
  ++generation_;
  triangleBase_.clear();
  tests_.clear();
  blocksAll_.clear();
  maps_.resize(frame.lights.size());
  for (std::size_t j = 0; j < maps_.size(); ++j) {
    std::vector<Texel> texels = std::move(maps_[j].texels);
    maps_[j] = Map{};
    maps_[j].texels = std::move(texels);
    maps_[j].light = frame.lights[j];
  }
  // Every triangle in render space, as Embree's instances place it.
  std::vector<Triangle> tris;
  std::uint64_t total = 0;
  triangleBase_.resize(scene.instances.size());
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    triangleBase_[i] = static_cast<std::uint32_t>(std::min<std::uint64_t>(total, ~0u));
    total += scene.meshes[scene.instances[i].mesh].triangleCount();
  }
  if (total >= ~0u || embree.instanceCount() != scene.instances.size()) {
    clear();  // ids would not fit: every ray is traced
    return;
  }
  tris.reserve(static_cast<std::size_t>(total));
  tests_.reserve(static_cast<std::size_t>(total));
  blocksAll_.reserve(static_cast<std::size_t>(total));
  glm::vec3 lo(kInf), hi(-kInf);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Mesh& mesh = scene.meshes[scene.instances[i].mesh];
    const glm::mat4& m = embree.transform(i).worldFromObject;
    // An exact solid's triangles are its raster proxy, which encloses the solid: a ray that misses them
    // misses the solid, but one that crosses them may still pass it by, so they never prove a shadow.
    bool blocks = !embree.letsRaysThrough(i) && !mesh.exact;
    const glm::vec3 tr = embree.transform(i).absTranslation;
    const glm::mat3& lin = embree.transform(i).absLinear;
    // The transform's translation (a render-space magnitude) and the largest term it scales by (object-space
    // rounding, brought to render space).
    const float translation = std::max({tr.x, tr.y, tr.z});
    const float scale = std::max({lin[0][0], lin[0][1], lin[0][2], lin[1][0], lin[1][1], lin[1][2], lin[2][0],
                                  lin[2][1], lin[2][2]});
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        tri.v[k] = glm::vec3(m * glm::vec4(mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]], 1.0f));
        lo = glm::min(lo, tri.v[k]);
        hi = glm::max(hi, tri.v[k]);
      }
      tri.id = triangleBase_[i] + static_cast<std::uint32_t>(t);
      tris.push_back(tri);
      tests_.push_back(makeTest(tri.v));
      // Embree tests rays in object space: its rounding follows the object-space coordinates and the
      // transform's translation as much as render space's, so the margin does too.
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = glm::abs(mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]]);
        tests_.back().magnitude = std::max(tests_.back().magnitude, scale * std::max(p.x, std::max(p.y, p.z)));
      }
      tests_.back().magnitude = std::max(tests_.back().magnitude, translation);
      tris.back().slack = kRelativeRounding * tests_.back().magnitude;
      blocksAll_.push_back(blocks ? 1 : 0);
    }
  }
  if (tris.empty()) {
    clear();
    return;
  }
  const float magnitude = std::max(glm::length(lo), glm::length(hi));
  const float diagonal = glm::length(hi - lo);

  struct Work {
    std::size_t map;
    int face, row0, row1;
  };
  std::vector<Work> work;
  for (std::size_t j = 0; j < maps_.size(); ++j) {
    Map& m = maps_[j];
    const shading::GpuLight& l = frame.lights[j];
    // An area light's rays go to points all over it: a map from one point proves nothing about them.
    if (!frame.castsShadows(j) || frame.isArea(j)) continue;
    if (static_cast<int>(l.posType.w + 0.5f) == TD_LIGHT_DIRECTIONAL) {
      glm::vec3 a = -glm::vec3(l.dirRange);
      if (!(glm::length(a) > 0.0f) || !std::isfinite(glm::length(a))) continue;
      a = glm::normalize(a);
      glm::vec3 s = glm::normalize(std::abs(a.x) < 0.9f ? glm::cross(a, glm::vec3(1, 0, 0)) : glm::cross(a, glm::vec3(0, 1, 0)));
      glm::vec3 t = glm::cross(a, s);
      glm::vec2 sLo(kInf), sHi(-kInf);
      float aHi = -kInf;
      for (const Triangle& tri : tris)
        for (const glm::vec3& v : tri.v) {
          glm::vec2 st(glm::dot(s, v), glm::dot(t, v));
          sLo = glm::min(sLo, st);
          sHi = glm::max(sHi, st);
          aHi = std::max(aHi, glm::dot(a, v));
        }
      m.kind = Kind::Ortho;
      m.size = kOrthoSize;
      m.axes[0][0] = s;
      m.axes[0][1] = t;
      m.axes[0][2] = a;
      m.centre = 0.5f * (sLo + sHi);
      float half = 0.5f * std::max(sHi.x - sLo.x, sHi.y - sLo.y);
      m.extent = withGuardBand(std::max(half, 1e-6f * std::max(magnitude, 1e-30f)), m.size);
      m.top = aHi + 0.01f * diagonal + 1e-6f * magnitude;
      m.depthEps = 1e-5f * diagonal + 4e-6f * magnitude;
      m.texels.assign(static_cast<std::size_t>(m.size) * m.size, emptyTexel());
      constexpr int kBands = 8;
      static_assert(kOrthoSize % (kBands * kBlock) == 0 && kCubeSize % kBlock == 0,
                    "bands of whole blocks: no block is written by two bands");
      for (int b = 0; b < kBands; ++b) work.push_back({j, 0, b * m.size / kBands, (b + 1) * m.size / kBands});
    } else {
      glm::vec3 light(l.posType);
      // The region near the light, within 4·nearZ of it: the part of a ray there may stray from its
      // texel's direction by more than the margin, so the maps leave it out (each face is clipped at
      // nearZ) and classify() tests the ray against every triangle in it instead. nearZ: a hundredth of
      // the scene, unless that region holds more than kNearLightMax triangles (then a quarter of the
      // distance to the nearest triangle, with none in it).
      std::vector<float> distance(tris.size());
      float nearest = kInf;
      for (std::size_t t = 0; t < tris.size(); ++t) {
        // (less its slack: where it may really lie)
        distance[t] = std::max(0.0f, glm::length(light - closestOnTriangle(light, tris[t].v[0], tris[t].v[1], tris[t].v[2])) -
                                         tris[t].slack);
        nearest = std::min(nearest, distance[t]);
      }
      if (!std::isfinite(nearest)) continue;
      float nearZ = 0.25f * nearest;
      const float wanted = 0.01f * diagonal;
      if (nearZ < wanted) {
        std::vector<std::uint32_t> within;
        for (std::size_t t = 0; t < tris.size() && within.size() <= kNearLightMax; ++t)
          if (!(distance[t] >= 4.0f * wanted)) within.push_back(tris[t].id);
        if (within.size() <= kNearLightMax) {
          nearZ = wanted;
          m.nearLight = std::move(within);
        }
      }
      if (!(nearZ > 0.0f)) continue;  // geometry at the light itself and too much around it: no map
      m.kind = Kind::Cube;
      m.size = kCubeSize;
      m.origin = light;
      m.nearZ = nearZ;
      m.extent = withGuardBand(1.0f, m.size);
      for (int f = 0; f < 6; ++f)
        for (int k = 0; k < 3; ++k) m.axes[f][k] = glm::vec3(kFaceAxes[f][k][0], kFaceAxes[f][k][1], kFaceAxes[f][k][2]);
      m.texels.assign(static_cast<std::size_t>(6) * m.size * m.size, emptyTexel());
      for (int f = 0; f < 6; ++f) work.push_back({j, f, 0, m.size});
    }
  }
  for (Map& m : maps_)
    if (m.kind == Kind::None) std::vector<Texel>().swap(m.texels);  // no map: no memory
  parallelIndices(threads, work.size(), [&](std::size_t w) {
    FaceRaster raster(maps_[work[w].map], work[w].face, work[w].row0, work[w].row1);
    for (const Triangle& tri : tris) raster.add(tri);
  });
}

ShadowAnswer ShadowCertainty::classify(std::size_t light, const ShadowPoint& hit, glm::vec3 originW, glm::vec3 dirW,
                                      float tFar) const {
  if (light >= maps_.size()) return ShadowAnswer::Unknown;
  const Map& m = maps_[light];
  if (m.kind == Kind::None || hit.instance >= triangleBase_.size()) return ShadowAnswer::Unknown;
  // The texel the ray starts in, and where its path across the map ends: the part of the ray the map
  // answers for projects to the straight segment between them (points project to points of the map
  // along straight lines), which must stay inside the texel's grown square.
  const float scale = static_cast<float>(m.size) / (2.0f * m.extent);
  int face = 0;
  glm::vec2 u0, u1;
  float depth, eps;
  if (m.kind == Kind::Cube) {
    const glm::vec3 d = originW - m.origin;
    face = cubeFace(d);
    const glm::vec3* axes = m.axes[face];
    const float a = glm::dot(axes[2], d), along = glm::dot(axes[2], dirW);
    // The ray's points nearer the light than nearZ (along the face's axis) lie within ~3.4·nearZ of it
    // when the origin is within nearZ / 4 of the hit: only the map's nearLight triangles are there, and
    // each is tested below. The rest of the ray, from the origin to tStar, is what the texel answers for.
    const float off = glm::length(originW - hit.posW);
    if (!(a > m.nearZ) || !(off < 0.25f * m.nearZ) || !(along < 0.0f)) return ShadowAnswer::Unknown;
    const float tStar = std::min(tFar, (m.nearZ - a) / along);
    const glm::vec3 e = d + tStar * dirW;
    const float eA = glm::dot(axes[2], e);
    if (!(eA > 0.0f)) return ShadowAnswer::Unknown;
    u0 = (glm::vec2(glm::dot(axes[0], d), glm::dot(axes[1], d)) / a + m.extent) * scale;
    u1 = (glm::vec2(glm::dot(axes[0], e), glm::dot(axes[1], e)) / eA + m.extent) * scale;
    depth = a;  // the ray's farthest point from the light is its origin
    eps = kDepthRel * a + 4e-6f * (glm::length(m.origin) + a);
  } else {
    // Towards a directional light the ray leaves the scene's slab at depth 0 (the map's top).
    const glm::vec3* axes = m.axes[0];
    const float a = glm::dot(axes[2], originW), along = glm::dot(axes[2], dirW);
    if (!(along > 0.0f)) return ShadowAnswer::Unknown;
    const glm::vec3 e = originW + std::max(0.0f, (m.top - a) / along) * dirW;
    u0 = (glm::vec2(glm::dot(axes[0], originW), glm::dot(axes[1], originW)) - m.centre + m.extent) * scale;
    u1 = (glm::vec2(glm::dot(axes[0], e), glm::dot(axes[1], e)) - m.centre + m.extent) * scale;
    depth = m.top - a;
    eps = m.depthEps;
  }
  if (!(u0.x >= 0.0f && u0.y >= 0.0f && u0.x < static_cast<float>(m.size) && u0.y < static_cast<float>(m.size)))
    return ShadowAnswer::Unknown;
  const glm::vec2 texel = glm::floor(u0);
  const glm::vec2 lo = texel - kQueryMargin, hi = texel + 1.0f + kQueryMargin;
  if (!(u1.x >= lo.x && u1.y >= lo.y && u1.x <= hi.x && u1.y <= hi.y)) return ShadowAnswer::Unknown;
  const std::size_t n = static_cast<std::size_t>(m.size);
  const Texel& t = m.texels[static_cast<std::size_t>(face) * n * n +
                            texelIndex(static_cast<int>(texel.x), static_cast<int>(texel.y), m.size)];
  // Margin of the exact tests (kRelativeMargin), relative to the magnitudes involved.
  float magnitude = std::max({std::abs(originW.x), std::abs(originW.y), std::abs(originW.z)});
  if (std::isfinite(tFar)) magnitude = std::max(magnitude, tFar * glm::length(dirW));
  // A point on an exact solid has no triangle of its own: every proxy triangle is tested (none blocks).
  const std::uint32_t own = hit.triangle == kExactTriangle ? ~0u : triangleBase_[hit.instance] + hit.triangle;
  bool missesAll = true;
  // The ray against one triangle: true when that decides the answer (shadowed).
  auto test = [&](std::uint32_t id) {
    // The hit's own triangle: the offset origin puts the ray on the far side of it from where it goes,
    // which is what every traced shadow ray relies on too (spawnOrigin).
    if (id == own) return false;
    const TriangleTest& tri = tests_[id];
    Crossing x = segmentVsTriangle(tri, originW, dirW, tFar, kRelativeMargin * std::max(magnitude, tri.magnitude));
    if (x == Crossing::Crosses && blocksAll_[id]) return true;
    if (x != Crossing::Misses) missesAll = false;
    return false;
  };
  for (std::uint32_t id : m.nearLight)
    if (test(id)) return ShadowAnswer::Shadowed;
  for (int k = 0; k < kCandidates; ++k) {
    const std::uint32_t id = t.triangles[k];
    if (id == ~0u) break;
    // In order of their depth bounds: from here on (and the rest) all lie behind the ray's every point.
    if (t.depths[k] > depth + eps) return missesAll ? ShadowAnswer::Lit : ShadowAnswer::Unknown;
    if (test(id)) return ShadowAnswer::Shadowed;
  }
  if (missesAll && t.restDepth > depth + eps) return ShadowAnswer::Lit;
  return ShadowAnswer::Unknown;
}

}  // namespace tandem::rt
