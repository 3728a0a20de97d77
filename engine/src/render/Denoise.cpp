// The spatiotemporal filter's part of the frame (FrameSettings::denoise, docs/denoise.md): each filtered frame
// draws the next sample of one sequence, the shade pass writes the noisy frame and the filter's guides into the
// filter's target, and gl::DenoisePass filters it into the frame's output.
#include <algorithm>

#include "core/Timer.h"
#include "render/RendererImpl.h"
#include "tandem/Log.h"

namespace tandem {

namespace {
// Frames the temporal mean spans at most: long enough that a still view's one-sample noise falls by ~5x
// (sqrt(32)) before the a-trous filter, short enough that what the clamp lets through fades within a second.
constexpr int kMaxHistory = 32;
}  // namespace

FramePlan Renderer::Impl::denoisePlan(FramePlan plan, const SceneFacts& facts) {
  if (denoiseFailed) plan.withoutFilter();
  if (plan.denoise && facts.lensOrShutter && !denoiseLensWarned) {
    // Filtered as asked, but said: the frame is likely further from the truth than the raw samples' (the
    // frame-time budget never offers the filter for such a camera). Said at the plan: the frames of an
    // accumulation and throughput mode's draw from a pinhole of the lens.
    logWarning("the spatiotemporal filter: a thin-lens, orthographic or open-shutter camera; its motion vectors "
               "and guides model a pinhole at the frame's time, and the filtered frame may be further from the "
               "truth than the raw samples (docs/denoise.md, Limits)");
    denoiseLensWarned = true;
  }
  return plan;
}

void Renderer::Impl::leaveDenoise() {
  if (!denoisePass) return;
  // Cost follows the settings: the filter goes, but for its programs while a frame-time budget may take it
  // again (building them again, and a software GL's first draws of each, cost the next frames ~0.3-0.6 s).
  if (budget.offersFilter()) denoisePass->release();
  else denoisePass.reset();
}

bool Renderer::Impl::shadeDenoised(const FramePlan& plan, const Camera& glCamera, const gl::ShadeInputs& in,
                                   const gl::VisibilityPass& pass, FrameStats& sample) {
  if (!plan.settings.denoise) {
    leaveDenoise();
    return false;
  }
  if (!plan.denoise || denoiseFailed) {
    if (denoisePass) denoisePass->forget();  // the frame after this one has no past
    return false;
  }
  if (!denoisePass) {
    auto made = gl::DenoisePass::create();
    if (!made) {
      logError("the spatiotemporal filter: " + made.error().message + " (frames are drawn without it)");
      denoiseFailed = true;
      return false;
    }
    denoisePass = std::move(*made);
  }
  if (auto reserved = denoisePass->reserve(pass.width(), pass.height(), std::max(1, in.rayScale)); !reserved) {
    logWarning("the spatiotemporal filter: " + reserved.error().message + " (this frame is drawn without it)");
    return false;
  }
  gl::ShadeInputs guided = in;
  guided.fusedOutput = false;  // the filter writes the display
  guided.denoiseGuides = true;
  shadePass.shade(denoisePass->shadeFramebuffer(), caches.gpu(), pass, glCamera, guided);
  // The filter's own time (its part of the composite): the shade pass finished first.
  glFinish();
  Timer filtered;
  // A light that changed reaches any pixel, by amounts the history's statistics cannot tell from noise within
  // a few frames: the filter starts again (docs/denoise.md).
  denoisePass->filter(outputPass.linearTexture(), outputPass.displayTexture(), pass.ids(), glCamera,
                      in.motionHistory && in.denoiseHistory, in.moved, in.exposure, in.toneMap, kMaxHistory);
  glFinish();
  sample.denoiseMs = filtered.ms();
  sample.denoised = true;
  return true;
}

}  // namespace tandem
