#pragma once
// The frame-time budget (FrameSettings::targetMs, docs/budget.md): each frame, the choice of ray-pass scale,
// recursion depth and raster fallbacks that is expected to be the least wrong among those predicted to fit
// the target. Pure logic (no GL, no Embree, no clock): the Renderer feeds it each frame's FrameStats, the
// unit tests feed it synthetic costs.
//
// Choices: the requested settings, then every combination of a coarser ray grid (1/2, 1/4), a depth cap
// (2, 1), a raster fallback for any set of the ray-traced effects and, where the scene samples area lights
// or glossy lobes with more than one sample through a pinhole camera, one sample a frame with the
// spatiotemporal filter (FrameSettings::denoise), less those that change nothing the frame would do for this
// scene. Each has an expected error (the error table, measured by tandem-bench --sweep against the reference)
// and a predicted cost:
//   cost = fixed[set] + rayMsPerPixel · rayGridPixels · exp(work[choice])
// or, in throughput mode (FrameSettings::pipelined: the rays of one frame beside the GL's stages of the next
// and the last), max(fixed, rays − transfers) + transfers, the transfers (read-back, upload) being the ray
// term's learned share that runs between one frame landing and the next launching; there the hysteresis
// below reads the interval between frames (which, unlike a latency frame's total, holds the application's
// time between the calls), and a frame drawn with a choice already left is not learned from.
// fixed = every stage but readback, rays and upload: the scene's load now times a learned factor per set of
// raster fallbacks, raw or with the filter on each ray grid (its passes are GL stages); rayMsPerPixel follows
// the scene from frame to frame; work starts from a prior and is learned from the frames a choice runs: its
// first sets it, its next two halve the gap (in the logarithm), later ones move rayMsPerPixel, every choice's
// cost alike, by 0.3 of the gap (the scene's drift). A new size or view re-measures the loads and keeps the
// factors.
// Hysteresis: frame times are smoothed (m ← (m + t) / 2). A choice is left when m runs over 1.05 × target
// (on its first frame, which carries the switch and counts as at most its own rays with the fixed part
// predicted, only over 1.5 ×): one frame a little slow is no reason to leave, two in a row are. A better one
// is taken only after 10 frames on the current one running under 0.95 × target, and only when predicted to
// fit in 0.85 × target — so a choice that ran over is not taken again until the scene got cheaper by that
// margin. tests/unit/FrameBudgetTest.cpp scripts each rule.
#include <cstdint>
#include <vector>

#include "render/FramePlan.h"
#include "tandem/FrameStats.h"
#include "tandem/Settings.h"

