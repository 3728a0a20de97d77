#include "tandem/HeavyScene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "tandem/Primitives.h"

namespace tandem {

namespace {

// The fixed objects: mirror and glass spheres fine enough that their silhouettes and refractions look
// round at 1280×720, and the mirror panel (a box).
constexpr int kFixedSegments = 48;
constexpr std::size_t kBoxTriangles = 12;
constexpr std::size_t kMinFloorTriangles = 2;
constexpr int kMinSegments = 4;  // makeSphere's smallest closed sphere with rings = segments / 2

/// Triangles of makeSphere(r, s, s / 2): two caps of s triangles and s·(rings − 2) quads.
std::size_t sphereTriangles(int segments) {
  auto s = static_cast<std::size_t>(segments);
  return s * (s - 2);
}

std::size_t fixedTriangles(const HeavySceneOptions& o) {
  std::size_t n = 0;
  if (o.mirrors) n += sphereTriangles(kFixedSegments) + kBoxTriangles;
  if (o.glass) n += sphereTriangles(kFixedSegments);
  return n;
}

std::size_t gridCount(const HeavySceneOptions& o) {
  auto side = static_cast<std::size_t>(std::max(1, o.gridSide));
  return side * side;
}

/// Largest even segment count whose sphere fits in `budget` triangles (at least kMinSegments).
int segmentsFor(std::size_t budget) {
  int s = kMinSegments;
  while (sphereTriangles(s + 2) <= budget) s += 2;
  return s;
}

/// A floor in XZ facing +Y with exactly `triangles` triangles: row-major quads of a grid, the last row
/// partial, and a half quad when the count is odd. This is where the exact count comes from.
Mesh makeExactFloor(std::size_t triangles, float size) {
  Mesh m;
  m.name = "heavy-floor";
  std::size_t quads = triangles / 2, halves = triangles % 2;
  std::size_t slots = quads + halves;
  auto cols = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(slots))));
  cols = std::max<std::size_t>(cols, 1);
  std::size_t rows = (slots + cols - 1) / cols;
  float dx = size / static_cast<float>(cols), dz = size / static_cast<float>(rows);
  for (std::size_t j = 0; j <= rows; ++j)
    for (std::size_t i = 0; i <= cols; ++i) {
      float x = -0.5f * size + dx * static_cast<float>(i), z = -0.5f * size + dz * static_cast<float>(j);
      m.positions.push_back({x, 0.0f, z});
      m.normals.push_back({0.0f, 1.0f, 0.0f});
      m.uvs.push_back({x + 0.5f * size, z + 0.5f * size});  // world units: checker frequency = squares per unit
    }
  auto at = [cols](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(j * (cols + 1) + i); };
  for (std::size_t q = 0; q < slots; ++q) {
    std::size_t i = q % cols, j = q / cols;
    // Counter-clockwise seen from +Y (the face normal is +Y).
    m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
    if (q < quads) m.indices.insert(m.indices.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
  }
  return m;
}

std::uint32_t add(std::vector<Mesh>& v, Mesh m) {
  v.push_back(std::move(m));
  return static_cast<std::uint32_t>(v.size() - 1);
}
std::uint32_t add(std::vector<Material>& v, Material m) {
  v.push_back(std::move(m));
  return static_cast<std::uint32_t>(v.size() - 1);
}
void place(Scene& s, std::uint32_t mesh, std::uint32_t material, glm::mat4 worldFromObject, std::string name) {
  Instance i;
  i.name = std::move(name);
  i.mesh = mesh;
  i.material = material;
  i.worldFromObject = worldFromObject;
  s.instances.push_back(std::move(i));
}
glm::mat4 at(glm::vec3 t) { return glm::translate(glm::mat4(1.0f), t); }

void addFloor(Scene& s, std::size_t floorTriangles, float side) {
  Material floor;
  floor.name = "checker";
  floor.kd = {0.85f, 0.85f, 0.85f};
  floor.kd2 = {0.15f, 0.15f, 0.18f};
  floor.checkerFrequency = 0.5f;
  floor.ks = glm::vec3(0.1f);
  std::uint32_t floorMaterial = add(s.materials, floor);
  place(s, add(s.meshes, makeExactFloor(floorTriangles, 6.0f * side + 20.0f)), floorMaterial, glm::mat4(1.0f),
        "floor");
}

