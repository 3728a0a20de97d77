#pragma once
// Rendering feedback loops (GL 4.5 core, 9.3 "Feedback Loops Between Textures and the Framebuffer"):
// a texture the current program can sample that is also attached to the bound draw framebuffer makes the
// draw undefined, even when nothing writes that attachment (a read-only depth buffer). llvmpipe happens
// to give the expected picture; tiled and compressing GPUs need not, so the passes check before drawing.
//
//   glUseProgram(p); glBindTextureUnit(...);
//   assertNoFeedbackLoop("shade");   // then draw
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace tandem::gl {

/// Every loop the next draw would have, one line each, e.g. "sampler 'depthTex' (unit 1) reads texture
/// 12 'gbuffer depth' level 0, attached to framebuffer 7 'linear radiance' as GL_DEPTH_ATTACHMENT";
/// empty when there is none. Reads the current program's active sampler uniforms, the textures bound
/// to their units and the attachments of the bound draw framebuffer (the default framebuffer has none).
/// Costs dozens of GL queries: for checks, not for frames.
std::vector<std::string> findFeedbackLoops();

/// Called by every pass right before it draws. Checks only when checks are on: always in builds with
/// assertions (a loop is a bug: it asserts), and in any build after setFeedbackLoopChecks(true) (tests),
/// where each loop found is logged as an error and kept for takeFeedbackLoopReport().
void assertNoFeedbackLoop(std::string_view pass);

/// Turns the checks on or off for builds without assertions (they stay on with assertions).
void setFeedbackLoopChecks(bool on);

struct FeedbackLoopReport {
  std::size_t draws = 0;           // draws checked since the last take
  std::vector<std::string> loops;  // "pass: loop" for each loop found
};
/// What the checks saw since the last call, and resets it.
FeedbackLoopReport takeFeedbackLoopReport();

}  // namespace tandem::gl
