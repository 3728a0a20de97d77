#pragma once
// Anti-aliasing and progressive accumulation (FrameSettings::aa and accumulate; docs/antialiasing.md) as one
// unit without GL, so its decisions are unit tests (tests/unit/AccumulationTest.cpp): the samples drawn so far
// for the camera, scene and settings they were drawn with, summed per pixel in linear radiance; whether a frame
// goes on with them, starts again or has nothing left to add; each sample's camera; adaptive rounds; the mean
// to show. The Renderer draws the samples it is asked for and hands their linear frames here.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "render/FramePlan.h"
#include "tandem/Camera.h"
#include "tandem/Image.h"
#include "tandem/Settings.h"

namespace tandem {

/// The camera of sample `index` of a sequence: its sub-pixel offset, its index for light and gloss samples, and
/// where the camera has a lens or a shutter, its lens point and time (core/Sampling.h's sequences).
Camera sampleCamera(const Camera& camera, std::uint32_t index);
/// How far a frame of `size` pixels moves on screen from camera `before` to `now`: the most any of five points
/// moved since `before`'s view, `now`'s target (the centre of its frame) and the points its frame's corners show
/// at the target's distance along the view axis (a rotation's motion at any depth, a translation's at the
/// target's distance: the points the camera looks at; a dolly moves the corners and not the centre).
/// Infinite when one of them was behind `before`.
float cameraMotionPx(const Camera& before, const Camera& now, glm::ivec2 size);
/// The sub-pixel offset's scale for a frame the spatiotemporal filter draws while the camera moves `motionPx`
/// a frame: 1 up to 1.5 pixels, falling to 0 (the pixel centres) at 3 and beyond. A jittered frame pays only
/// where its history lasts long enough to average the offsets out; a camera moving pixels a frame shortens
/// the anti-aliasing's history (denoise.frag, over the same range) and the offsets showed as edges jumping by
/// up to a pixel (docs/denoise.md: the game's run, 2 to 16 pixels a frame, FLIP 0.033 with the offsets down to
/// 8 pixels, 0.030 so; a slow pan keeps them).
float filteredJitterScale(float motionPx);
/// sampleCamera with its sub-pixel offset scaled by `jitterScale` (filteredJitterScale).
Camera filteredSample(const Camera& camera, std::uint32_t index, float jitterScale);

/// The filter's samples (FrameSettings::denoise): each filtered frame draws the next sample of one sequence, so
/// that its history gathers new ones, with its sub-pixel offset scaled by how far the view moved since the
/// frame next() drew before it (filteredJitterScale of cameraMotionPx, frame to frame: a camera that slows down
/// gets its offsets back). An accumulation's first frame takes its index from the same sequence (take(); its
/// offset is Accumulation::restart's to scale).
class FilteredSequence {
 public:
  /// The next filtered frame's camera, from `camera` (as the application gave it) at `size` pixels.
  Camera next(const Camera& camera, glm::ivec2 size);
  /// The next index without a camera (an accumulation's first frame: Accumulation::restart scales its offset).
  std::uint32_t take() { return frames_++; }
  /// The scale next() gave the last sample's offset.
  float lastScale() const { return lastScale_; }

 private:
  std::uint32_t frames_ = 0;
  bool haveLast_ = false;
  Camera last_;  // the last filtered frame's camera, as given (not jittered)
  float lastScale_ = 1.0f;
};

class Accumulation {
 public:
  /// What a frame does with the samples so far.
  enum class Step {
    Restart,    // draw from nothing: something they show changed (or there are none)
    GoOn,       // add this frame's samples to them
    Converged,  // `accumulate` frames are in: the mean on show stays, nothing is drawn
  };

  /// What the frame as it stands has changed since the samples, for `step`.
  struct Since {
    bool lastDrawn = false;      // the last frame was drawn (a frame that failed leaves the targets unknown)
    bool sceneChanged = false;   // an instance, a light or the scene changed since it
    bool probesCurrent = true;   // no probe is still catching up with a move (probesPerFrame > 0)
  };

  /// Pure: the samples go on only while nothing they show changed: the camera as the application gave it
  /// (unjittered), the scene, the settings (the plan's, which hold the size) and the probes.
  Step step(const Camera& camera, const FrameSettings& settings, const Since& since) const;

  /// Starts again from nothing for `camera` and `settings` (its size): sums, counts, and for adaptive
  /// anti-aliasing each pixel's smallest and largest display luminance.
  /// `firstSample`: the sequence index the samples start from (the filter's frames go on along the sequence
  /// so that each draws new samples; 0 otherwise). `filtered`: the first frame is the filter's, its sub-pixel
  /// offset scaled by how far the camera moved since the last restart (filteredJitterScale).
  void restart(const Camera& camera, const FrameSettings& settings, std::uint32_t firstSample = 0,
               bool filtered = false);
  /// Frees everything (cost follows the settings: a frame without anti-aliasing or accumulation holds none).
  void release() { *this = Accumulation{}; }
  bool active() const { return active_; }
  /// Whether the sums are set up: from the first sample added after a restart (a restart itself touches no
  /// per-pixel memory).
  bool holdsSums() const { return summing_; }