namespace tandem {

/// The expected error of each knob, against the reference (mean FLIP over the bench's scenes, measured at
/// hybrid-full with the one knob changed). tandem-bench --sweep prints this table next to what it measured.
struct BudgetErrorTable {
  double rayScale2 = 0, rayScale4 = 0;      // the ray grid at 1/2, 1/4 of the frame
  double depth2 = 0, depth1 = 0;            // recursion capped at 2, 1 bounces (vs 3 or more)
  double refractionRaster = 0;              // refraction by probes instead of rays
  double reflectionsRaster = 0;             // reflections by probes instead of rays
  double shadowsRaster = 0;                 // shadow maps instead of shadow rays
  /// One light and lobe sample a frame with the spatiotemporal filter instead of the request's samples
  /// raw. Negative: on the scenes it is offered for it was as near the truth as four raw samples or nearer,
  /// camera moving (and cheaper in rays); the ladder still keeps the request first (the budget cuts only what
  /// does not fit).
  double filtered = 0;
};
const BudgetErrorTable& budgetErrorTable();

/// BudgetChoice::fallback: which ray-traced effects this choice draws by raster instead.
inline constexpr int kRefractionRaster = 1, kReflectionsRaster = 2, kShadowsRaster = 4, kFallbackSets = 8;
/// The sets whose fixed part is learned apart (BudgetChoice::fixedSet): a set of fallbacks raw, and with the
/// filter on each ray grid, 1/1, 1/2 and 1/4 (its temporal and a-trous passes run on the grid, its upsampling
/// from it at full size: on area-lights.json it added 53 ms to the frame at every pixel and 68 on the 1/2 grid,
/// 2 cores, 2026-11-30).
inline constexpr int kFilterGrids = 3, kFixedSets = (1 + kFilterGrids) * kFallbackSets;
inline constexpr int filteredSet(int fallback, int rayScale) {
  return fallback + kFallbackSets * (rayScale >= 4 ? 3 : rayScale == 2 ? 2 : 1);
}
inline constexpr bool isFilteredSet(int set) { return set >= kFallbackSets; }
inline constexpr int rawTwin(int set) { return set % kFallbackSets; }

struct BudgetChoice {
  FrameSettings settings;   // the requested settings with this choice's knobs
  int rayScale = 1, depthCap = 0;
  int fallback = 0;          // a set of k*Raster bits
  bool filtered = false;     // one sample a frame, filtered (settings.denoise), in place of the request's
  double error = 0;          // expected FLIP over the requested settings' own
  bool rays = false;         // the plan has a ray pass
  double work = 0;           // log of the ray cost per ray-grid pixel, relative (learned)
  double prior = 0;          // work's prior (what learning a filtered choice corrects for the others)
  int framesRun = 0;         // clean frames this choice has run since the ladder was made
  int fixedSet() const { return filtered ? filteredSet(fallback, rayScale) : fallback; }
};

class FrameBudget {
 public:
  /// The settings for this frame. `requested` is resolved; targetMs 0 (or a reference frame) returns it
  /// as it is and leaves the budget idle.
  FrameSettings choose(const FrameSettings& requested, const SceneFacts& facts);
  /// What the frame drawn with choose()'s last answer cost.
  void observe(const FrameStats& frame);
  /// Throughput mode: the frame a render() call showed, a call after its choice was made. Its totalMs is its
  /// latency (from the call that began it to its show), which also holds the next frame's raster and whatever
  /// the application did between the calls: the budget learns from its own stages instead, and reads
  /// `intervalMs` (this call's, up to now) as what the player gets.
  void observeShown(FrameStats shown, double intervalMs);
  /// A new scene: what was learned belonged to the old one.
  void reset();
  /// The last choice, for FrameStats.
  const BudgetStats& stats() const { return stats_; }
  const std::vector<BudgetChoice>& choices() const { return choices_; }
  int current() const { return current_; }
  /// Whether the last choose() had a target and a ladder with filtered choices: the filter may be taken again.
  bool offersFilter() const { return !idle_ && filterOffered_; }
  /// Predicted frame ms of choice i (NaN before anything was measured).
  double predictMs(int i) const;
  /// Choice i's frame ms with a ray part of `rayMs` (its readback, ray pass and upload) and the fixed part
  /// as predicted (NaN before anything was measured).
  double costMs(int i, double rayMs) const;
  /// The fixed part's offset of a set (fixedSet): as learned, or for one not yet drawn, from those drawn.
  double fixedOffsetOf(int set) const;

 private:
  void makeLadder(const FrameSettings& requested, const SceneFacts& facts);
  int pick(double meanMs);
  /// Costs measured again from the next frame: the absolute scales go, the relative ones stay.
  void reanchor();

  FrameSettings requested_;  // what the ladder was made for (ladderPart)
  SceneFacts facts_;
  FrameSettings view_;       // size and view of the last frame (viewPart)
  bool haveLadder_ = false;
  bool idle_ = true;         // the last choose() had no target
  bool filterOffered_ = false;  // the ladder has filtered choices
  std::vector<BudgetChoice> choices_;
  int current_ = 0;
  int framesOnCurrent_ = 0;  // clean frames on current_ since it was chosen
  int width_ = 0, height_ = 0;
  double targetMs_ = 0;
  bool pipelined_ = false;   // throughput mode asked for (predictMs: the slower side, not the sum) ...
  bool overlapping_ = false; // ... and the frames observed overlap (not latency-mode frames, not every one drained)
  bool lastDrained_ = false;
  bool haveShare_ = false;
  double transferShare_ = 0; // the read-back and upload's share of the ray part (smoothed): outside the overlap
  double meanMs_ = 0;        // smoothed frame ms of current_ (clean frames only)
  // Ray part: log ms per ray-grid pixel at work 0 (the scene's load now) and each choice's work.
  bool haveRho_ = false;
  double logRho_ = 0;
  // Fixed part: log ms of the fixed set at offset 0 (the load now), and each set's offset.
  bool haveFixedBase_ = false;
  double logFixedBase_ = 0;
  double fixedOffset_[kFixedSets]{};
  bool fixedKnown_[kFixedSets]{};
  int fixedFrames_[kFixedSets]{};
  BudgetStats stats_;
};

}  // namespace tandem
