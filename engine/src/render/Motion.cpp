// Motion since the last frame composited (docs/motion.md), for the motion view (DebugView::Motion) and the
// spatiotemporal filter (FramePlan::denoise): the shade pass projects the pixel's exact primary hit with this
// frame's camera and, moved back by its instance's previous-from-current transform, with the last frame's.
// The view also copies the last frame's ids and depth (whether the point was in view there); the filter keeps
// its own (gl/DenoisePass).
#include <algorithm>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "render/RendererImpl.h"
#include "tandem/Log.h"

namespace tandem {

void Renderer::Impl::motionInputs(const FramePlan& plan, const Camera& camera, gl::ShadeInputs& in) {
  const FrameSettings& s = plan.settings;
  const bool view = s.debugView == DebugView::Motion;
  if (!view && !plan.denoise) {
    if (motionLast.held || motionNext.held || motionBuffer) {
      motionLast = motionNext = motionPending = {};
      motionBuffer.reset();
      motionTexture.reset();
      previousIds.reset();
      previousDepth.reset();
      nextIds.reset();
      nextDepth.reset();
      motionBufferBytes = 0;
    }
    return;
  }
  // The last frame composited by an earlier call is the one this frame moves from (the samples of one frame
  // all move from the same frame).
  if (motionNext.held && motionNext.call != calls) {
    motionLast = std::move(motionNext);
    motionNext = {};
    std::swap(previousIds, nextIds);
    std::swap(previousDepth, nextDepth);
  }
  MotionFrame now;
  now.held = true;
  now.call = calls;
  now.sceneGeneration = sceneGeneration;
  now.anchor = caches.gpu().anchor();
  now.width = s.width;
  now.height = s.height;
  now.camera = camera;
  now.worldFromObject.reserve(scene.instances.size());
  for (const Instance& inst : scene.instances) now.worldFromObject.emplace_back(inst.worldFromObject);
  if (plan.denoise) {
    // The area lights: the filter smooths their light alone (the others' goes past it).
    for (const Light& l : scene.lights) (isAreaLight(l.type) ? now.lights : now.otherLights).push_back(l);
    now.shading = shadingSettings(s);
  }
  const MotionFrame& before = motionLast;
  // (a new anchor keeps it: what the last frame was is held in world space and taken to this frame's render
  // space below, as a renderer anchored here from the start would have it)
  const bool history = before.held && before.sceneGeneration == now.sceneGeneration &&
                       before.width == now.width && before.height == now.height &&
                       before.worldFromObject.size() == now.worldFromObject.size() &&
                       (!view || (previousIds && previousDepth));
  // Per instance, where its points were in render space last frame given where they are now: exactly the
  // identity for an instance that did not move (its pixels then move by the camera alone), else worked out in
  // double around the anchor, so that a scene 1e6 from the origin moves as one at the origin does.
  std::vector<glm::vec4> texels(4 * std::max<std::size_t>(now.worldFromObject.size(), 1), glm::vec4(0.0f));
  for (std::size_t i = 0; i < now.worldFromObject.size(); ++i) {
    glm::mat4 previousFromCurrent(1.0f);
    if (history && before.worldFromObject[i] != now.worldFromObject[i]) {
      const glm::dvec3 a(now.anchor);
      const glm::dmat4 d = glm::translate(glm::dmat4(1.0), -a) * before.worldFromObject[i] *
                           glm::inverse(now.worldFromObject[i]) * glm::translate(glm::dmat4(1.0), a);
      previousFromCurrent = glm::mat4(d);
    }
    for (int c = 0; c < 4; ++c) texels[4 * i + static_cast<std::size_t>(c)] = previousFromCurrent[c];
  }
  const std::size_t bytes = texels.size() * sizeof(glm::vec4);
  if (bytes != motionBufferBytes) {
    motionBuffer = gl::createBuffer("motion: instances' previous-from-current", bytes, texels.data());
    motionTexture = gl::createBufferTexture("motion: instances view", GL_RGBA32F, motionBuffer);
    motionBufferBytes = bytes;
  } else {
    glNamedBufferSubData(motionBuffer.id(), 0, static_cast<GLsizeiptr>(bytes), texels.data());
  }
  in.motionInstances = &motionTexture;
  in.motionHistory = history;
  if (history && plan.denoise) denoiseInputs(before, now, in);
  in.previousIds = history && view ? &previousIds : nullptr;
  in.previousDepth = history && view ? &previousDepth : nullptr;
  const Camera beforeR = toRenderSpace(before.camera, now.anchor);
  in.previousClipFromViewRotation = history ? gl::clipFromViewRotation(beforeR, before.width, before.height) : glm::mat4(1.0f);
  in.previousCameraPos = history ? beforeR.posW : glm::vec3(0.0f);
  in.previousCameraForward = history ? glm::normalize(beforeR.targetW - beforeR.posW) : glm::vec3(0.0f, 0.0f, -1.0f);
  motionPending = std::move(now);
}

void Renderer::Impl::rememberMotion(const FramePlan& plan, const gl::VisibilityPass& pass) {
  if (!motionPending.held) return;
  if (plan.settings.debugView != DebugView::Motion) {
    if (plan.denoise) motionNext = motionPending;  // the filter's guides are its own last ids and depth
    return;
  }
  // (pending stays: a frame of several samples composites each with the same inputs)
  const int w = pass.width(), h = pass.height();
  // Made at the frame's size on first need; a copy the GL refuses (out of memory) leaves the next frame
  // without a last frame (every pixel new), not the process without a frame.
  auto sized = [&](gl::Texture& t, GLenum internal, const char* name) {
    GLint tw = 0, th = 0;
    if (t) {
      glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_WIDTH, &tw);
      glGetTextureLevelParameteriv(t.id(), 0, GL_TEXTURE_HEIGHT, &th);
    }
    if (t && tw == w && th == h) return true;
    t.reset();
    auto made = gl::tryCreateTexture2D(name, internal, w, h);
    if (!made) {
      logWarning("the motion view: " + made.error().message + " (the next frame has no last frame)");
      return false;
    }
    t = std::move(*made);
    gl::setSampling(t, GL_NEAREST, GL_NEAREST);
    return true;
  };
  if (!sized(nextIds, gl::kChannelIds.internal, "motion: the last frame's ids") ||
      !sized(nextDepth, gl::kChannelDepth.internal, "motion: the last frame's depth")) {
    motionNext = motionLast = {};  // nor the one before it: the next frame must not measure from that
    return;
  }
  glCopyImageSubData(pass.ids().id(), GL_TEXTURE_2D, 0, 0, 0, 0, nextIds.id(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
  glCopyImageSubData(pass.depth().id(), GL_TEXTURE_2D, 0, 0, 0, 0, nextDepth.id(), GL_TEXTURE_2D, 0, 0, 0, 0, w, h, 1);
  motionNext = motionPending;
}

// What of the settings shapes the light the filter accumulates: the frame's own, less the display's (exposure
// and tone map: its history is linear radiance), the size (checked on its own), the frame-time budget's target
// (its choice is in the other fields) and how the frame is scheduled (reuse, throughput mode).
FrameSettings Renderer::Impl::shadingSettings(const FrameSettings& s) {
  FrameSettings shaping = s;
  shaping.exposure = FrameSettings{}.exposure;
  shaping.toneMap = FrameSettings{}.toneMap;
  shaping.targetMs = FrameSettings{}.targetMs;
  shaping.reuseRays = FrameSettings{}.reuseRays;
  shaping.pipelined = FrameSettings{}.pipelined;
  return shaping;
}

// The filter keeps its history only while the lights and the settings that shape the light are as they were
// (a change of light reaches pixels by amounts its statistics cannot tell from noise in a few frames); the
// instances that moved go to the shade
// pass as boxes (render space, where they were and where they are), so that the pixels whose light they may
// have blocked or unblocked start again.
void Renderer::Impl::denoiseInputs(const MotionFrame& before, const MotionFrame& now, gl::ShadeInputs& in) const {
  in.denoiseHistory = before.lights == now.lights && before.shading == now.shading;
  in.moved = {};
  if (!in.denoiseHistory) return;
  in.moved.lobesStale = before.otherLights != now.otherLights;
  in.moved.lobes = std::any_of(scene.materials.begin(), scene.materials.end(), hasGlossyLobe);
  // The area lights whose shadows a moving instance may move: each a sphere holding it (render space).
  for (const Light& l : now.lights) {
    if (!l.castShadows || in.moved.areaLightCount == kMaxLights) continue;
    in.moved.areaLights[static_cast<std::size_t>(in.moved.areaLightCount++)] =
        glm::vec4(glm::vec3(glm::dvec3(l.posW) - glm::dvec3(now.anchor)), shading::areaLightReach(l));
  }
  struct Moved {
    gl::Bounds box;
    std::size_t instance;
  };
  std::vector<Moved> moved;
  const std::vector<gl::Bounds>& meshes = caches.meshBounds();
  const glm::dmat4 fromWorld = glm::translate(glm::dmat4(1.0), -glm::dvec3(now.anchor));
  // One box an instance: where it was and where it is (the two overlap for all but the fastest).
  for (std::size_t i = 0; i < now.worldFromObject.size(); ++i) {
    if (before.worldFromObject[i] == now.worldFromObject[i]) continue;
    const std::size_t mesh = scene.instances[i].mesh;
    if (mesh >= meshes.size() || meshes[mesh].empty()) continue;
    gl::Bounds box;
    for (const glm::dmat4* m : {&before.worldFromObject[i], &now.worldFromObject[i]}) {
      const gl::Bounds& b = meshes[mesh];
      for (int k = 0; k < 8; ++k) {
        const glm::dvec4 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z, 1.0);
        box.add(glm::vec3(fromWorld * *m * corner));
      }
    }
    moved.push_back({box, i});
  }
  // More boxes than the shader holds (a game moves many small things): merged two at a time, each time the
  // two whose union adds least surface (what a box flags grows with its extent: merging neighbours keeps
  // it small; merging far-apart things into slabs flagged every point of a floor). Quadratic in the boxes
  // per merge: above kGreedy of them, first runs of neighbours along the axis their centres spread most,
  // each run's union one box. The instance becomes unknown (-1) when boxes of two merge.
  static constexpr std::size_t kNoInstance = ~std::size_t{0};
  constexpr std::size_t kGreedy = 32;
  auto unite = [](Moved a, const Moved& b) {
    a.box.add(b.box);
    if (a.instance != b.instance) a.instance = kNoInstance;
    return a;
  };
  if (moved.size() > kGreedy) {
    gl::Bounds centres;
    for (const Moved& m : moved) centres.add(m.box.centre());
    const glm::vec3 spread = centres.hi - centres.lo;
    const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
    std::sort(moved.begin(), moved.end(),
              [axis](const Moved& a, const Moved& b) { return a.box.centre()[axis] < b.box.centre()[axis]; });
    std::vector<Moved> runs;
    for (std::size_t k = 0; k < kGreedy; ++k) {
      const std::size_t first = k * moved.size() / kGreedy, end = (k + 1) * moved.size() / kGreedy;
      Moved run = moved[first];
      for (std::size_t m = first + 1; m < end; ++m) run = unite(run, moved[m]);
      runs.push_back(run);
    }
    moved = std::move(runs);
  }
  auto area = [](const gl::Bounds& b) {
    const glm::vec3 d = b.hi - b.lo;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  };
  while (moved.size() > TD_MAX_MOVED_BOXES) {
    std::size_t bestA = 0, bestB = 1;
    float bestGrowth = std::numeric_limits<float>::infinity();
    for (std::size_t a = 0; a < moved.size(); ++a)
      for (std::size_t b = a + 1; b < moved.size(); ++b) {
        gl::Bounds u = moved[a].box;
        u.add(moved[b].box);
        const float growth = area(u) - area(moved[a].box) - area(moved[b].box);
        if (growth < bestGrowth) bestGrowth = growth, bestA = a, bestB = b;
      }
    moved[bestA] = unite(moved[bestA], moved[bestB]);
    moved.erase(moved.begin() + static_cast<std::ptrdiff_t>(bestB));
  }
  const glm::vec3 cameraPosR = toRenderSpace(now.camera.posW, now.anchor);
  for (const Moved& m : moved) {
    in.moved.boxes[static_cast<std::size_t>(in.moved.boxCount++)] = {
        glm::vec4(m.box.lo, m.instance == kNoInstance ? -1.0f : static_cast<float>(m.instance)), glm::vec4(m.box.hi, 0.0f)};
    const glm::vec3 far = glm::max(glm::abs(m.box.lo - cameraPosR), glm::abs(m.box.hi - cameraPosR));
    in.moved.reach = std::max(in.moved.reach, glm::length(far));
  }
}

}  // namespace tandem
