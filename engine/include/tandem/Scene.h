#pragma once
// The scene: plain data, independent of GL and Embree. The GL buffers and the Embree scene are caches
// derived from it by the Renderer. A flat list of instances (no graph): loaders flatten hierarchies.
//
// Spaces are in names: posW = world space, posO = object space; worldFromObject maps object to world.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/Camera.h"
#include "tandem/Solid.h"

namespace tandem {

/// Non-ambient lights a scene may hold. Ambient lights do not count (they sum into one Ia).
/// The limit comes from the per-pixel light-visibility mask and the per-light varyings of Gouraud
/// shading; loaders reject scenes with more.
inline constexpr int kMaxLights = 8;

enum class ShadingModel : std::uint8_t { Flat = 0, Gouraud = 1, Phong = 2, Toon = 3 };

enum class AlphaMode : std::uint8_t { Opaque = 0, Mask = 1, Blend = 2 };

/// Solid (3D) procedural patterns (docs/procedural.md; shaders/procedural.glsl): improved Perlin noise and what
/// is built on it. The numbers are shading.glsl's TD_PATTERN_* codes.
enum class Pattern : std::uint8_t { None = 0, Noise = 1, Fbm = 2, Turbulence = 3, Marble = 4, Wood = 5, Granite = 6 };

/// A procedural texture: a pattern value v in [0, 1] at each surface point, evaluated in the instance's
/// object space (it moves with the object) or in world space, which mixes the material's kd (v = 0) and kd2
/// (v = 1) and, with `bump` > 0, bends the shading normal by v's gradient (a height of bump·v along the normal).
struct ProceduralTexture {
  Pattern type = Pattern::None;
  bool worldSpace = false;
  float scale = 1.0f;       // pattern features per unit (the frequency of the first octave), > 0
  float turbulence = 1.0f;  // how far noise perturbs marble's veins and wood's rings, >= 0
  int octaves = 4;          // 1..8: octaves of fBm and turbulence
  float bump = 0.0f;        // bump amplitude in the pattern's space units (0: no bump)
  bool operator==(const ProceduralTexture&) const = default;
};

/// One step of a cartoon ramp: N·L at or above `threshold` gives `level` (the highest matching step wins).
struct ToonStep {
  float threshold = 0.0f;  // N·L in [-1, 1]
  float level = 0.0f;      // diffuse factor, usually in [0, 1]
};

/// A material's ramp unless it names its own: dark, mid and lit bands.
inline constexpr ToonStep kDefaultToonRamp[] = {{-1.0f, 0.15f}, {0.1f, 0.55f}, {0.6f, 1.0f}};

/// Whitted / Phong material. Colours are linear RGB.
/// Local shading: I = ka·Ia + Σj vis_j·[kd·Idj·max(N·Lj,0) + ks·Isj·max(Rj·V,0)^ns] + emission.
/// Whitted sum:   I = local + kr·S + kt·T (or the Fresnel-weighted form, see FrameSettings::fresnelWeighted).
struct Material {
  std::string name;
  glm::vec3 ka{0.1f};   // ambient reflectance
  glm::vec3 kd{0.8f};   // diffuse reflectance (multiplied by the texture and vertex colour when present)
  int kdTexture = -1;   // index into Scene::textures (sRGB-encoded), -1 for none
  glm::vec3 ks{0.0f};   // specular reflectance of the highlight
  float ns = 32.0f;     // specular exponent, >= 0
  float kr = 0.0f;      // mirror reflectance in [0, 1]: weight of the reflected ray S
  float kt = 0.0f;      // transmittance in [0, 1]: weight of the refracted ray T
  float ior = 1.5f;     // index of refraction of the inside (the outside is 1)
  // Glossy reflection and transmission (docs/glossy.md): the S and T rays are sampled from a lobe around the
  // mirror and refracted directions, glTF's roughness (α = roughness², a Phong lobe of exponent 2/α² − 2);
  // 0 is the perfect mirror and sharp refraction. In [0, 1].
  float roughness = 0.0f;
  glm::vec3 emission{0.0f};
  ShadingModel shading = ShadingModel::Phong;
  // (From a named array: GCC 12 at -O1 takes the temporary array behind a braced list for uninitialized.)
  std::vector<ToonStep> toonRamp = std::vector<ToonStep>(std::begin(kDefaultToonRamp), std::end(kDefaultToonRamp));
  // Procedural checkerboard (the Whitted floor): kd and kd2 alternate in squares of 1/checkerFrequency
  // texture units; 0 turns it off.
  glm::vec3 kd2{0.0f};
  float checkerFrequency = 0.0f;
  // Procedural 3D texture (docs/procedural.md): kd and kd2 mixed by the pattern, and its bump map. Not with the
  // checker.
  ProceduralTexture procedural;
  // Material features of glTF 2.0 (docs/gltf.md), which JSON scene files may set too. Each default
  // changes nothing, so a material that does not set them renders as it would without them.
  int normalTexture = -1;       // tangent-space normal map, linear
  float normalScale = 1.0f;
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  float opacity = 1.0f;         // base alpha
  bool unlit = false;           // KHR_materials_unlit: colour = kd, no lights
  // false (glTF's single-sided, its default there): the back faces of an opaque material are culled in the
  // raster and passed by rays (passedFromBehind below; a transmissive one stays a surface from both sides: a
  // closed glass volume). Both sides are surfaces by default, as every scene file's faces were before.
  bool doubleSided = true;
  glm::mat3 uvTransform{1.0f};  // KHR_texture_transform applied to uv before sampling
  int emissiveTexture = -1;     // sRGB, multiplies `emission` (glTF emissiveTexture); -1 for none
  // Colour filter on the transmitted ray T (glTF: transmission is tinted by the base colour). Applied to
  // the material's kt·T part only, not to light passing uncovered parts of a BLEND surface.
  glm::vec3 transmissionTint{1.0f};
};

/// Whether the raster culls this material's back faces and rays pass them (docs/gltf.md, "Single-sided
/// faces"): single-sided and opaque. A transmissive single-sided face is a surface from both sides in both,
/// since a closed glass volume refracts at its inner faces.
inline bool passedFromBehind(const Material& m) { return !m.doubleSided && !(m.kt > 0.0f); }

struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba8;  // width*height*4, top row first
  bool srgb = true;                 // colour textures are sRGB; normal maps are linear
};