// The grid, shading models mixed. Each sphere gets its own mesh (no instancing), so the triangle count
// is also what Embree builds and stores, not only what the rasterizer draws.
void addSphereGrid(Scene& s, int segments, int gridSide) {
  const Mesh sphere = makeSphere(1.0f, segments, segments / 2);
  const glm::vec3 colours[] = {{0.8f, 0.25f, 0.2f}, {0.2f, 0.6f, 0.3f}, {0.25f, 0.35f, 0.85f}, {0.85f, 0.7f, 0.2f}};
  const ShadingModel models[] = {ShadingModel::Phong, ShadingModel::Gouraud, ShadingModel::Toon, ShadingModel::Flat};
  std::uint32_t gridMaterials[4];
  for (int i = 0; i < 4; ++i) {
    Material m;
    m.name = "grid-" + std::to_string(i);
    m.kd = colours[i];
    m.ks = glm::vec3(0.4f);
    m.ns = 48.0f;
    m.shading = models[i];
    gridMaterials[i] = add(s.materials, m);
  }
  const int g = std::max(1, gridSide);
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i) {
      glm::vec3 p(3.0f * (static_cast<float>(i) - 0.5f * static_cast<float>(g - 1)), 1.0f,
                  3.0f * (static_cast<float>(j) - 0.5f * static_cast<float>(g - 1)) - 2.0f);
      place(s, add(s.meshes, sphere), gridMaterials[(i + j) % 4], at(p), "sphere-" + std::to_string(j * g + i));
    }
}

void addMirrors(Scene& s, float side, float front) {
  Material mirror;
  mirror.name = "mirror";
  mirror.kd = glm::vec3(0.05f);
  mirror.ks = glm::vec3(0.8f);
  mirror.ns = 200.0f;
  mirror.kr = 0.85f;
  std::uint32_t mm = add(s.materials, mirror);
  place(s, add(s.meshes, makeSphere(1.5f, kFixedSegments, kFixedSegments / 2)), mm, at({-2.5f, 1.5f, front}),
        "mirror-sphere");
  place(s, add(s.meshes, makeBox({3.0f * side + 2.0f, 4.0f, 0.2f})), mm, at({0.0f, 2.0f, -1.5f * side - 5.0f}),
        "mirror-panel");
}

void addGlassSphere(Scene& s, float front) {
  Material glass;
  glass.name = "glass";
  glass.kd = glm::vec3(0.0f);
  glass.ka = glm::vec3(0.0f);
  glass.ks = glm::vec3(0.9f);
  glass.ns = 300.0f;
  glass.kr = 0.0f;
  glass.kt = 0.95f;
  glass.ior = 1.5f;
  std::uint32_t gm = add(s.materials, glass);
  place(s, add(s.meshes, makeSphere(1.5f, kFixedSegments, kFixedSegments / 2)), gm, at({2.5f, 1.5f, front}),
        "glass-sphere");
}

std::vector<Light> heavySceneLights() {
  Light ambient;
  ambient.name = "ambient";
  ambient.type = LightType::Ambient;
  ambient.intensity = 0.2f;
  Light point;
  point.name = "point";
  point.type = LightType::Point;
  point.posW = {0.0f, 8.0f, 4.0f};
  point.intensity = 0.6f;
  Light spot;
  spot.name = "spot";
  spot.type = LightType::Spot;
  spot.posW = {-6.0f, 9.0f, 6.0f};
  spot.dirW = glm::normalize(glm::vec3(6.0f, -9.0f, -8.0f));
  spot.intensity = 0.5f;
  spot.innerConeDeg = 25.0f;
  spot.outerConeDeg = 35.0f;
  Light sun;
  sun.name = "sun";
  sun.type = LightType::Directional;
  sun.dirW = glm::normalize(glm::vec3(0.3f, -1.0f, -0.4f));
  sun.intensity = 0.5f;
  return {ambient, point, spot, sun};
}

}  // namespace

std::size_t heavySceneMinTriangles(const HeavySceneOptions& options) {
  return fixedTriangles(options) + gridCount(options) * sphereTriangles(kMinSegments) + kMinFloorTriangles;
}

Scene makeHeavyScene(std::size_t targetTriangles, const HeavySceneOptions& options) {
  const std::size_t target = std::max(targetTriangles, heavySceneMinTriangles(options));
  const std::size_t grid = gridCount(options);
  const std::size_t free = target - fixedTriangles(options) - kMinFloorTriangles;
  float share = std::clamp(options.sphereShare, 0.0f, 1.0f);
  int segments = segmentsFor(static_cast<std::size_t>(static_cast<double>(free) * static_cast<double>(share)) / grid);
  // The floor takes whatever the spheres leave, so the total is exact.
  std::size_t floorTriangles = target - fixedTriangles(options) - grid * sphereTriangles(segments);

  Scene s;
  s.name = "heavy-" + std::to_string(target);
  s.background = {0.05f, 0.07f, 0.10f};
  const float side = static_cast<float>(std::max(1, options.gridSide));
  addFloor(s, floorTriangles, side);
  addSphereGrid(s, segments, options.gridSide);
  const float front = 1.5f * side + 1.0f;
  if (options.mirrors) addMirrors(s, side, front);
  if (options.glass) addGlassSphere(s, front);
  s.lights = heavySceneLights();

  s.camera.posW = {0.0f, 6.0f, front + 9.0f};
  s.camera.targetW = {0.0f, 1.0f, -1.0f};
  s.camera.yFovDeg = 50.0f;
  s.camera.nearZ = 0.1f;
  s.render.width = 640;
  s.render.height = 360;
  return s;
}

}  // namespace tandem
