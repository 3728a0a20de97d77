#include "rt/SurfaceShading.h"

#include <bit>
#include <cassert>
#include <cmath>
#include <limits>

#include "core/Procedural.h"
#include "core/Sampling.h"
#include "core/Solids.h"
#include "rt/RayMath.h"

namespace tandem::rt {

using namespace tandem::shading;

CameraRays::CameraRays(const Camera& camera, glm::ivec2 size)
    : pos_(camera.posW),
      jitter_(camera.jitterPx),
      sizeX_(float(size.x)),
      sizeY_(float(size.y)),
      aspect_(float(size.x) / float(size.y)),
      tanHalf_(std::tan(glm::radians(camera.yFovDeg) * 0.5f)),
      halfH_(camera.orthoHeight * 0.5f),
      orthographic_(camera.orthographic) {
  forward_ = glm::normalize(camera.targetW - camera.posW);
  right_ = glm::normalize(glm::cross(forward_, camera.upW));
  up_ = glm::cross(right_, forward_);
  time_ = std::clamp(std::isfinite(camera.timeU) ? camera.timeU : 0.5f, 0.0f, 1.0f);
  // Camera::lensOffsetW's rules: a finite positive aperture on a perspective camera with a plane in focus.
  if (camera.aperture > 0.0f && std::isfinite(camera.aperture) && !camera.orthographic) {
    lensRadius_ = 0.5f * camera.aperture;
    focus_ = camera.focusPlane();
    if (!(focus_ > 0.0f) || !std::isfinite(focus_)) lensRadius_ = 0.0f;
    lensUv_ = camera.lensUv;
  }
}

Ray CameraRays::throughLens(glm::vec2 pixel, glm::vec2 lensU) const {
  Ray r = through(pixel);
  if (lensRadius_ <= 0.0f) return r;
  // The centre's ray meets the plane in focus at depth focus_ along forward_.
  const glm::vec3 focusW = r.origin + r.dir * (focus_ / glm::dot(r.dir, forward_));
  const glm::vec2 u(std::isfinite(lensU.x) ? lensU.x : 0.5f, std::isfinite(lensU.y) ? lensU.y : 0.5f);
  const glm::vec2 d = lensRadius_ * squareToDisk(glm::clamp(u, 0.0f, 1.0f));
  r.origin += right_ * d.x + up_ * d.y;
  r.dir = glm::normalize(focusW - r.origin);
  return r;
}

InstanceTransform makeInstanceTransform(const glm::mat4& worldFromObject, glm::vec3 anchor) {
  InstanceTransform t;
  t.worldFromObject = toRenderSpace(worldFromObject, anchor);
  glm::mat3 m(worldFromObject);
  // A singular transform (scale 0 on an axis) has no inverse; its normals fall back to Ng per hit.
  float det = glm::determinant(m);
  t.normalWorldFromObject = std::isfinite(det) && det != 0.0f ? glm::transpose(glm::inverse(m)) : glm::mat3(0.0f);
  t.absLinear = glm::mat3(glm::abs(t.worldFromObject[0]), glm::abs(t.worldFromObject[1]), glm::abs(t.worldFromObject[2]));
  t.absTranslation = glm::abs(glm::vec3(t.worldFromObject[3]));
  t.anchor = anchor;
  return t;
}

FrameShading::FrameShading(const Scene& scene, std::optional<ShadingModel> shadingOverride, glm::vec3 anchor) {
  for (const Light* l : scene.directLights()) {
    lights.push_back(packLight(*l, areaLights));
    if (isAreaLight(l->type)) ++areaLights;
    lights.back().posType = glm::vec4(toRenderSpace(l->posW, anchor), lights.back().posType.w);
  }
  materials.reserve(scene.materials.size());
  toonRamps.resize(scene.materials.size());
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    materials.push_back(packMaterial(scene.materials[i], static_cast<int>(i), shadingOverride));
    bakeToonRamp(scene.materials[i], toonRamps[i].data());
  }
  ambient = scene.ambientIntensity();
  environment = EnvironmentLookup(scene);
  roughness.reserve(scene.materials.size());
  for (const Material& m : scene.materials) roughness.push_back(m.roughness);
}