/// Triangle mesh in object space. Vertex attributes other than positions may be empty; indices are
/// triangles (3 per face) and always valid (< positions.size()): loaders check before building one.
struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;   // unit or empty (then faces are flat)
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec4> tangents;  // xyz tangent, w handedness; for normal maps
  std::vector<glm::vec4> colors;    // linear vertex colours
  std::vector<std::uint32_t> indices;
  /// An exact solid (docs/csg.md): the rays see it, analytically, instead of the triangles, which are then the
  /// raster's proxy — a tessellation that covers the solid's silhouette (the pixels the frame resolves by
  /// ray). Empty: the triangles are the surface.
  std::optional<solid::Solid> exact;
  std::size_t triangleCount() const { return indices.size() / 3; }
  /// Bytes its arrays hold (what the loaders charge to their budget).
  std::size_t bytes() const {
    return name.size() + positions.size() * sizeof(glm::vec3) + normals.size() * sizeof(glm::vec3) +
           uvs.size() * sizeof(glm::vec2) + tangents.size() * sizeof(glm::vec4) + colors.size() * sizeof(glm::vec4) +
           indices.size() * sizeof(std::uint32_t);
  }
};

enum class LightType : std::uint8_t { Ambient = 0, Point = 1, Spot = 2, Directional = 3, Rect = 4, Disk = 5, Sphere = 6 };

/// Whether a light has an extent (rect, disk, sphere): it is sampled, and its shadows are soft.
inline bool isAreaLight(LightType t) { return t == LightType::Rect || t == LightType::Disk || t == LightType::Sphere; }

/// A light. Radiance reaching a point: color·intensity·attenuation(d)·cone.
///   attenuation(d) = 1 / (c + l·d + q·d²), and 0 beyond `range` when range > 0 (point, spot, area lights);
///   cone = smoothstep(cos(outer), cos(inner), cos angle to dirW) (spot).
/// Ambient lights contribute color·intensity to Ia only; directional lights have no position.
/// Area lights (docs/area-lights.md) are point lights spread over a surface: each patch dA of it is a point
/// light of intensity L·cosθ·dA, attenuated by its own distance, with the radiance L = color·intensity / A⊥
/// (A⊥ = the area of a rect or disk, πr² for a sphere). So `intensity` is the light's intensity along its
/// normal whatever its size, and as the size goes to 0 a sphere becomes the point light at posW, a rect or
/// disk the point light times the cosine to its normal (a one-sided Lambertian emitter facing dirW).
struct Light {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  glm::vec3 posW{0.0f};
  glm::vec3 dirW{0.0f, -1.0f, 0.0f};  // direction the light travels (spot axis, directional rays); unit
  float range = 0.0f;                  // 0 = unbounded
  glm::vec3 attenuation{1.0f, 0.0f, 0.0f};  // constant, linear, quadratic
  float innerConeDeg = 20.0f;
  float outerConeDeg = 30.0f;
  bool castShadows = true;
  glm::vec2 size{1.0f};                // rect: width and height (world units)
  float radius = 0.5f;                 // disk and sphere
  glm::vec3 upW{0.0f, 1.0f, 0.0f};     // rect: the direction of its height, projected onto its plane

  bool operator==(const Light&) const = default;
};

