#pragma once
// Progressive refinement radiosity (Cohen, Chen, Wallace and Greenberg 1988) on the scene's meshes, for the
// two-pass frame (docs/radiosity.md): diffuse interreflection from here, shown per vertex by the raster and
// read at the ray pass's hits; direct and specular light stay the frame's own.
//
// Patches: each triangle of every instance cut into n × n sub-triangles (the grid of core/Radiosity.h), n
// from a target patch area; each patch has two sides. Reflectance: the material's kd (× its texture's and
// vertex colours' mean); emission: the material's. The analytic lights' direct light, with shadow rays,
// is the first unshot light; ambient lights are what the solution replaces and play no part.
//
// Form factors (receiver j from shooter i): the mean over j of the exact point-to-polygon form factor of i
// (Lambert's contour integral, i clipped to the point's hemisphere; a 3-point rule, on finer parts of j
// where i is near), times the fraction of rays from j's points to points of i that Embree finds
// unobstructed. With exact
// point form factors, every receiver's form factors in a closed scene sum to 1 (up to the quadrature),
// so the furnace holds at any patch size.
//
// Not thread-safe: one thread calls shoot(); shoot() runs its receivers on the TBB arena.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/Radiosity.h"
#include "rt/EmbreeScene.h"
#include "tandem/Scene.h"

namespace tandem::rt {

struct RadiosityOptions {
  /// Largest patch area (world units²); 0: the scene's surface area over targetPatches.
  float patchArea = 0.0f;
  int targetPatches = 2048;
  int maxSegments = 64;  // n is at most this per triangle (n² patches)
  /// Visibility rays per receiver–shooter pair: 4, then this many where the first 4 disagree (a shadow edge).
  int visibilityRays = 16;
  /// Direct-light points per patch side (each with a shadow ray per light; area lights: one point of the
  /// light each).
  int lightSamples = 16;
  /// Memory for the form factors of patches already shot (a patch is shot several times as light keeps
  /// arriving): past it, a patch's form factors are computed again at each of its shots.
  std::size_t cacheBytes = std::size_t{256} << 20;
  /// Segments n per triangle (instance-major, each mesh's triangle order), for a refined solve
  /// (RadiositySolver::refinedSegments); empty: from the patch area.
  std::vector<int> segments;
  /// Set (by another thread) to abandon the solver: its loops then skip their work, leaving a state to throw
  /// away, so that a background solve stops within a moment even in the middle of its set-up or a shot.
  const std::atomic<bool>* cancel = nullptr;
};

/// One side of one patch. Positions are in render space (EmbreeScene::anchor()).
struct RadiosityPatch {
  std::uint32_t instance = 0, triangle = 0;
  glm::vec3 cornerW[3];
  glm::vec3 normalW{0.0f, 1.0f, 0.0f};  // unit, towards this side
  float area = 0.0f;
  glm::vec3 reflectance{0.0f};
  glm::vec3 emission{0.0f};
  glm::vec3 centreW() const { return (cornerW[0] + cornerW[1] + cornerW[2]) * (1.0f / 3.0f); }
};

/// Exact form factor from the point x with unit normal n to the planar convex polygon `corners` (count <= 4),
/// clipped to x's hemisphere: Lambert's formula, in double precision. 0 when nothing of it is above x's plane.
double pointToPolygonFormFactor(glm::dvec3 x, glm::dvec3 n, const glm::dvec3* corners, int count);

class RadiositySolver {
 public:
  /// Cuts the scene into patches and gathers the lights' direct light at them (the first unshot light):
  /// shadow rays through `embree`, which must be built from `scene` and outlive the solver.
  RadiositySolver(const Scene& scene, const EmbreeScene& embree, const RadiosityOptions& options = {});

