#include "render/Accumulation.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "core/Sampling.h"
#include "render/Adaptive.h"

namespace tandem {

Accumulation::Step Accumulation::step(const Camera& camera, const FrameSettings& settings, const Since& since) const {
  const bool same = active_ && since.lastDrawn && !since.sceneChanged && since.probesCurrent && camera_ == camera &&
                    settings_ == settings;
  // The motion view draws each frame's own motion: a mean over frames would blend the motions of several.
  if (!same || settings.accumulate <= 1 || settings.debugView == DebugView::Motion) return Step::Restart;
  return frames_ >= settings.accumulate ? Step::Converged : Step::GoOn;
}

void Accumulation::restart(const Camera& camera, const FrameSettings& settings, std::uint32_t firstSample,
                           bool filtered) {
  // The sums are set up by the first add, not here: while things move a game restarts every frame and shows
  // its one sample as drawn (firstUnread), and zeroing fresh sums would cost it every frame (at 1920x1080 the
  // 58 MB of new pages took ~35 ms on the GPU machine). The buffers keep their memory between restarts.
  jitterScale_ = filtered && active_
                     ? filteredJitterScale(cameraMotionPx(camera_, camera, {settings.width, settings.height}))
                     : 1.0f;
  active_ = true;
  camera_ = camera;
  settings_ = settings;
  frames_ = 0;
  next_ = firstSample;
  firstUnread = firstFiltered_ = false;
  summing_ = false;
  handover_ = ImageF{};
}

void Accumulation::startSums() {
  const std::size_t n = static_cast<std::size_t>(settings_.width) * static_cast<std::size_t>(settings_.height);
  sum_.assign(n, glm::dvec3(0.0));
  count_.assign(n, 0u);
  if (settings_.aa == AntiAlias::Adaptive) {
    lo_.assign(n, std::numeric_limits<float>::infinity());
    hi_.assign(n, -std::numeric_limits<float>::infinity());
  } else {
    lo_.clear();
    hi_.clear();
  }
  summing_ = true;
}

float cameraMotionPx(const Camera& before, const Camera& now, glm::ivec2 size) {
  const glm::ivec2 pixels(std::max(size.x, 1), std::max(size.y, 1));
  const glm::vec2 frame(pixels);
  // Points relative to `before`'s eye, through its view's rotation alone: far from the origin a world-space
  // view matrix's translation would round a still camera's points by pixels (37 at 1e6).
  const glm::mat4 clipFromEye = before.clipFromView(frame.x / frame.y) * glm::mat4(glm::mat3(before.viewFromWorld()));
  // Where a point `now` shows at `at` (pixels, y down), `fromEye` from `before`'s eye, lay in `before`'s frame,
  // and so how far it moved.
  auto moved = [&](glm::vec3 fromEye, glm::vec2 at) {
    const glm::vec4 clip = clipFromEye * glm::vec4(fromEye, 1.0f);
    if (!(clip.w > 0.0f)) return std::numeric_limits<float>::infinity();
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return glm::length(glm::vec2(0.5f + 0.5f * ndc.x, 0.5f - 0.5f * ndc.y) * frame - at);
  };
  // The target (the frame's centre), and the points the frame's corners show at the target's distance along
  // the view axis: a dolly or a turn moves the corners most, a strafe every point at that distance alike.
  const glm::vec3 eyeMoved = now.posW - before.posW;
  float most = moved(now.targetW - before.posW, 0.5f * frame);
  Camera centred = now;
  centred.jitterPx = glm::vec2(0.0f);
  const glm::vec3 forward = glm::normalize(now.targetW - now.posW);
  const float depth = glm::dot(now.targetW - now.posW, forward);
  for (const glm::vec2 corner : {glm::vec2(0.0f), glm::vec2(frame.x, 0.0f), glm::vec2(0.0f, frame.y), frame}) {
    const Ray ray = centred.rayThroughPixel(corner, pixels);
    // (a perspective ray from the eye: the target's depth along it; an orthographic one from the image plane;
    // within a field of view under 180 degrees `along` is positive)
    const glm::vec3 offset = ray.origin - now.posW;
    const float along = glm::dot(ray.dir, forward);
    const glm::vec3 fromNowEye = offset + ray.dir * ((depth - glm::dot(offset, forward)) / along);
    most = std::max(most, moved(eyeMoved + fromNowEye, corner));
  }
  return most;
}

float filteredJitterScale(float motionPx) { return glm::clamp((3.0f - motionPx) / 1.5f, 0.0f, 1.0f); }

Camera filteredSample(const Camera& camera, std::uint32_t index, float jitterScale) {
  Camera sample = sampleCamera(camera, index);
  sample.jitterPx *= jitterScale;
  return sample;
}

Camera FilteredSequence::next(const Camera& camera, glm::ivec2 size) {
  const float motionPx = haveLast_ ? cameraMotionPx(last_, camera, size) : 0.0f;
  last_ = camera;
  haveLast_ = true;
  lastScale_ = filteredJitterScale(motionPx);
  return filteredSample(camera, frames_++, lastScale_);
}

Camera sampleCamera(const Camera& camera, std::uint32_t index) {
  Camera jittered = camera;
  jittered.sampleIndex = index;  // new light samples with each new sub-pixel offset
  jittered.jitterPx = subpixelJitter(index);
  if (camera.aperture > 0.0f) jittered.lensUv = lensSample(index);  // and a new point of the lens
  if (camera.shutter > 0.0f) jittered.timeU = timeSample(index);   // and a new time in the shutter
  return jittered;
}

Camera Accumulation::nextSample(const Camera& camera) {
  return filteredSample(camera, next_++, std::exchange(jitterScale_, 1.0f));
}

void Accumulation::add(const ImageF& linear, const std::vector<std::uint8_t>* only) {
  const std::size_t n = static_cast<std::size_t>(settings_.width) * static_cast<std::size_t>(settings_.height);
  if (!active_ || linear.rgb.size() != n || (only != nullptr && only->size() != n)) return;
  if (firstFiltered_) {
    firstFiltered_ = false;
    handover_ = linear;
    return;
  }
  if (!summing_) startSums();
  const bool adaptive = settings_.aa == AntiAlias::Adaptive;
  for (std::size_t i = 0; i < n; ++i) {
    if (only != nullptr && (*only)[i] == 0) continue;
    sum_[i] += glm::dvec3(linear.rgb[i]);
    ++count_[i];
    if (adaptive) {
      const float l = displayLuminance(linear.rgb[i], settings_);
      lo_[i] = std::min(lo_[i], l);
      hi_[i] = std::max(hi_[i], l);
    }
  }
}

bool Accumulation::nextRound(std::vector<std::uint8_t>& refine, std::vector<std::uint8_t>& traced) const {
  if (!summing_) return false;  // no samples to compare
  return adaptiveRound(lo_, hi_, count_, settings_.width, settings_.height, settings_.aaThreshold, settings_.rayScale,
                       refine, traced);
}

const ImageF& Accumulation::mean() {
  mean_.width = settings_.width;
  mean_.height = settings_.height;
  mean_.rgb.resize(static_cast<std::size_t>(settings_.width) * static_cast<std::size_t>(settings_.height));
  for (std::size_t i = 0; i < mean_.rgb.size(); ++i)
    mean_.rgb[i] = summing_ && count_[i] > 0 ? glm::vec3(sum_[i] / static_cast<double>(count_[i])) : glm::vec3(0.0f);
  return mean_;
}

const ImageF& Accumulation::shown() {
  const ImageF& m = mean();
  if (handover_.rgb.size() != m.rgb.size()) return m;
  // Linear in the samples: the filtered frame's error is mostly bias, the mean's noise falls as 1/sqrt(n); by
  // about 16 one-sample frames their errors are alike (docs/denoise.md).
  const int span = std::max(1, std::min(settings_.accumulate, 16) - 1);
  const float w = std::min(1.0f, static_cast<float>(mostSamples()) / static_cast<float>(span));
  if (w >= 1.0f) {
    handover_ = ImageF{};  // handed over: the exact mean from here on
    return m;
  }
  shown_ = m;
  for (std::size_t i = 0; i < shown_.rgb.size(); ++i) shown_.rgb[i] = glm::mix(handover_.rgb[i], m.rgb[i], w);
  return shown_;
}

int Accumulation::mostSamples() const {
  return !summing_ || count_.empty() ? 0 : static_cast<int>(*std::max_element(count_.begin(), count_.end()));
}

}  // namespace tandem
