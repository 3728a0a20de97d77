#include "render/FrameBudget.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

namespace tandem {

namespace {

// Thresholds of the hysteresis (fractions of the target) and the quiet spell before a better choice.
constexpr double kOver = 1.05;       // a choice whose smoothed frame runs over this is left at once
constexpr double kFarOver = 1.5;     // ... or, on its first frame, over this
constexpr double kFitDown = 0.92;    // ... for one predicted to fit in this
constexpr double kFitUp = 0.85;      // a better choice is taken only when predicted to fit in this
constexpr double kQuietUp = 0.95;    // ... and the current one runs under this
constexpr int kQuietFrames = 10;     // ... for this many frames since the last change
constexpr int kLearnFrames = 3;     // a choice's first frames teach its own cost, later ones the scene's drift
constexpr double kClearlyCheaper = 0.95;  // out of reach: a move must save this much

// Priors for a choice not yet run: its ray cost per ray-grid pixel relative to the requested settings.
// Only the first move down rests on them: each choice's own frames replace them.
double priorWork(int rayScale, int requestedScale, int depthCap, int requestedDepth, int fallback, bool filtered) {
  auto gridOverhead = [](int s) { return s == 4 ? 1.5 : s == 2 ? 1.2 : 1.0; };  // upsampling, fixed costs
  auto depthWork = [](int d) { return d >= 3 ? 1.0 : d == 2 ? 0.8 : d == 1 ? 0.65 : 0.5; };
  // What each effect's rays are of the pass, roughly; a set that leaves no ray effect has no ray pass at
  // all (BudgetChoice::rays), whatever this says.
  double fallbackWork = 1.0;
  if (fallback & kRefractionRaster) fallbackWork *= 0.8;
  if (fallback & kReflectionsRaster) fallbackWork *= 0.6;
  if (fallback & kShadowsRaster) fallbackWork *= 0.7;
  // One light and lobe sample where the request draws more: their rays are much of the pass in a scene the
  // filter is offered for (hybrid-full on area-lights.json: 4 samples to 1 took the rays from ~120 to ~45 ms,
  // before the hits past the primary hit kept their four, FrameSettings::lightSamplesPastFilter; the budget
  // corrects the guess by what it measures).
  if (filtered) fallbackWork *= 0.4;
  const double w = gridOverhead(rayScale) / gridOverhead(requestedScale) * depthWork(depthCap) /
                   depthWork(requestedDepth) * fallbackWork;
  return std::log(std::max(w, 1e-3));
}

double scaleError(const BudgetErrorTable& t, int s) { return s >= 4 ? t.rayScale4 : s == 2 ? t.rayScale2 : 0.0; }
double depthError(const BudgetErrorTable& t, int d) { return d >= 3 ? 0.0 : d == 2 ? t.depth2 : t.depth1; }

// What a frame would do, for telling apart two choices that differ in name only (a fallback for an
// effect the scene cannot show, a depth cap without reflection or refraction rays, a depth cap the probes
// do not read, hybrid shadows without shadow rays).
bool samePlan(FramePlan a, FramePlan b) {
  if (a.rayPass != b.rayPass || a.rasterShadows != b.rasterShadows || a.probeReflections != b.probeReflections ||
      a.probeRefraction != b.probeRefraction || a.denoise != b.denoise)
    return false;
  if (!a.rayPass) {
    // (the filter runs its temporal and a-trous stages on the ray grid's pixels even without rays)
    if (a.denoise && a.settings.rayScale != b.settings.rayScale) return false;
    // the probes read only whether there is a bounce at all
    return !(a.probeReflections || a.probeRefraction) || (a.settings.maxDepth > 0) == (b.settings.maxDepth > 0);
  }
  for (FramePlan* p : {&a, &b}) {
    FrameSettings& r = p->raySettings;
    if (r.reflections != EffectMode::Ray && r.refraction != EffectMode::Ray) r.maxDepth = 0;  // no bounce traced
    if (r.shadows != EffectMode::Ray) r.hybridShadows = false;
  }
  return sameRayInputs(a, b);
}

/// The fields of the settings that change what a frame costs but not which choices there are: a change
/// re-measures the costs and keeps the ladder. Copies them from `from` into `to`.
void copyViewPart(const FrameSettings& from, FrameSettings& to) {
  to.width = from.width;
  to.height = from.height;
  to.debugView = from.debugView;
  to.exposure = from.exposure;
  to.toneMap = from.toneMap;
  to.reuseRays = from.reuseRays;
  to.probesPerFrame = from.probesPerFrame;
  to.probeSize = from.probeSize;
  to.targetMs = from.targetMs;
  to.pipelined = from.pipelined;
}

FrameSettings viewPart(const FrameSettings& s) {
  FrameSettings v;
  copyViewPart(s, v);
  v.targetMs = 0;  // a new target alone keeps the measured costs
  return v;
}

FrameSettings ladderPart(const FrameSettings& s) {
  FrameSettings k = s;
  copyViewPart(FrameSettings{}, k);
  return k;
}

}  // namespace

const BudgetErrorTable& budgetErrorTable() {
  // Mean FLIP added over hybrid-full by each knob alone, against the 8×8 (640×360) / 4×4 (1280×720) spp
  // reference: tandem-bench --sweep of 2026-11-23 on whitted.json, LightsPunctualLamp and TransmissionTest at
  // both sizes (docs/budget.md has the spread; the sweep prints its own measurement of this table to compare).
  static const BudgetErrorTable t{
      /*rayScale2*/ 0.0033, /*rayScale4*/ 0.0103,
      /*depth2*/ 0.0099,    /*depth1*/ 0.0534,
      /*refractionRaster*/ 0.0349,
      /*reflectionsRaster*/ 0.0223,
      /*shadowsRaster*/ 0.0012,
      // hybrid-full-1-denoised against hybrid-full, camera panning: area-lights.json -0.0092, glossy.json 0.0000
      // (sweep of 2026-11-29; the only scenes of the sweep it is offered for: distribution.json's thin lens and
      // open shutter are not).
      /*filtered*/ -0.0046,
  };
  return t;
}

std::string describeBudget(const BudgetStats& b) {
  if (!b.active) return {};
  if (b.step == 0) return "as requested";
  std::string s = "1/" + std::to_string(b.rayScale) + " d" + std::to_string(b.maxDepth);
  auto mode = [&](const char* name, EffectMode m) {
    if (m == EffectMode::Raster) s += std::string(" ") + name + " raster";
  };
  mode("refraction", b.refraction);
  mode("reflections", b.reflections);
  mode("shadows", b.shadows);
  if (b.denoise) s += " filtered";
  return s;
}

void FrameBudget::reset() {
  *this = FrameBudget{};
}

void FrameBudget::makeLadder(const FrameSettings& r, const SceneFacts& facts) {
  const BudgetErrorTable& table = budgetErrorTable();
  std::vector<BudgetChoice> all;
  std::vector<int> scales{r.rayScale};
  for (int s = r.rayScale * 2; s <= 4; s *= 2) scales.push_back(s);
  std::vector<int> depths{r.maxDepth};
  for (int d : {2, 1})
    if (d < r.maxDepth) depths.push_back(d);
  // The filter in place of the request's samples: where the scene samples something it smooths and the
  // request draws more than one sample of it raw (with one already, the filter would only add its cost), seen
  // through a camera its motion vectors model (on distribution.json, a thin lens and an open shutter, one
  // filtered sample measured FLIP 0.121 against four raw samples' 0.078).
  const bool offer = !r.denoise && !facts.lensOrShutter;
  const bool lightSampled = offer && facts.areaLight && r.lightSamples > 1;
  const bool glossSampled = offer && facts.glossy && r.glossSamples > 1;
  // Each ray-traced effect may fall back to raster on its own: which loses least is the table's to say.
  for (int fallback = 0; fallback < kFallbackSets; ++fallback) {
    FrameSettings f = r;
    double fallbackError = 0;
    if (fallback & kRefractionRaster) {
      if (f.refraction != EffectMode::Ray) continue;
      f.refraction = EffectMode::Raster;
      fallbackError += table.refractionRaster;
    }
    if (fallback & kReflectionsRaster) {
      if (f.reflections != EffectMode::Ray) continue;
      f.reflections = EffectMode::Raster;
      fallbackError += table.reflectionsRaster;
    }
    if (fallback & kShadowsRaster) {
      if (f.shadows != EffectMode::Ray) continue;
      f.shadows = EffectMode::Raster;
      f.hybridShadows = false;
      fallbackError += table.shadowsRaster;
    }
    // (a glossy lobe is sampled by rays only: with both bounces by probes there is none to filter)
    const bool filterable =
        lightSampled || (glossSampled && (f.reflections == EffectMode::Ray || f.refraction == EffectMode::Ray));
    for (int s : scales)
      for (int d : depths)
        for (bool filtered : {false, true}) {
          if (filtered && !filterable) continue;
          BudgetChoice c;
          c.settings = f;
          c.settings.rayScale = s;
          c.settings.maxDepth = d;
          if (filtered) {
            c.settings.denoise = true;
            c.settings.lightSamples = c.settings.glossSamples = 1;
          }
          c.rayScale = s;
          c.depthCap = d;
          c.fallback = fallback;
          c.filtered = filtered;
          c.error = fallbackError + scaleError(table, s) - scaleError(table, r.rayScale) + depthError(table, d) -
                    depthError(table, r.maxDepth) + (filtered ? table.filtered : 0.0);
          c.work = c.prior = priorWork(s, r.rayScale, d, r.maxDepth, fallback, filtered);
          all.push_back(c);
        }
  }
  // The request first (a budget with headroom draws what was asked for, though the filter's expected error is
  // below it), then least wrong first; among equals the cheaper by prior. Then drop choices that draw what a
  // kept one draws: the kept one is as good (a knob that changes nothing saves nothing, so its own prior stays).
  auto isRequest = [&](const BudgetChoice& c) {
    return c.fallback == 0 && !c.filtered && c.rayScale == r.rayScale && c.depthCap == r.maxDepth;
  };
  std::stable_sort(all.begin(), all.end(), [&](const BudgetChoice& a, const BudgetChoice& b) {
    if (isRequest(a) != isRequest(b)) return isRequest(a);
    return a.error != b.error ? a.error < b.error : a.work < b.work;
  });
  choices_.clear();
  std::vector<FramePlan> plans;
  for (BudgetChoice& c : all) {
    FramePlan p = planFrame(facts, c.settings);
    c.rays = p.rayPass;
    bool dup = false;
    for (std::size_t i = 0; i < plans.size() && !dup; ++i) dup = samePlan(plans[i], p);
    if (dup) continue;
    plans.push_back(p);
    choices_.push_back(c);
  }
  assert(!choices_.empty() && choices_[0].error == 0.0);
  filterOffered_ = std::any_of(choices_.begin(), choices_.end(), [](const BudgetChoice& c) { return c.filtered; });
}

void FrameBudget::reanchor() {
  haveRho_ = false;
  haveFixedBase_ = false;
  meanMs_ = 0;
  framesOnCurrent_ = 0;
}

double FrameBudget::predictMs(int i) const {
  const BudgetChoice& c = choices_[static_cast<std::size_t>(i)];
  if (!c.rays) return costMs(i, 0.0);
  if (!haveRho_) return std::numeric_limits<double>::quiet_NaN();
  const double pixels = static_cast<double>((width_ + c.rayScale - 1) / c.rayScale) *
                        static_cast<double>((height_ + c.rayScale - 1) / c.rayScale);
  return costMs(i, std::exp(logRho_ + c.work) * pixels);
}

double FrameBudget::costMs(int i, double rayMs) const {
  const BudgetChoice& c = choices_[static_cast<std::size_t>(i)];
  if (!haveFixedBase_) return std::numeric_limits<double>::quiet_NaN();
  const double fixed = std::exp(logFixedBase_ + fixedOffsetOf(c.fixedSet()));
  if (!c.rays) return fixed;
  // Throughput mode: the ray pass runs beside the GL's stages of the frames around it, so a frame costs the
  // slower of the two sides rather than their sum; the transfers (the ids read out, the results uploaded) lie
  // between one frame's landing and the next one's launch, on neither side.
  if (!(pipelined_ && overlapping_)) return fixed + rayMs;
  const double transfers = transferShare_ * rayMs;
  return std::max(fixed, rayMs - transfers) + transfers;
}

double FrameBudget::fixedOffsetOf(int set) const {
  if (fixedKnown_[set]) return fixedOffset_[set];
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  // Not yet drawn, with the filter: its raw twin's part plus the most the filter was seen to add to a set
  // drawn both ways (the filter's passes and guides, less the shading of one sample instead of several), on
  // this ray grid where it was drawn on it, else on any.
  if (isFilteredSet(set)) {
    double sameGrid = kNone, anyGrid = kNone;
    for (int f = kFallbackSets; f < kFixedSets; ++f) {
      if (!fixedKnown_[f] || !fixedKnown_[rawTwin(f)]) continue;
      const double added = fixedOffset_[f] - fixedOffset_[rawTwin(f)];
      anyGrid = std::max(anyGrid, added);
      if (f / kFallbackSets == set / kFallbackSets) sameGrid = std::max(sameGrid, added);
    }
    const double added = sameGrid > kNone ? sameGrid : anyGrid;
    if (added > kNone) return fixedOffsetOf(rawTwin(set)) + added;
  }
  // Otherwise the dearest set seen (a raster fallback or the filter adds GL passes): for a raw set, the
  // dearest raw one, so that it never takes on the filter's cost; the dearest of all where none is seen.
  double raw = kNone, any = kNone;
  for (int f = 0; f < kFixedSets; ++f) {
    if (!fixedKnown_[f]) continue;
    any = std::max(any, fixedOffset_[f]);
    if (!isFilteredSet(f)) raw = std::max(raw, fixedOffset_[f]);
  }
  return !isFilteredSet(set) && raw > kNone ? raw : any;
}

int FrameBudget::pick(double meanMs) {
  const int n = static_cast<int>(choices_.size());
  std::vector<double> pred(static_cast<std::size_t>(n));
  bool unknown = false;
  for (int i = 0; i < n; ++i) {
    pred[static_cast<std::size_t>(i)] = predictMs(i);
    unknown = unknown || std::isnan(pred[static_cast<std::size_t>(i)]);
  }
  auto fits = [&](int i, double fraction, double calibration = 1.0) {
    const double p = pred[static_cast<std::size_t>(i)];
    return !std::isnan(p) && p * calibration <= fraction * targetMs_;
  };
  // Out of reach only when every choice is predicted over the target (not while some are unknown).
  stats_.reachable = unknown;
  for (int i = 0; i < n && !stats_.reachable; ++i) stats_.reachable = fits(i, 1.0);
  if (framesOnCurrent_ == 0) return current_;  // nothing measured on it yet
  const double now = pred[static_cast<std::size_t>(current_)];
  // A choice's first frame may carry the switch itself (maps, probes, buffers at a new size): it is left
  // after one frame only when that frame ran far over.
  const bool over = framesOnCurrent_ >= 2 ? meanMs > kOver * targetMs_ : meanMs > kFarOver * targetMs_;
  if (over) {
    // Over: the least wrong choice predicted to fit with margin and cheaper than this one by the model. The
    // model is scaled by how far it is off on this choice right now (a resize, a stale set), so a choice it
    // underestimates like this one is not taken for one that fits.
    const double calibration = std::isnan(now) || now <= 0 ? 1.0 : std::clamp(meanMs / now, 0.5, 2.0);
    for (int i = 0; i < n; ++i) {
      const double p = pred[static_cast<std::size_t>(i)];
      if (i != current_ && fits(i, kFitDown, calibration) && p < (std::isnan(now) ? meanMs : now)) return i;
    }
    // None fits: the cheapest predicted, if it is clearly cheaper than this one by the model (not by a noisy
    // frame: at an unreachable target the cheapest choice itself runs over, and must stay).
    int best = current_;
    double bestMs = std::isnan(now) ? meanMs : std::min(now, meanMs);
    for (int i = 0; i < n; ++i) {
      const double p = pred[static_cast<std::size_t>(i)];
      if (!std::isnan(p) && p < kClearlyCheaper * bestMs) best = i, bestMs = p / kClearlyCheaper;
    }
    return best;
  }
  if (framesOnCurrent_ >= kQuietFrames && meanMs <= kQuietUp * targetMs_) {
    // Headroom: the least wrong choice better than this one that fits with the wider margin.
    for (int i = 0; i < current_; ++i)
      if (fits(i, kFitUp)) return i;
  }
  return current_;
}

FrameSettings FrameBudget::choose(const FrameSettings& requested, const SceneFacts& facts) {
  if (requested.targetMs <= 0.0f || requested.reference) {
    stats_ = {};
    idle_ = true;
    return requested;
  }
  // The ladder belongs to the requested settings (but for what only changes costs: size, view, target) and
  // to what the scene can show (a light that stops casting shadows): any other change makes a new one.
  const FrameSettings key = ladderPart(requested);
  if (!haveLadder_ || !(key == requested_) || !(facts == facts_)) {
    reset();
    requested_ = key;
    facts_ = facts;
    makeLadder(requested, facts);
    haveLadder_ = true;
  } else if (idle_ || !(viewPart(requested) == view_)) {
    // Back from no budget, a new size or view: the same choices, costs measured again from this frame
    // (what each choice costs relative to the others is kept).
    reanchor();
  }
  idle_ = false;
  view_ = viewPart(requested);
  width_ = requested.width;
  height_ = requested.height;
  targetMs_ = requested.targetMs;
  pipelined_ = requested.pipelined;
  const int next = pick(meanMs_);
  if (next != current_) {
    current_ = next;
    framesOnCurrent_ = 0;
    meanMs_ = 0;
  }
  const BudgetChoice& c = choices_[static_cast<std::size_t>(current_)];
  FrameSettings s = c.settings;
  copyViewPart(requested, s);
  stats_.active = true;
  stats_.step = current_;
  stats_.steps = static_cast<int>(choices_.size());
  stats_.rayScale = s.rayScale;
  stats_.maxDepth = s.maxDepth;
  stats_.shadows = s.shadows;
  stats_.hybridShadows = s.hybridShadows;
  stats_.reflections = s.reflections;
  stats_.refraction = s.refraction;
  stats_.denoise = c.filtered;
  stats_.targetMs = targetMs_;
  const double p = predictMs(current_);
  stats_.predictedMs = std::isnan(p) ? 0.0 : p;
  stats_.expectedError = c.error;
  return s;
}

void FrameBudget::observeShown(FrameStats shown, double intervalMs) {
  shown.totalMs = shown.stagesMs();
  shown.intervalMs = intervalMs;
  observe(shown);
}

void FrameBudget::observe(const FrameStats& frame) {
  if (!stats_.active || !haveLadder_) return;
  // Throughput mode shows a frame a call after its choice was made: one drawn with a choice the budget has
  // since left teaches nothing about the current one.
  if (frame.budget.active && frame.budget.step != current_) return;
  // Whether frames overlap: throughput mode asked for and taken (not a latency-mode frame: several samples,
  // accumulating at rest), and not draining every time (two drains running).
  overlapping_ = frame.pipelined && !(frame.pipelineDrained && lastDrained_);
  lastDrained_ = frame.pipelined && frame.pipelineDrained;
  // A frame that compiled shaders or failed says nothing about the steady cost, nor does one that only showed
  // an accumulation that had converged (FrameSettings::accumulate: it drew no sample).
  if (!frame.error.empty() || frame.shaderCompiles > 0 || frame.samples == 0) return;
  BudgetChoice& c = choices_[static_cast<std::size_t>(current_)];
  const double total = frame.totalMs;
  const double rayMs = frame.readbackMs + frame.raysMs + frame.uploadMs;
  // The fixed part (reused frames teach it too: they skip only the rays), as the ray part below: the first
  // frame anchors the scale, a set's first frames teach its offset, later ones the drift.
  // A choice's first frame is left out of it: it carries the switch (shadow maps and probes drawn for
  // the first time, buffers at a new size), which would otherwise stay in the set's cost for good.
  const double fixedLog = std::log(std::max(total - rayMs, 0.01));
  const int set = c.fixedSet();
  if (framesOnCurrent_ == 0) {
    // (the ray part below still learns from it: a first frame over the target is left at once)
  } else if (!haveFixedBase_) {
    if (!fixedKnown_[set]) fixedOffset_[set] = 0.0, fixedKnown_[set] = true;
    logFixedBase_ = fixedLog - fixedOffset_[set];
    haveFixedBase_ = true;
  } else if (!fixedKnown_[set]) {
    fixedOffset_[set] = fixedLog - logFixedBase_;
    fixedKnown_[set] = true;
    fixedFrames_[set] = 1;
  } else if (fixedFrames_[set] < kLearnFrames) {
    fixedOffset_[set] += 0.5 * (fixedLog - logFixedBase_ - fixedOffset_[set]);
    ++fixedFrames_[set];
  } else {
    logFixedBase_ += 0.3 * (fixedLog - logFixedBase_ - fixedOffset_[set]);
  }
  // A frame that traced: rayWidth is 0 when the plan lost its rays (Embree refused the scene).
  if (c.rays && !frame.raysReused && rayMs > 0 && frame.rayWidth > 0 && frame.rayHeight > 0) {
    const double pixels = static_cast<double>(frame.rayWidth) * static_cast<double>(frame.rayHeight);
    const double measured = std::log(rayMs / pixels);
    const double share = std::clamp((frame.readbackMs + frame.uploadMs) / rayMs, 0.0, 1.0);
    transferShare_ = haveShare_ ? 0.5 * (transferShare_ + share) : share;
    haveShare_ = true;
    if (!haveRho_) {
      logRho_ = measured - c.work;  // the first frame anchors the scale of every choice's work
      haveRho_ = true;
    } else if (c.framesRun < kLearnFrames) {
      const double delta = measured - logRho_ - c.work;
      c.work += c.framesRun == 0 ? delta : 0.5 * delta;
      // What one filtered sample saves depends on the scene (how much of its rays the sampled lights and lobes
      // are): the filtered choices not yet run take this one's correction of the prior.
      if (c.filtered)
        for (BudgetChoice& x : choices_)
          if (x.filtered && x.framesRun == 0) x.work = x.prior + (c.work - c.prior);
    } else {
      logRho_ += 0.3 * (measured - logRho_ - c.work);  // the scene's drift moves every choice alike
    }
    ++c.framesRun;
  }
  // The smoothed frame time of the current choice decides when to move (reused frames count: they are
  // what the player gets). In throughput mode that is the interval between frames; its stages above still
  // teach the two sides' costs.
  // A drained frame did not overlap (its interval holds the frame before it too): its own stages count.
  double shown = frame.pipelined && !frame.pipelineDrained && frame.intervalMs > 0 ? frame.intervalMs : total;
  // A choice's first frame carries the switch in its GL part, which the fixed part above leaves out: on a
  // software GL the first draws in a new state compile the shaders' variants for it (0.9-1.6 s at 640x360 on 2
  // cores in the sweep's budget runs, with no program built, and again when a state comes back), besides the
  // maps, probes and buffers first drawn. It counts as its own rays with the fixed part the model predicts, where
  // that is less: far over by these it is still left at once, and its next frames show the rest.
  if (framesOnCurrent_ == 0) {
    const bool traced = c.rays && !frame.raysReused && rayMs > 0;
    const double steady = traced ? costMs(current_, rayMs) : predictMs(current_);
    if (!std::isnan(steady)) shown = std::min(shown, steady);
  }
  meanMs_ = framesOnCurrent_ == 0 ? shown : 0.5 * meanMs_ + 0.5 * shown;
  ++framesOnCurrent_;
}

}  // namespace tandem