void FrameShading::setGlossSampling(int samples, std::uint32_t sampleIndex) {
  glossSamples = std::clamp(samples, 1, 32);
  glossBase = sampleIndex * static_cast<std::uint32_t>(glossSamples);
}

float glossExponent(float roughness) {
  if (!(roughness > 0.0f)) return std::numeric_limits<float>::infinity();
  const double alpha = static_cast<double>(roughness) * static_cast<double>(roughness);
  const double e = std::max(2.0 / (alpha * alpha) - 2.0, 0.0);
  // Below roughness ~1e-10 the exponent leaves float's range: a mirror.
  return e > static_cast<double>(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
                                                                    : static_cast<float>(e);
}

glm::vec3 glossyDirection(glm::vec3 axis, float roughness, glm::vec2 u, glm::vec3 side) {
  if (!(roughness > 0.0f)) return axis;
  const double e = static_cast<double>(glossExponent(roughness));
  if (std::isinf(e)) return axis;
  // 1 − cos θ = 1 − u^(1/(e+1)) = −expm1(ln u / (e + 1)): exact for the narrow lobes of small roughness,
  // where cos θ rounds to 1. u.x = 0 is the lobe's rim direction at the most.
  const double ux = std::max(static_cast<double>(u.x), 1e-12);
  const double oneMinusCos = -std::expm1(std::log(ux) / (e + 1.0));
  const double sinT = std::sqrt(std::max(oneMinusCos * (2.0 - oneMinusCos), 0.0));
  const double cosT = 1.0 - oneMinusCos;
  const double phi = 6.283185307179586 * static_cast<double>(u.y);
  // An orthonormal frame around the axis (Duff et al. 2017).
  const glm::dvec3 w(axis);
  const double sgn = w.z >= 0.0 ? 1.0 : -1.0;
  const double a = -1.0 / (sgn + w.z);
  const double b = w.x * w.y * a;
  const glm::dvec3 t1(1.0 + sgn * w.x * w.x * a, sgn * b, -sgn * w.x);
  const glm::dvec3 t2(b, sgn + w.y * w.y * a, -w.y);
  glm::dvec3 d = t1 * (sinT * std::cos(phi)) + t2 * (sinT * std::sin(phi)) + w * cosT;
  const glm::dvec3 n(side);
  const double across = glm::dot(d, n);
  if (!(across > 0.0)) d -= 2.0 * across * n;  // mirrored back over the facet
  const double len = glm::length(d);
  return len > 0.0 && std::isfinite(len) ? glm::vec3(d / len) : axis;
}

void FrameShading::setLightSampling(int primary, int deeper, std::uint32_t sampleIndex) {
  for (auto [sampling, count] : {std::pair{&primaryLight, primary}, std::pair{&deeperLight, deeper}}) {
    sampling->count = std::clamp(count, 1, TD_MAX_LIGHT_SAMPLES);
    sampling->base = sampleIndex * static_cast<std::uint32_t>(sampling->count);
  }
}

namespace {

// sRGB → linear for every 8-bit value, with the GLSL twin's decode so CPU and GL agree.
const std::array<float, 256>& srgbTable() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[static_cast<std::size_t>(i)] = tdSrgbDecode1(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table;
}

glm::vec4 texel(const Texture& t, int x, int y) {
  std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(t.width) + static_cast<std::size_t>(x)) * 4;
  const std::uint8_t* p = &t.rgba8[i];
  if (t.srgb) {
    const auto& lut = srgbTable();
    return {lut[p[0]], lut[p[1]], lut[p[2]], static_cast<float>(p[3]) / 255.0f};
  }
  return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
}

int wrap(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

template <class T>
T interpolate(const std::vector<T>& attr, const SurfaceHit& h) {
  return h.bary.x * attr[h.vertex[0]] + h.bary.y * attr[h.vertex[1]] + h.bary.z * attr[h.vertex[2]];
}

}  // namespace

glm::vec4 sampleBilinear(const Texture& texture, glm::vec2 uv) {
  if (texture.width <= 0 || texture.height <= 0 ||
      texture.rgba8.size() < static_cast<std::size_t>(texture.width) * static_cast<std::size_t>(texture.height) * 4)
    return glm::vec4(1.0f);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  // Texel centres at (i + 0.5) / size; keep the coordinate small so the float fraction stays exact.
  float fx = (uv.x - std::floor(uv.x)) * static_cast<float>(texture.width) - 0.5f;
  float fy = (uv.y - std::floor(uv.y)) * static_cast<float>(texture.height) - 0.5f;
  float x0f = std::floor(fx), y0f = std::floor(fy);
  float tx = fx - x0f, ty = fy - y0f;
  int x0 = wrap(static_cast<int>(x0f), texture.width), x1 = wrap(static_cast<int>(x0f) + 1, texture.width);
  int y0 = wrap(static_cast<int>(y0f), texture.height), y1 = wrap(static_cast<int>(y0f) + 1, texture.height);
  glm::vec4 top = glm::mix(texel(texture, x0, y0), texel(texture, x1, y0), tx);
  glm::vec4 bottom = glm::mix(texel(texture, x0, y1), texel(texture, x1, y1), tx);
  return glm::mix(top, bottom, ty);
}

namespace {

/// The material's procedural texture at the hit (shaders/procedural.glsl, as shade.frag evaluates it), at `posO`
/// in object space or at the world position: its value, and its bump map bending the shading normal (the
/// gradient brought to world space as normals are; before the two-sided flip, as normal maps).
void applyProcedural(const Material& m, const InstanceTransform& transform, glm::vec3 posO, SurfaceHit& h) {
  const ProceduralTexture& t = m.procedural;
  if (t.type == Pattern::None) return;
  const glm::vec3 p = t.worldSpace ? h.posW + transform.anchor : posO;
  const glm::vec4 v = tdPattern(static_cast<int>(t.type), p, t.scale, t.turbulence, t.octaves);
  h.pattern = v.x;
  if (t.bump > 0.0f) {
    const glm::vec3 g(v.y, v.z, v.w);
    h.normalW = tdBumpNormal(h.normalW, t.worldSpace ? g : transform.normalWorldFromObject * g, t.bump);
  }
}

/// The exact hit of a ray on an instance's exact solid (Mesh::exact, docs/csg.md): its first crossing past
/// `tNear`, found in double precision in the solid's space as the ray pass's user geometry finds it, the
/// crossing's normal through the instance's normal matrix. No uvs or vertex attributes. False when the ray
/// passes by (the raster's proxy covered the pixel, the solid does not).
bool resolveExact(const Scene& scene, const InstanceTransform& transform, std::uint32_t instance, const Ray& ray,
                  float tNear, SurfaceHit& h) {
  const Instance& inst = scene.instances[instance];
  const Mesh& mesh = scene.meshes[inst.mesh];
  const glm::dmat4 objectFromWorld = glm::inverse(glm::dmat4(transform.worldFromObject));
  const solid::Ray objectRay{glm::dvec3(objectFromWorld * glm::dvec4(glm::dvec3(ray.origin), 1.0)),
                             glm::dmat3(objectFromWorld) * glm::dvec3(ray.dir)};
  solid::Crossing c;
  if (!solid::firstHit(solid::intersect(*mesh.exact, objectRay), tNear, std::numeric_limits<double>::infinity(), c))
    return false;
  h.instance = instance;
  h.triangle = kExactTriangle;
  h.material = inst.material;
  const glm::dvec3 posD = glm::dvec3(ray.origin) + c.t * glm::dvec3(ray.dir);
  h.posW = glm::vec3(posD);
  for (int i = 0; i < 3; ++i) h.vertexW[i] = h.posW;
  h.bary = glm::vec3(1.0f, 0.0f, 0.0f);
  // Rounding to float is the position's error; the transform's terms bound the solid's own.
  const glm::vec3 objectPos(glm::dvec3(objectFromWorld * glm::dvec4(posD, 1.0)));
  h.posMagnitude = glm::max(glm::abs(h.posW), transform.absLinear * glm::abs(objectPos) + transform.absTranslation);
  h.eyeW = ray.origin;
  h.toEyeW = -ray.dir;
  const glm::dvec3 n = glm::dmat3(glm::transpose(objectFromWorld)) * c.normal;
  const double len = glm::length(n);
  h.geomNormalW = len > 0.0 && std::isfinite(len) ? glm::vec3(n / len) : h.toEyeW;
  h.normalW = h.geomNormalW;
  applyProcedural(scene.materials[h.material], transform, objectPos, h);
  if (glm::dot(h.geomNormalW, h.toEyeW) < 0.0f) {
    h.backFace = true;
    h.geomNormalW = -h.geomNormalW;
    h.normalW = -h.normalW;
  }
  h.lightSeed = tdHash(std::bit_cast<std::uint32_t>(h.posW.x) ^
                       tdHash(std::bit_cast<std::uint32_t>(h.posW.y) ^ tdHash(std::bit_cast<std::uint32_t>(h.posW.z))));
  return true;
}

}  // namespace

namespace {

// The triangle's part of a hit, shared by resolveHit and resolvePrimaryPoint so that both give a point to the
// bit: the vertices in world space, the ray's barycentrics, the position and its error scale, the plane's
// normal and the interpolated vertex normal (as the mesh has it: no normal map, not yet facing the viewer).
void resolveTriangle(const Mesh& mesh, const InstanceTransform& transform, std::uint32_t triangle, const Ray& ray,
                     std::uint32_t (&vertex)[3], glm::vec3 (&vertexW)[3], glm::vec3& bary, ShadowPoint& p) {
  assert(triangle < mesh.triangleCount());
  for (int i = 0; i < 3; ++i) {
    vertex[i] = mesh.indices[3 * static_cast<std::size_t>(triangle) + static_cast<std::size_t>(i)];
    vertexW[i] = glm::vec3(transform.worldFromObject * glm::vec4(mesh.positions[vertex[i]], 1.0f));
  }
  bary = triangleBarycentrics(ray.origin, ray.dir, vertexW[0], vertexW[1], vertexW[2]);
  p.posW = bary.x * vertexW[0] + bary.y * vertexW[1] + bary.z * vertexW[2];
  // Error scale of posW: the interpolation's terms and, before them, the transform's (|M|·|p| + |t|,
  // larger than |vertexW| when the transform cancels a large object-space coordinate).
  glm::vec3 mag[3];
  for (int i = 0; i < 3; ++i)
    mag[i] = transform.absLinear * glm::abs(mesh.positions[vertex[i]]) + transform.absTranslation;
  p.posMagnitude = interpolationMagnitude(bary, mag[0], mag[1], mag[2]);

  // The plane's normal in double: a needle triangle's edge vectors are nearly parallel and their float
  // cross product can point anywhere, sending offsets and the inside/outside test the wrong way.
  glm::dvec3 ngD = glm::cross(glm::dvec3(vertexW[1]) - glm::dvec3(vertexW[0]),
                              glm::dvec3(vertexW[2]) - glm::dvec3(vertexW[0]));
  double ngLen = glm::length(ngD);
  // A zero-area triangle has no plane: face the ray so shading and offsets stay finite.
  p.geomNormalW = ngLen > 0.0 && std::isfinite(ngLen) ? glm::vec3(ngD / ngLen) : -ray.dir;
  p.normalW = p.geomNormalW;
  if (!mesh.normals.empty()) {
    const glm::vec3 nO =
        bary.x * mesh.normals[vertex[0]] + bary.y * mesh.normals[vertex[1]] + bary.z * mesh.normals[vertex[2]];
    glm::vec3 n = transform.normalWorldFromObject * nO;
    float len = glm::length(n);
    if (len > 0.0f && std::isfinite(len)) p.normalW = n / len;
  }
}

// Two-sided lighting: a point seen from behind its counter-clockwise front is lit like a front. True when
// the normals were flipped.
bool faceTheViewer(ShadowPoint& p, glm::vec3 toEyeW) {
  if (!(glm::dot(p.geomNormalW, toEyeW) < 0.0f)) return false;
  p.geomNormalW = -p.geomNormalW;
  p.normalW = -p.normalW;
  return true;
}

}  // namespace

bool primaryNeedsWholeHit(const Scene& scene, const FrameShading& frame, std::uint32_t instance, bool secondaryRays) {
  const Instance& inst = scene.instances[instance];
  const Mesh& mesh = scene.meshes[inst.mesh];
  const Material& m = scene.materials[inst.material];
  // Wavefront::spawn's test; coverage is 1 unless BLEND, where it is the texture's at the point.
  const bool spawns = secondaryRays && (m.alphaMode == AlphaMode::Blend ||
                                        !spawnsNoRay(frame.materials[inst.material].krKtIorModel, 1.0f));
  const bool normalMapped = m.normalTexture >= 0 && !mesh.tangents.empty() && !mesh.uvs.empty();
  const bool bumped = m.procedural.type != Pattern::None && m.procedural.bump > 0.0f;
  return mesh.exact || spawns || normalMapped || bumped;
}

ShadowPoint resolvePrimaryPoint(const Scene& scene, const InstanceTransform& transform, glm::uvec2 id, const Ray& ray) {
  ShadowPoint p;
  p.instance = id.x - 1;
  p.triangle = id.y;
  assert(p.instance < scene.instances.size());
  const Instance& inst = scene.instances[p.instance];
  p.material = inst.material;
  std::uint32_t vertex[3];
  glm::vec3 vertexW[3], bary;
  resolveTriangle(scene.meshes[inst.mesh], transform, p.triangle, ray, vertex, vertexW, bary, p);
  faceTheViewer(p, -ray.dir);
  return p;
}

SurfaceHit resolveHit(const Scene& scene, const InstanceTransform& transform, std::uint32_t instance,
                      std::uint32_t triangle, const Ray& ray, float tNear) {
  assert(instance < scene.instances.size());
  const Instance& inst = scene.instances[instance];
  const Mesh& mesh = scene.meshes[inst.mesh];
  // One named result on every path, so it is built in the caller's slot (a second named one would make
  // the return a copy of the ~200-byte record per hit).
  SurfaceHit h;
  if (mesh.exact) {
    if (resolveExact(scene, transform, instance, ray, tNear, h)) return h;
    h = SurfaceHit{};  // whatever the solid's test wrote
    // Past the solid (Embree and this disagree only on a grazing ray): the proxy's triangle, as before; a
    // hit named as the solid's (kExactTriangle) takes the proxy's first.
    if (triangle == kExactTriangle) triangle = 0;
  }
  h.instance = instance;
  h.triangle = triangle;
  h.material = inst.material;
  resolveTriangle(mesh, transform, triangle, ray, h.vertex, h.vertexW, h.bary, h);
  h.eyeW = ray.origin;
  h.toEyeW = -ray.dir;
  if (!mesh.uvs.empty()) {
    glm::vec2 uv = interpolate(mesh.uvs, h);
    const Material& m = scene.materials[h.material];
    h.uv = glm::vec2(m.uvTransform * glm::vec3(uv, 1.0f));
  }
  const Material& m = scene.materials[h.material];
  if (m.normalTexture >= 0 && !mesh.tangents.empty() && !mesh.uvs.empty()) {
    // Tangent-space normal map (glTF): perturb N in the frame (T, B, N), T re-orthogonalised against N.
    // The formula is shading.glsl's tdPerturbNormal, which GL's shade pass calls too.
    glm::vec4 t4 = interpolate(mesh.tangents, h);
    glm::vec3 t = glm::mat3(transform.worldFromObject) * glm::vec3(t4);
    glm::vec3 tn = glm::vec3(sampleBilinear(scene.textures[static_cast<std::size_t>(m.normalTexture)], h.uv)) * 2.0f - 1.0f;
    glm::vec3 n = tdPerturbNormal(h.normalW, t, t4.w, tn, m.normalScale);
    if (isFinite(n)) h.normalW = n;
  }
  if (m.procedural.type != Pattern::None) applyProcedural(m, transform, interpolate(mesh.positions, h), h);
  h.backFace = faceTheViewer(h, h.toEyeW);
  float texA = 1.0f;
  if (m.kdTexture >= 0) {
    glm::vec4 kd = sampleBilinear(scene.textures[static_cast<std::size_t>(m.kdTexture)], h.uv);
    h.tint = glm::vec3(kd);
    texA = kd.a;
  }
  // BLEND coverage only: MASK holes are decided by the visibility pass (and Embree's filter).
  if (m.alphaMode == AlphaMode::Blend) h.coverage = tdCoverage(packMaterial(m, 0, std::nullopt), texA);
  // Emissive texture, only with uvs, like GL's shade pass; the index is checked (validateScene does not).
  if (m.emissiveTexture >= 0 && static_cast<std::size_t>(m.emissiveTexture) < scene.textures.size() && !mesh.uvs.empty())
    h.emissionTint = glm::vec3(sampleBilinear(scene.textures[static_cast<std::size_t>(m.emissiveTexture)], h.uv));
  if (!mesh.colors.empty()) h.tint *= glm::vec3(interpolate(mesh.colors, h));
  h.lightSeed = tdHash(std::bit_cast<std::uint32_t>(h.posW.x) ^
                       tdHash(std::bit_cast<std::uint32_t>(h.posW.y) ^ tdHash(std::bit_cast<std::uint32_t>(h.posW.z))));
  return h;
}

FrameShading FrameShading::forFrame(const Scene& scene, const FrameSettings& settings, std::uint32_t sampleIndex,
                                   glm::vec3 anchor, const RadiosityField* radiosity) {
  FrameShading frame(scene, settings.shadingOverride, anchor);
  frame.setLightSampling(settings.lightSamples, settings.unfilteredLightSamples(), sampleIndex);
  frame.setGlossSampling(settings.glossSamples, sampleIndex);
  if (settings.gi == GlobalIllumination::Path) {
    frame.ambient = glm::vec3(0.0f);  // docs/path-tracing.md
    frame.environment = EnvironmentLookup(scene, false);  // (its paths gather the environment's light)
  } else if (radiosity && !radiosity->empty()) {
    frame.radiosity = radiosity;  // in place of the ambient term where it covers a surface (docs/radiosity.md)
  }
  return frame;
}

glm::vec3 shadeLocal(const Scene& scene, const FrameShading& frame, const InstanceTransform& transform,
                     const SurfaceHit& hit, std::uint32_t visibleLights, const AreaSampleBits* areaSamples, int depth) {
  const GpuMaterial& m = frame.materials[hit.material];
  glm::vec3 emission = glm::vec3(m.emissionFlags) * hit.emissionTint;
  glm::vec3 c = tdSurfaceColor(m, hit.uv, hit.pattern, hit.tint);
  // BLEND: the covered fraction of the surface shades; the rest is the ray pass's straight-through T.
  if (m.emissionFlags.w > 0.5f) return hit.coverage * (c + emission);
  int model = static_cast<int>(m.krKtIorModel.w + 0.5f);
  // Diffuse interreflection: the radiosity solution where it covers the surface, else the ambient term (the
  // environment's light at the normal the lights see: a flat face's own).
  glm::vec3 h;
  const glm::vec3 ambientN = model == TD_MODEL_FLAT ? hit.geomNormalW : hit.normalW;
  glm::vec3 color = emission + (frame.radiosity && frame.radiosity->at(hit.instance, hit.triangle, hit.bary, hit.backFace, h)
                                    ? tdRadiosityTerm(m, h, hit.uv, hit.pattern, hit.tint)
                                    : tdAmbient(m, frame.ambient + frame.environment.ambient(ambientN), hit.uv,
                                                hit.pattern, hit.tint));
  glm::vec3 ks(m.ksNs);
  float ns = m.ksNs.w;
  const auto& ramp = frame.toonRamps[hit.material];

  // Gouraud: the per-vertex normals, flipped with the pixel's two-sided flip. An exact solid has no vertices:
  // its three are the hit itself with the solid's normal (shade.frag's twin), so Gouraud shades it per pixel.
  glm::vec3 vertexNormalW[3];
  if (model == TD_MODEL_GOURAUD && hit.triangle == kExactTriangle) {
    for (glm::vec3& n : vertexNormalW) n = hit.geomNormalW;
  } else if (model == TD_MODEL_GOURAUD) {
    const Mesh& mesh = scene.meshes[scene.instances[hit.instance].mesh];
    for (int i = 0; i < 3; ++i) {
      glm::vec3 n = hit.geomNormalW;
      if (!mesh.normals.empty()) {
        glm::vec3 t = transform.normalWorldFromObject * mesh.normals[hit.vertex[i]];
        float len = glm::length(t);
        if (len > 0.0f && std::isfinite(len)) n = (hit.backFace ? -t : t) / len;
      }
      vertexNormalW[i] = n;
    }
  }
  glm::vec3 n = model == TD_MODEL_FLAT ? hit.geomNormalW : hit.normalW;

  // Gouraud's per-vertex eye directions.
  glm::vec3 vertexToEye[3];
  if (model == TD_MODEL_GOURAUD)
    for (int i = 0; i < 3; ++i) {
      glm::vec3 toEye = hit.eyeW - hit.vertexW[i];
      float len = glm::length(toEye);
      vertexToEye[i] = len > 0.0f ? toEye / len : hit.toEyeW;
    }

  for (std::size_t j = 0; j < frame.lights.size(); ++j) {
    if (!(visibleLights & (1u << j))) continue;
    const GpuLight& light = frame.lights[j];
    if (frame.isArea(j)) {
      // The mean over the frame's samples, each where its shadow ray got through (shade.frag's twin).
      const std::uint32_t bits = areaSamples ? (*areaSamples)[static_cast<std::size_t>(frame.areaSlot(j))] : ~0u;
      const LightSampling& sampling = frame.lightAt(depth);
      glm::vec3 sum(0.0f);
      for (int k = 0; k < sampling.count; ++k) {
        if (!((bits >> k) & 1u)) continue;
        glm::vec3 toLight;
        float dist;
        if (model == TD_MODEL_GOURAUD) {
          for (int i = 0; i < 3; ++i) {
            glm::vec3 e = areaLightSample(frame, sampling, j, hit.lightSeed, hit.vertexW[i], k, toLight, dist);
            sum += hit.bary[i] * tdShadeLight(c, ks, ns, model, vertexNormalW[i], vertexToEye[i], e, toLight, 0.0f);
          }
          continue;
        }
        glm::vec3 e = areaLightSample(frame, sampling, j, hit.lightSeed, hit.posW, k, toLight, dist);
        float toon = model == TD_MODEL_TOON ? ramp[static_cast<std::size_t>(toonRampIndex(glm::dot(n, toLight)))] : 0.0f;
        sum += tdShadeLight(c, ks, ns, model, n, hit.toEyeW, e, toLight, toon);
      }
      color += sum * (1.0f / static_cast<float>(sampling.count));
      continue;
    }
    if (model == TD_MODEL_GOURAUD) {
      glm::vec3 sum(0.0f);
      for (int i = 0; i < 3; ++i) {
        glm::vec3 toLight;
        float dist;
        glm::vec3 e = tdLightIncident(light, hit.vertexW[i], toLight, dist);
        sum += hit.bary[i] * tdShadeLight(c, ks, ns, model, vertexNormalW[i], vertexToEye[i], e, toLight, 0.0f);
      }
      color += sum;
      continue;
    }
    glm::vec3 toLight;
    float dist;
    glm::vec3 e = tdLightIncident(light, hit.posW, toLight, dist);
    float toon = model == TD_MODEL_TOON ? ramp[static_cast<std::size_t>(toonRampIndex(glm::dot(n, toLight)))] : 0.0f;
    color += tdShadeLight(c, ks, ns, model, n, hit.toEyeW, e, toLight, toon);
  }
  return hit.coverage * color;
}

}  // namespace tandem::rt
