#include "render/ShadowProofs.h"

#include <algorithm>

#include "gl/Bindings.h"
#include "core/Timer.h"
#include "render/RendererImpl.h"
#include "rt/Whitted.h"

namespace tandem {

static_assert(rt::ShadowCertainty::kCandidates == TD_PROOF_CANDIDATES &&
                  sizeof(rt::ShadowCertainty::Texel) == TD_PROOF_RECORD * sizeof(std::uint32_t) &&
                  rt::ShadowCertainty::kBlock == TD_PROOF_BLOCK,
              "shadow_proof.frag reads ShadowCertainty's texel records as bindings.glsl's TD_PROOF_* say");
static_assert(rt::kProofDecidedShift == TD_PROOF_DECIDED_SHIFT && rt::kProofNeededShift == TD_PROOF_NEEDED_SHIFT &&
                  rt::kProofComplete == TD_PROOF_COMPLETE,
              "the ray pass reads the proof words as shadow_proof.frag writes them");

std::vector<std::uint32_t> proofInstanceFlags(const Scene& scene, const FrameSettings& settings) {
  std::vector<std::uint32_t> flags(scene.instances.size(), 0u);
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.material >= scene.materials.size()) continue;
    const Material& m = scene.materials[inst.material];
    const bool bump = m.procedural.type != Pattern::None && m.procedural.bump > 0.0f;
    if (m.kr == 0.0f && m.kt == 0.0f && m.alphaMode != AlphaMode::Blend && m.normalTexture < 0 && !bump)
      flags[i] |= TD_PROOF_PLAIN;
    if (settings.shadingOverride.value_or(m.shading) == ShadingModel::Flat) flags[i] |= TD_PROOF_FLAT;
  }
  return flags;
}

gl::ProofSource proofSource(const rt::ShadowCertainty& maps, const Scene& scene) {
  using Map = rt::ShadowCertainty::Map;
  gl::ProofSource out;
  out.generation = maps.generation();
  out.constants = glm::vec4(rt::ShadowCertainty::kQueryMargin, rt::ShadowCertainty::kDepthRel,
                            rt::ShadowCertainty::kRelativeMargin, rt::kShadowRayEnd);
  for (const Map& m : maps.maps()) {
    gl::ProofMapData d;
    d.kind = m.kind == rt::ShadowCertainty::Kind::Cube ? 1 : m.kind == rt::ShadowCertainty::Kind::Ortho ? 2 : 0;
    d.size = m.size;
    d.origin = m.origin;
    for (int f = 0; f < 6; ++f)
      for (int k = 0; k < 3; ++k) d.axes[f][k] = m.axes[f][k];
    d.extent = m.extent;
    d.top = m.top;
    d.nearZ = m.nearZ;
    d.depthEps = m.depthEps;
    d.centre = m.centre;
    // Whitted's toLight for a directional light (tdLightIncident): -dirRange, as the record holds it.
    d.toLight = -glm::vec3(m.light.dirRange);
    d.texels = m.texels.data();
    d.texelCount = m.texels.size();
    d.nearLight = m.nearLight;
    out.maps.push_back(d);
  }
  const auto& tests = maps.tests();
  const auto& blocks = maps.blocksAll();
  out.triangles.reserve(tests.size() * 5);
  for (std::size_t t = 0; t < tests.size(); ++t) {
    const rt::ShadowCertainty::TriangleTest& x = tests[t];
    out.triangles.push_back(x.plane);
    for (const glm::vec4& e : x.edges) out.triangles.push_back(e);
    out.triangles.emplace_back(x.magnitude, x.valid ? 1.0f : 0.0f, blocks[t] ? 1.0f : 0.0f, 0.0f);
  }
  out.instanceBase = maps.triangleBase();
  for (std::size_t i = 0; i < out.instanceBase.size() && i < scene.instances.size(); ++i)
    if (scene.meshes[scene.instances[i].mesh].exact) out.instanceBase[i] = ~0u;
  return out;
}

// Hybrid shadows proved in the GL (docs/shadows.md, "Proofs in the GL"): the maps the ray pass reads (built
// when the geometry or a light changed: the rays' time), copied to the GL when they are new, and the pass
// over the visibility buffer that decides each primary hit's shadow rays where it can (the raster's time).
bool Renderer::Impl::proveShadows(const FramePlan& plan, const Camera& camera, FrameStats& stats) {
  if (!plan.glShadowProofs || proofFailed) {
    releaseGlProofs();
    return false;
  }
  Timer build;
  const rt::ShadowCertainty* maps = tracer->shadowMapsFor(scene, camera, plan.raySettings, caches.gpu().anchor());
  stats.raysMs += build.ms();
  stats.shadowMapsMs += tracer->lastShadowMapMs();
  if (!maps) return false;
  if (!proofRoute.inGl(plan, maps->generation())) return false;
  Timer gl;
  if (!proofPass) {
    auto pass = gl::ShadowProofPass::create();
    if (!pass) {
      logError("shadow proofs: " + pass.error().message + " (the ray pass proves them instead)");
      proofFailed = true;
      return false;
    }
    proofPass = std::move(*pass);
  }
  if (proofPass->generation() != maps->generation()) proofPass->upload(proofSource(*maps, scene));
  proofPass->setInstanceFlags(proofInstanceFlags(scene, plan.raySettings));
  const Camera glCamera = toRenderSpace(camera, caches.gpu().anchor());
  auto drawn = proofPass->prove(caches.gpu(), visibilityPass.ids(), plan.settings.width, plan.settings.height, glCamera,
                                plan.raySettings.rayScale);
  if (!drawn) logError("shadow proofs: " + drawn.error().message);
  else glFinish();
  stats.rasterMs += gl.ms();
  stats.shadowsProvedInGl = drawn.ok();
  return drawn.ok();
}

}  // namespace tandem