  /// Shoots the patch with the most unshot power, up to `maxShots` times while the residual is above
  /// `residualTarget`; returns the shots taken.
  int shoot(int maxShots, float residualTarget = 0.0f);
  /// Unshot power (gained or, after relight, lost) over the power that entered the solution (emission and
  /// reflected direct light): 1 before the first shot, 0 when nothing is left to distribute.
  float residual() const;
  std::size_t shots() const { return shots_; }
  std::size_t patchCount() const { return patches_.size(); }
  const RadiosityPatch& patch(std::size_t p) const { return patches_[p]; }
  /// The patch's radiosity B (emission + reflected direct + reflected indirect) and indirect irradiance H.
  glm::vec3 radiosity(std::size_t p) const { return radiosity_[p]; }
  glm::vec3 indirect(std::size_t p) const { return indirect_[p]; }
  glm::vec3 direct(std::size_t p) const { return direct_[p]; }
  /// The scene's lights changed (the geometry did not): the change of each patch's direct light becomes
  /// unshot light, negative where it lost some, and the next shots carry the solution over to the new
  /// lights with the form factors already made (incremental radiosity, Chen 1990).
  void relight(const Scene& scene);
  /// Adaptive refinement: each triangle's segments, doubled where the solution shown across it (its grid
  /// vertices, welded to its neighbours') steps by more than `threshold` times the mean indirect light — a
  /// gradient or the edge of a shadow in the indirect light — steepest first, as long as the patches stay
  /// under `maxPatches`. Solve again with RadiosityOptions::segments set to it.
  std::vector<int> refinedSegments(float threshold, std::size_t maxPatches) const;
  /// The frame's refinement (FrameSettings::radiosityRefine): steps over half the mean indirect light, within
  /// twice the patches. Measured on the Cornell box (docs/radiosity.md): lower thresholds refine nearly every
  /// triangle there, for little.
  static constexpr float kRefineStep = 0.5f;
  static constexpr std::size_t kRefineGrowth = 2;
  /// Segments of each triangle (refinedSegments' order).
  std::vector<int> segments() const {
    std::vector<int> out;
    for (const GridTriangle& g : triangles_) out.push_back(g.n);
    return out;
  }
  /// The form factor from receiver patch j to shooter patch i, with visibility, as shoot() uses it.
  float formFactor(std::size_t receiver, std::size_t shooter) const;
  /// The solution per grid vertex (patch values averaged at each vertex, across the triangles of an
  /// instance that share it with a normal within 25 degrees), with the unshot light's ambient estimate.
  RadiosityField field() const;

 private:
  void gatherDirect(const Scene& scene);
  std::vector<glm::vec3> directLight(const Scene& scene) const;  // per patch side, the lights' irradiance
  double enteredPower() const;  // Σ luminance(emission + ρ·direct)·area
  void buildLayout(const Scene& scene);
  bool visible(glm::vec3 fromW, glm::vec3 fromN, glm::vec3 toW, glm::vec3 toN) const;
  bool cancelled() const { return options_.cancel && options_.cancel->load(std::memory_order_relaxed); }

  const EmbreeScene& embree_;
  RadiosityOptions options_;
  std::vector<RadiosityPatch> patches_;  // side s of sub-triangle e is patch 2e + s
  // The grid: per covered triangle, its instance, n and first patch; per instance, its first triangle.
  struct GridTriangle {
    std::uint32_t instance = 0, triangle = 0;
    int n = 1;
    std::size_t firstPatch = 0;  // sub-triangle k of the grid: patches firstPatch + 2k, +2k+1
  };
  std::vector<GridTriangle> triangles_;
  std::vector<std::size_t> instanceFirst_;   // index into triangles_, or SIZE_MAX
  // The field's layout (buildLayout): its table, its value count, and per value slot the slots it is
  // averaged with (weldMembers_[weldStart_[v] .. weldStart_[v + 1]]).
  std::vector<glm::uvec2> table_;
  std::size_t valueCount_ = 0;
  std::vector<std::uint32_t> weldStart_, weldMembers_;
  std::vector<std::size_t> instanceTriangles_;
  std::vector<glm::vec3> radiosity_, indirect_, direct_, unshot_;
  std::vector<std::vector<float>> rows_;  // per shooter: its form factors, one per receiver (empty: not kept)
  std::size_t cachedBytes_ = 0;
  double enteredPower_ = 0.0;  // Σ (emission + reflected direct) · area, in luminance
  glm::vec3 meanReflectance_{0.0f};
  std::size_t shots_ = 0;
};

}  // namespace tandem::rt
