// Reuse across frames when the camera stands still and something moves (rt/RayReuse.h, docs/reuse.md).
// The oracle is the pass without reuse: each frame is traced twice, once keeping the frame before's
// answers and once from nothing on a second tracer, and the outputs must agree bit for bit. The scenes
// are built to catch a kept answer that tracing would change: an occluder moving into and out of shadow
// rays, a thin slab teleported across the light, a light that moves, contacts, and the same at 1e-4 and
// 1e4 scale and far from the origin. Each also checks that answers were kept, so none passes by keeping
// none.
#include <cstring>
#include <functional>

#include <gtest/gtest.h>

#include "RtTestScenes.h"
#include "rt/RayReuse.h"

namespace tandem::rt::test {
namespace {

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

TEST(RayReuse, RayMeetsBoxByTheSlabs) {
  const ReuseBox box{glm::dvec3(-1.0), glm::dvec3(1.0)};
  // Through it, stopping short of it, starting inside, leaving it behind, and axis-parallel rays whose
  // other coordinates lie inside or outside the slabs (a zero direction component).
  EXPECT_TRUE(ReuseGate::rayMeetsBox({-5, 0, 0}, {1, 0, 0}, 10.0, box));
  EXPECT_FALSE(ReuseGate::rayMeetsBox({-5, 0, 0}, {1, 0, 0}, 3.9, box));
  EXPECT_TRUE(ReuseGate::rayMeetsBox({-5, 0, 0}, {1, 0, 0}, 4.0, box)) << "touching the face counts";
  EXPECT_TRUE(ReuseGate::rayMeetsBox({0.5, 0.5, 0.5}, {0, 1, 0}, 0.01, box));
  EXPECT_FALSE(ReuseGate::rayMeetsBox({-5, 0, 0}, {-1, 0, 0}, INFINITY, box));
  EXPECT_TRUE(ReuseGate::rayMeetsBox({-5, 0.99, -0.99}, {1, 0, 0}, INFINITY, box));
  EXPECT_FALSE(ReuseGate::rayMeetsBox({-5, 1.01, 0}, {1, 0, 0}, INFINITY, box));
  const glm::dvec3 diagonal = glm::normalize(glm::dvec3(1, 1, 1));
  EXPECT_TRUE(ReuseGate::rayMeetsBox({-3, -3, -3}, diagonal, INFINITY, box));
  // Passing beside a corner: the x and y slabs' spans do not overlap.
  EXPECT_FALSE(ReuseGate::rayMeetsBox({-3, 0.5, 0}, glm::normalize(glm::dvec3(1, -1, 0)), INFINITY, box));
}

TEST(RayReuse, InstanceBoxHoldsTheMovedMeshWithAMarginThatFollowsTheCoordinates) {
  const ReuseBox unit{glm::dvec3(-0.5), glm::dvec3(0.5)};
  for (const double far : {0.0, 1e4, 1e7}) {
    SCOPED_TRACE(far);
    const glm::mat4 t = glm::rotate(translate(glm::vec3(static_cast<float>(far), 2.0f, 0.0f)), 0.7f, glm::vec3(0, 1, 0));
    ReuseBox box;
    ASSERT_TRUE(ReuseGate::instanceBox(unit, t, glm::dvec3(far, 0.0, 0.0), box));
    // Every corner of the transformed cube lies inside, strictly (the margin), in render space.
    for (int k = 0; k < 8; ++k) {
      const glm::dvec4 c((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5, 1.0);
      const glm::dvec3 p = glm::dvec3(glm::dmat4(t) * c) - glm::dvec3(far, 0.0, 0.0);
      for (int a = 0; a < 3; ++a) {
        EXPECT_LT(box.lo[a], p[a]);
        EXPECT_GT(box.hi[a], p[a]);
      }
    }
    // The margin (the rotation is about y: the y extent is the cube's) grows with the translation, as
    // Embree's rounding does, and stays a small fraction of it.
    const double margin = box.hi.y - 2.5;
    EXPECT_GT(margin, 0.0);
    EXPECT_LT(margin, 1e-3 * std::max(far, 3.0));
  }
  // An empty mesh has no box.
  ReuseBox none;
  EXPECT_FALSE(ReuseGate::instanceBox({glm::dvec3(1.0), glm::dvec3(-1.0)}, glm::mat4(1.0f), glm::dvec3(0.0), none));
}

// A floor, a sphere on it, a box in contact with it and a thin slab above, under a point light and a
// directional light; `scale` and `offset` move the whole scene (camera and lights included).
struct Stage {
  Scene scene;
  std::uint32_t sphere = 0, box = 0, slab = 0;
  float scale = 1.0f;
  glm::vec3 offset{0.0f};
  glm::mat4 at(glm::vec3 p) const {
    return translate(p * scale + offset) * glm::scale(glm::mat4(1.0f), glm::vec3(scale));
  }
};

Stage makeStage(float scale, glm::vec3 offset) {
  Stage st;
  st.scale = scale;
  st.offset = offset;
  Scene& s = st.scene;
  const std::uint32_t mat = addMaterial(s, diffuse(glm::vec3(0.8f)));
  addInstance(s, addMesh(s, makePlane({20.0f, 20.0f}, 8)), mat, st.at(glm::vec3(0.0f)));
  st.sphere = addInstance(s, addMesh(s, makeSphere(1.0f, 32, 16)), mat, st.at({-1.5f, 1.0f, 0.0f}), true);
  st.box = addInstance(s, addMesh(s, makeBox({1.0f, 1.0f, 1.0f})), mat, st.at({1.5f, 0.5f, 0.5f}), true);
  // A slab 1/1000 thick, far off to the side at first.
  st.slab = addInstance(s, addMesh(s, makeBox({2.0f, 0.001f, 2.0f})), mat, st.at({8.0f, 3.0f, -6.0f}), true);
  s.lights.push_back(ambientLight(0.1f));
  s.lights.push_back(pointLight(glm::vec3(-2.0f, 6.0f, 3.0f) * scale + offset));
  s.lights.push_back(directional(glm::vec3(-0.4f, -1.0f, -0.3f)));
  s.camera.posW = glm::vec3(0.0f, 5.0f, 9.0f) * scale + offset;
  s.camera.targetW = glm::vec3(0.0f, 0.5f, 0.0f) * scale + offset;
  s.camera.nearZ = 0.05f * scale;
  s.camera.farZ = 100.0f * scale;
  return st;
}

// One change per frame: what it does to the scene, and whether the frame should still keep answers.
struct Change {
  const char* what;
  void (*apply)(Stage&);
};

const Change kChanges[] = {
    {"the sphere rolls a little", [](Stage& st) { st.scene.instances[st.sphere].worldFromObject = st.at({-1.3f, 1.0f, 0.1f}); }},
    {"the box slides into contact with the sphere's shadow",
     [](Stage& st) { st.scene.instances[st.box].worldFromObject = st.at({0.2f, 0.5f, 0.4f}); }},
    {"the thin slab teleports over the floor, across the light",
     [](Stage& st) { st.scene.instances[st.slab].worldFromObject = st.at({0.0f, 3.0f, 1.0f}); }},
    {"the slab tilts", [](Stage& st) {
       st.scene.instances[st.slab].worldFromObject = st.at({0.0f, 3.0f, 1.0f}) * glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(1, 0, 0));
     }},
    {"the point light moves", [](Stage& st) { st.scene.lights[1].posW += glm::vec3(0.3f, 0.0f, -0.2f) * st.scale; }},
    {"the slab leaves again", [](Stage& st) { st.scene.instances[st.slab].worldFromObject = st.at({8.0f, 3.0f, -6.0f}); }},
    {"the sun turns", [](Stage& st) { st.scene.lights[2].dirW = glm::normalize(glm::vec3(-0.3f, -1.0f, -0.4f)); }},
};

// What changed between two states of the stage, as the Renderer finds it.
RayReuse changesBetween(const Scene& before, const Scene& now) {
  RayReuse r;
  for (std::uint32_t i = 0; i < now.instances.size(); ++i)
    if (now.instances[i].worldFromObject != before.instances[i].worldFromObject)
      r.moved.emplace_back(i, before.instances[i].worldFromObject);
  const auto a = before.directLights(), b = now.directLights();
  for (std::size_t j = 0; j < b.size(); ++j)
    if (!(*a[j] == *b[j])) r.changedLights |= 1u << j;
  return r;
}

struct Step {
  const char* what;
  std::function<void()> apply;  // changes the scene given to keepAndCompare
};

// Traces the scene, then after each step traces it again keeping the frame before's answers and, on a
// second tracer, from nothing; the outputs must agree bit for bit and each step must keep answers.
// Returns the answers kept and the answers in all (traced or by map, without reuse) over the steps.
std::pair<std::uint64_t, std::uint64_t> keepAndCompare(Scene& scene, const FrameSettings& s, const std::vector<Step>& steps) {
  auto keeping = makeTracer(scene), fresh = makeTracer(scene);
  if (!keeping || !fresh) {
    ADD_FAILURE() << "no tracer";
    return {0, 0};
  }
  VisibilityBuffer ids[2];
  RayOutputs rays[2];
  castAndTrace(*keeping, scene, s, ids[0], rays[0]);
  std::uint64_t kept = 0, answers = 0;
  for (std::size_t f = 0; f < steps.size(); ++f) {
    SCOPED_TRACE(steps[f].what);
    const Scene before = scene;
    steps[f].apply();
    keeping->updateTransforms(scene);
    fresh->updateTransforms(scene);
    const int prev = static_cast<int>(f % 2), cur = 1 - prev;
    RayReuse reuse = changesBetween(before, scene);
    reuse.ids = &ids[prev];
    reuse.rays = &rays[prev];
    keeping->castVisibility(scene.camera, s.width, s.height, ids[cur]);
    keeping->trace(scene, scene.camera, s, ids[cur], rays[cur], &reuse);
    RayOutputs want;
    VisibilityBuffer wantIds;
    castAndTrace(*fresh, scene, s, wantIds, want);
    EXPECT_EQ(wantIds.ids, ids[cur].ids);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < std::min(want.lightMask.size(), rays[cur].lightMask.size()); ++i)
      differ += want.lightMask[i] != rays[cur].lightMask[i];
    EXPECT_EQ(differ, 0u) << "pixels whose kept shadow is not what tracing gives";
    EXPECT_TRUE(sameBits(want.lightMask, rays[cur].lightMask));
    EXPECT_TRUE(sameBits(want.reflected, rays[cur].reflected));
    EXPECT_TRUE(sameBits(want.transmitted, rays[cur].transmitted));
    EXPECT_EQ(rays[cur].counts.shadow + rays[cur].counts.shadowByMap + rays[cur].counts.shadowByShaft +
                  rays[cur].counts.shadowKept,
              want.counts.shadow + want.counts.shadowByMap + want.counts.shadowByShaft);
    EXPECT_GT(rays[cur].counts.shadowKept, 0u) << "a change this small leaves most answers";
    kept += rays[cur].counts.shadowKept;
    answers += want.counts.shadow + want.counts.shadowByMap + want.counts.shadowByShaft;
  }
  return {kept, answers};
}

void playChanges(float scale, glm::vec3 offset, bool hybridShadows, int rayScale) {
  Stage st = makeStage(scale, offset);
  FrameSettings s = settingsFor(160, 96);
  s.shadows = s.reflections = s.refraction = EffectMode::Ray;
  s.hybridShadows = hybridShadows;
  // The maps alone: the tile shafts (auto) would answer most of the floor before reuse could keep it.
  s.shadowProofs = ShadowProofs::Cpu;
  s.rayScale = rayScale;
  std::vector<Step> steps;
  for (const Change& c : kChanges) steps.push_back({c.what, [&st, &c] { c.apply(st); }});
  const auto [kept, answers] = keepAndCompare(st.scene, s, steps);
  // Small things moved: most of the floor's answers stand.
  EXPECT_GT(kept, answers / 3) << kept << " of " << answers;
}

TEST(RayReuse, KeptShadowsEqualTracedOnesAsThingsMove) { playChanges(1.0f, glm::vec3(0.0f), false, 1); }
TEST(RayReuse, KeptShadowsEqualTracedOnesOnACoarseGridWithHybridShadows) { playChanges(1.0f, glm::vec3(0.0f), true, 2); }
TEST(RayReuse, KeptShadowsEqualTracedOnesAtTinyScale) { playChanges(1e-4f, glm::vec3(0.0f), false, 1); }
TEST(RayReuse, KeptShadowsEqualTracedOnesAtHugeScale) { playChanges(1e4f, glm::vec3(0.0f), false, 1); }
TEST(RayReuse, KeptShadowsEqualTracedOnesFarFromTheOrigin) { playChanges(1.0f, glm::vec3(1e5f, -3e4f, 2e5f), false, 1); }

// A slope of one huge quad (1000 across, the view 20): its hits' rays leave from origins offset by up to
// 1.5e-5 of the quad's coordinates, far more than of the hits' own; boxes resting on the slope (a 1e-4
// gap) slide a little each step, lit from uphill and by the sun. The kind of scene where the tile's choice
// of moved bounds must count the offsets' scale, not the hits' (selectForTile); the margin argument that
// makes it conservative is in docs/reuse.md.
TEST(RayReuse, KeptShadowsEqualTracedOnesOnAHugeTiltedQuad) {
  Scene scene;
  const std::uint32_t mat = addMaterial(scene, diffuse(glm::vec3(0.8f)));
  const glm::mat4 tilt = glm::rotate(glm::mat4(1.0f), 0.5f, glm::vec3(1, 0, 0));
  addInstance(scene, addMesh(scene, makePlane({1000.0f, 1000.0f}, 1)), mat, tilt);
  const std::uint32_t box = addMesh(scene, makeBox({0.6f, 0.6f, 0.6f}));
  // Resting on the slope: its centre 0.3 above the plane along the tilted normal.
  const glm::vec3 up = glm::vec3(tilt * glm::vec4(0, 1, 0, 0));
  auto onSlope = [&](float x, float z) {
    return translate(glm::vec3(tilt * glm::vec4(x, 0, z, 1)) + 0.3001f * up) * tilt;
  };
  const std::uint32_t a = addInstance(scene, box, mat, onSlope(-1.0f, 0.0f), true);
  const std::uint32_t b = addInstance(scene, box, mat, onSlope(1.2f, 0.8f), true);
  scene.lights.push_back(pointLight(glm::vec3(0.0f, 6.0f, -5.0f)));
  scene.lights.push_back(directional(glm::vec3(0.2f, -1.0f, 0.9f)));
  scene.camera.posW = glm::vec3(0.0f, 6.0f, 9.0f);
  scene.camera.targetW = glm::vec3(0.0f, 0.0f, 0.0f);
  FrameSettings s = settingsFor(160, 96);
  s.shadows = EffectMode::Ray;
  std::vector<Step> steps;
  for (int k = 1; k <= 4; ++k)
    steps.push_back({"the boxes slide along the slope", [&, k] {
                       scene.instances[a].worldFromObject = onSlope(-1.0f + 0.05f * static_cast<float>(k), 0.02f * static_cast<float>(k));
                       scene.instances[b].worldFromObject = onSlope(1.2f, 0.8f - 0.04f * static_cast<float>(k));
                     }});
  const auto [kept, answers] = keepAndCompare(scene, s, steps);
  EXPECT_GT(kept, answers / 2) << kept << " of " << answers;
}

// A kept frame of another size keeps nothing (the Renderer never asks for it, but the gate must not read
// past the kept arrays if it did).
TEST(RayReuse, AKeptFrameOfAnotherSizeKeepsNothing) {
  Stage st = makeStage(1.0f, glm::vec3(0.0f));
  auto tracer = makeTracer(st.scene);
  ASSERT_TRUE(tracer);
  FrameSettings s = settingsFor(64, 40);
  s.shadows = EffectMode::Ray;
  VisibilityBuffer small, big;
  RayOutputs before, now;
  castAndTrace(*tracer, st.scene, s, small, before);
  s.width = 80;
  RayReuse reuse;
  reuse.ids = &small;
  reuse.rays = &before;
  tracer->castVisibility(st.scene.camera, s.width, s.height, big);
  tracer->trace(st.scene, st.scene.camera, s, big, now, &reuse);
  EXPECT_EQ(now.counts.shadowKept, 0u);
  EXPECT_GT(now.counts.shadow, 0u);
}

}  // namespace
}  // namespace tandem::rt::test