  /// The next sample's camera: its sub-pixel offset, its index for light samples, and where the camera has a
  /// lens or a shutter, its lens point and time (core/Sampling.h's sequences, in order).
  Camera nextSample(const Camera& camera);

  /// Whether this frame is the accumulation's first and draws one sample (no anti-aliasing): it is shown as
  /// drawn, and read into the sums only if the next frame goes on (firstUnread).
  bool singleSample(const FrameSettings& settings) const { return frames_ == 0 && settings.aa == AntiAlias::Off; }
  /// The plan each of this frame's samples is drawn with. Several samples in one frame must all see the same
  /// probes: the first sample draws every probe that is not current (probesPerFrame 0: a new scene's too, which
  /// with a budget would show the environment in that sample) instead of a few by each. A frame of one sample
  /// catches up as a plain frame does.
  /// The spatiotemporal filter runs only on a first frame shown as drawn: the samples summed after it are
  /// drawn as they are (their mean converges to the exact image; shown() hands over to it from the filtered
  /// frame).
  FramePlan samplePlan(const FramePlan& plan) const {
    if (singleSample(plan.settings)) return plan;
    FramePlan sample = plan;
    sample.withoutFilter();
    sample.settings.probesPerFrame = 0;
    return sample;
  }
  /// Adds a sample's linear frame at the pixels `only` marks (nullptr: all). A frame of another size (a debug
  /// view has no linear frame) adds nothing. The first frame's, when the filter drew it (firstShown(true)), is
  /// kept to hand over from instead: it is not a sample of the mean.
  void add(const ImageF& linear, const std::vector<std::uint8_t>* only);

  /// Adaptive: the next round's pixels (`refine`) and the pixels whose rays it traces (`traced`;
  /// render/Adaptive.h). False when no pixel's samples disagree.
  bool nextRound(std::vector<std::uint8_t>& refine, std::vector<std::uint8_t>& traced) const;

  /// The mean of each pixel's samples (black where none).
  const ImageF& mean();
  /// What to show: the mean, or after a first frame the filter drew, the mean blended with that frame, whose
  /// weight falls linearly to nothing over the first min(accumulate, 16) − 1 samples: a view that stops is
  /// never shown the raw mean of a few samples (noisier than the filtered frame), and the last frames of the
  /// accumulation are its exact mean.
  const ImageF& shown();
  /// Whether the last shown() still blended the filtered frame in (a reconstruction: FrameStats::denoised).
  bool handingOver() const { return !handover_.rgb.empty(); }
  /// The most samples any pixel has.
  int mostSamples() const;

  /// Frames whose samples are in the sums.
  int frames() const { return frames_; }
  void frameDone() { ++frames_; }
  /// Adaptive: no pixel disagrees any more, so the accumulation has converged early.
  void convergedEarly() { frames_ = std::max(frames_, settings_.accumulate); }
  /// The first frame's one sample is shown as drawn and read into the sums only if the next frame goes on
  /// (`firstUnread`): a game that accumulates at rest pays nothing for it while things move.
  bool firstUnread = false;
  /// The first frame is on show as drawn (its one sample, or `filtered`: the filter's reconstruction).
  void firstShown(bool filtered) {
    firstUnread = true;
    firstFiltered_ = filtered;
  }

 private:
  void startSums();  // zeroed sums and counts (adaptive: the luminance bounds) for the settings' size
  bool active_ = false;
  bool summing_ = false;     // the sums hold this restart's samples (false until the first add)
  Camera camera_;            // as the application gave it, without jitter
  FrameSettings settings_;   // the plan's
  int frames_ = 0;
  std::uint32_t next_ = 0;   // index of the next sample's sub-pixel offset (subpixelJitter)
  float jitterScale_ = 1.0f; // the next sample's sub-pixel offset scale (the filter's first: filteredSample)
  std::vector<glm::dvec3> sum_;  // double: 65536 frames of 256 samples would drift in float
  std::vector<std::uint32_t> count_;
  std::vector<float> lo_, hi_;  // adaptive: each pixel's samples' smallest and largest display luminance
  ImageF mean_;
  bool firstFiltered_ = false;  // the first frame on show is the filter's: add() keeps it in handover_
  ImageF handover_;             // that frame, while shown() still blends it in
  ImageF shown_;
};

}  // namespace tandem
