#pragma once
// One pixel's ray tree, for debugging a frame: every ray the ray pass followed for that pixel (the
// primary hit, shadow rays, reflection and refraction), what each hit, the weights of each Whitted sum
// and what every ray added to the pixel. Made by Renderer::tracePixel, which re-runs the pass's own
// recursion for that one pixel (as pbrt re-renders a single pixel), so the numbers are the frame's.
//
//   FrameStats stats = renderer->render(camera, settings);
//   if (auto trace = renderer->tracePixel(640, 360)) std::cout << toText(*trace, renderer->scene());
//
// Positions are in world space; colours are linear radiance before exposure and the tone map.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "tandem/FrameStats.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem {

enum class TraceRayKind : std::uint8_t { Primary = 0, Shadow = 1, Reflection = 2, Refraction = 3 };

/// How the visibility of one direct light at a hit was decided (its bit of the light mask).
enum class LightVisibility : std::uint8_t {
  Unoccluded,      // a shadow ray reached the light
  Occluded,        // a shadow ray hit something first
  CastsNoShadows,  // the light's castShadows is off: visible, no ray
  CannotReach,     // behind the surface, outside a spot cone or beyond range: no ray (it adds nothing)
  AtThePoint,      // a point light at the point itself: visible, no ray
  NotFinite,       // the ray's origin or direction was not finite: visible, no ray
  MapSaysLit,      // hybrid shadows: the light-space map proves the ray reaches the light: visible, no ray
  MapSaysShadowed, // hybrid shadows: the map proves something blocks it: not visible, no ray
  NotTraced,       // this hit's shadows are not by rays this frame (shadows off, or the shadow map's at a
                   // primary hit with raster shadows): the rays' shading counts the light as visible
};

/// Why a secondary ray of a hit was not followed.
enum class SecondaryRay : std::uint8_t {
  Traced,
  NotByRays,             // the effect is off or raster this frame (or no material of the scene needs it)
  DepthLimit,            // the hit is maxDepth bounces deep
  NoWeight,              // its weight is 0: no kr and no Fresnel reflection, no kt, or total internal reflection
  BelowMinContribution,  // throughput × weight < minContribution
};

/// One direct light at a hit, in Scene::directLights() order.
struct TraceLight {
  std::uint32_t light = 0;  // index into Scene::directLights(): bit `light` of the light mask
  LightVisibility visibility = LightVisibility::NotTraced;
  bool visible = true;      // the bit the local term was shaded with
  // The shadow ray, when one was traced (Unoccluded, Occluded).
  glm::vec3 originW{0.0f};
  glm::vec3 dirW{0.0f};
  float tFar = 0.0f;
};

/// One ray of the tree and, when it hit something, the hit and its Whitted sum.
struct TraceNode {
  TraceRayKind kind = TraceRayKind::Primary;
  int depth = 0;     // bounces before this ray: 0 for the primary ray
  int parent = -1;   // index into PixelTrace::nodes; -1 for a primary ray
  glm::vec3 originW{0.0f};
  glm::vec3 dirW{0.0f};
  float tNear = 0.0f;
  float tFar = 0.0f;
  /// The weight its radiance gets in the parent's sum: wR (grey) for a reflection, the wT vector for a
  /// refraction (each over N for one of a glossy hit's N rays), 1 for a primary ray; throughput is the product of weights along the path (the value
  /// minContribution is tested against).
  glm::vec3 weight{1.0f};
  float throughput = 1.0f;

  bool hit = false;  // false: the ray escaped and brings the background
  std::uint32_t instance = 0;
  std::uint32_t triangle = 0;
  std::uint32_t material = 0;
  /// Distance along dirW to the hit: Embree's t, or for a hybrid frame's primary ray (whose triangle
  /// comes from the raster pass, not Embree) the distance to the resolved point.
  float t = 0.0f;
  glm::vec3 positionW{0.0f};
  glm::vec3 geometricNormalW{0.0f};  // Ng and N after the two-sided flip (towards the ray's origin)
  glm::vec3 shadingNormalW{0.0f};
  bool backFace = false;  // the ray arrived at the back of the triangle (leaving a closed object)
  glm::vec2 barycentrics{0.0f};  // b1, b2 (b0 = 1 − b1 − b2)
  float coverage = 1.0f;  // BLEND coverage a (1 otherwise)