/// A mesh placed in the world with one material. `dynamic` marks an instance that moves (the loaders set
/// it for animated nodes); any instance may move (Renderer::setInstanceTransform), which updates the
/// top level of the ray scene and never rebuilds a mesh's BVH.
struct Instance {
  std::string name;
  std::uint32_t mesh = 0;
  std::uint32_t material = 0;
  glm::mat4 worldFromObject{1.0f};
  bool dynamic = false;
  /// Motion blur (docs/motion-blur.md): how the instance moves while the camera's shutter is open, a rigid
  /// motion about its own origin (worldFromObject's translation): world units per second, and radians per
  /// second about the world axis along angularVelocity. worldFromObject is its place at the middle of the
  /// exposure. Zero (the default) is an instance at rest.
  glm::vec3 velocity{0.0f};
  glm::vec3 angularVelocity{0.0f};
};

/// An equirectangular environment image (docs/environment.md): linear radiance, `width()`×`height()` texels,
/// the top row first. Row centres run from straight up (+Y) to straight down; the column centre u = 0.5
/// looks along −Z, u = 0.75 along +X. Immutable once made: its irradiance is projected once, here.
class EnvironmentMap {
 public:
  /// Asserts width, height > 0 and texels.size() == width·height (loaders check before making one).
  EnvironmentMap(int width, int height, std::vector<glm::vec3> texels);
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<glm::vec3>& texels() const { return texels_; }
  /// The image's ambient light: its irradiance over π (a uniform radiance L gives L) as nine spherical-
  /// harmonic coefficients, evaluated by shading.glsl's tdShAmbient; of the image unscaled and unturned.
  const std::array<glm::vec3, 9>& ambientSh() const { return ambientSh_; }

 private:
  int width_, height_;
  std::vector<glm::vec3> texels_;
  std::array<glm::vec3, 9> ambientSh_;
};

/// What rays that leave the scene see, and the ambient light it sheds (docs/environment.md).
struct Environment {
  enum class Kind {
    Background,  // Scene::background in every direction; lights nothing (a JSON scene's default)
    Sky,         // a gradient from the ground through the horizon to the zenith (glTF files' default)
    Map,         // an equirectangular image (a .hdr file)
  };
  Kind kind = Kind::Background;
  glm::vec3 zenith{0.42f, 0.47f, 0.55f};  // Sky: linear radiance straight up,
  glm::vec3 horizon{0.60f, 0.60f, 0.60f}; // along the horizon,
  glm::vec3 ground{0.17f, 0.16f, 0.15f};  // and below it (from a little under the horizon down)
  std::shared_ptr<const EnvironmentMap> map;  // Map (shared: copies of the scene share its texels)
  float intensity = 1.0f;    // Sky and Map: their radiance is scaled by it
  float rotationDeg = 0.0f;  // Sky and Map: turned about +Y (counter-clockwise seen from above)
  /// Sky and Map: the ambient term takes the environment's irradiance, added to the ambient lights'.
  bool lightsAmbient = true;
};

/// Defaults that a scene file may give for rendering it (the command line overrides them).
struct SceneRenderDefaults {
  int width = 1280;
  int height = 720;
  std::string preset;  // empty: the application's default (tandem-render: hybrid-full); the Renderer reads none of this
  int maxDepth = -1;   // -1 = the preset's
  int radiosity = -1;  // FrameSettings::radiosity: -1 = the application's (tandem-render: off), 0 off, 1 on
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;  // includes ambient lights
  std::vector<Instance> instances;
  Camera camera;
  glm::vec3 background{0.0f};  // linear radiance of rays that escape (Environment::Kind::Background)
  Environment environment;
  SceneRenderDefaults render;

  /// Sum of ambient lights (color·intensity): Ia of the formula.
  glm::vec3 ambientIntensity() const;
  /// Non-ambient lights, in scene order; index j here is bit j of the light-visibility mask.
  std::vector<const Light*> directLights() const;
  std::size_t triangleCount() const;
};

/// Checks that indices are in range, the light count is within kMaxLights, references resolve and
/// numbers are finite. Loaders call it; the Renderer refuses a scene that fails it.
struct Error;
template <class T> class Result;
Result<void> validateScene(const Scene& scene);
/// The per-light part of validateScene (Renderer::setLight checks a light with it): finite values, no
/// negative colour, intensity, size or radius, a direction where the type needs one. The error names `id`.
Result<void> validateLight(const Light& light, const std::string& id);

/// Pairs of instances whose faces lie in one plane, overlap and can be seen doing so: they fight for the same
/// depth, so the shared area flickers between the two surfaces. Faces looking the same way always count;
/// faces back to back (a box standing exactly on a floor) only when one of the two materials lets light
/// through (kt > 0, alpha), since otherwise neither can be seen from the other's side. Checked where it is
/// cheap: meshes made of at most `maxPlanes` planes (boxes, planes, quads); curved meshes are skipped. One
/// message per pair, naming both instances and the plane. The scene file loader logs them as warnings;
/// applications that build scenes in code can call it themselves.
std::vector<std::string> coplanarOverlaps(const Scene& scene, std::size_t maxPlanes = 32);

}  // namespace tandem
