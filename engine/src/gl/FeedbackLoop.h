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

/// Every sampler of the current program that reads what it must not (GL 4.5 core 8.17, 8.22, 11.1.3.5; the
/// driver reports none on llvmpipe, NVIDIA's calls them undefined behaviour): a unit with no texture of the
/// sampler's type, a shadow sampler on a texture without a depth format or without depth comparison, a
/// float sampler on a depth texture that compares, integer and float samplers and formats mixed, an integer
/// texture filtered linearly (incomplete), a buffer texture without its buffer. One line each.
std::vector<std::string> findSamplerProblems();

/// Called by every pass right before it draws: feedback loops and sampler problems. Checks only when checks
/// are on: always in builds with assertions (either is a bug: it asserts), and in any build after
/// setFeedbackLoopChecks(true) (tests), where each is logged as an error, kept for takeFeedbackLoopReport()
/// and, on a context with debug output, inserted as a KHR_debug message of type undefined behaviour.
void assertNoFeedbackLoop(std::string_view pass);

/// Turns the checks on or off for builds without assertions (they stay on with assertions).
void setFeedbackLoopChecks(bool on);

struct FeedbackLoopReport {
  std::size_t draws = 0;           // draws checked since the last take
  std::vector<std::string> loops;  // "pass: loop" for each loop found
  std::vector<std::string> samplers;  // "pass: problem" for each sampler problem found
};
/// What the checks saw since the last call, and resets it.
FeedbackLoopReport takeFeedbackLoopReport();

}  // namespace tandem::gl