  std::vector<TraceLight> lights;
  std::uint32_t lightMask = ~0u;  // the visibility bits the local term was shaded with
  glm::vec3 local{0.0f};          // emission + ambient + Σ visible lights (× coverage)

  // The Whitted sum at the hit (docs/shading.md): I = local + wR·S + wT·T.
  bool sumEvaluated = false;  // false: the hit spawns no secondary ray (depth limit or no ray effect);
                              // the weights below are still the ones the sum would use
  float fresnel = 0.0f;       // F at the hit (1 under total internal reflection; 0 without kt)
  bool totalInternal = false;
  float reflectWeight = 0.0f;            // a·wR
  glm::vec3 transmitWeight{0.0f};        // tdTransmitWeight(a, wT, tint)
  SecondaryRay reflection = SecondaryRay::NotByRays;
  SecondaryRay refraction = SecondaryRay::NotByRays;
  int reflectionChild = -1;   // node index of the (first) reflected ray, when traced
  int refractionChild = -1;
  /// Every reflected and refracted ray, in the order traced: one each, or glossSamples at a glossy primary
  /// hit (docs/glossy.md), whose contributions (weight wR/N or wT/N) add up to reflected and transmitted.
  std::vector<int> reflectionChildren, refractionChildren;
  glm::vec3 reflected{0.0f};    // wR·S: what the reflected rays added (0 when not traced)
  glm::vec3 transmitted{0.0f};  // wT·T

  /// The radiance along this ray: local + reflected + transmitted on a hit, the background on a miss.
  glm::vec3 radiance{0.0f};
  /// What it adds to its parent's sum: weight ⊙ radiance (the primary ray: its radiance).
  glm::vec3 contribution{0.0f};
};

struct PixelTrace {
  int x = 0, y = 0;           // the pixel asked for, in the output image (row 0 at the top)
  int width = 0, height = 0;  // the frame
  bool reference = false;     // a reference frame: primary visibility by camera rays, `samples` per pixel
  int samples = 1;
  /// Hybrid frames: the ray-grid pixel that covers (x, y) (rayScale > 1: the grid is 1/rayScale of the
  /// frame) and the frame pixel whose visibility ids and camera ray it was traced with.
  int rayScale = 1;
  int gridX = 0, gridY = 0;
  int tracedX = 0, tracedY = 0;
  FrameSettings settings;   // the frame's (resolved)
  bool rayPass = false;     // the frame ran the hybrid ray pass (false: raster-only or reference)

  std::vector<TraceNode> nodes;  // depth first: a node's children follow it
  std::vector<int> roots;        // the primary rays: one per sample (hybrid: one)

  /// What the pixel's sum is made of, as the frame computed it. Hybrid: the composite's
  /// I = local + wR·S + wT·T, where local is the CPU twin of the GL shade pass's term (equal within
  /// float rounding, docs/shading.md) and reflected, transmitted and lightMask are exactly the ray pass's
  /// outputs for the grid pixel. Reference: color is the mean of the samples, exactly the frame's (with
  /// several samples the parts are means too, and lightMask is the first sample's).
  glm::vec3 local{0.0f};
  glm::vec3 reflected{0.0f};
  glm::vec3 transmitted{0.0f};
  std::uint32_t lightMask = ~0u;
  glm::vec3 color{0.0f};
  RayCounts rays;  // the rays this pixel traced (hybrid: the primary hit counts as one)

  /// Where the frame's pixel has parts the trace does not recompute (a shadow map, reflection probes,
  /// the upsampling of a reduced ray grid, a debug view), one line each; empty when `color` is the frame's.
  std::vector<std::string> notes;
};

/// The tree as indented text, one line per ray, hit, light and sum, names taken from `scene` (the
/// scene the frame was rendered from).
std::string toText(const PixelTrace& trace, const Scene& scene);

std::string_view toString(TraceRayKind kind);
std::string_view toString(LightVisibility visibility);
std::string_view toString(SecondaryRay reason);

}  // namespace tandem
