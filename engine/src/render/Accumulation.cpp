#include "render/Accumulation.h"

#include <limits>

#include "core/Sampling.h"
#include "render/Adaptive.h"

namespace tandem {

Accumulation::Step Accumulation::step(const Camera& camera, const FrameSettings& settings, const Since& since) const {
  const bool same = active_ && since.lastDrawn && !since.sceneChanged && since.probesCurrent && camera_ == camera &&
                    settings_ == settings;
  if (!same || settings.accumulate <= 1) return Step::Restart;
  return frames_ >= settings.accumulate ? Step::Converged : Step::GoOn;
}

void Accumulation::restart(const Camera& camera, const FrameSettings& settings) {
  release();
  active_ = true;
  camera_ = camera;
  settings_ = settings;
  const std::size_t n = static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height);
  sum_.assign(n, glm::dvec3(0.0));
  count_.assign(n, 0u);
  if (settings.aa == AntiAlias::Adaptive) {
    lo_.assign(n, std::numeric_limits<float>::infinity());
    hi_.assign(n, -std::numeric_limits<float>::infinity());
  }
}

Camera Accumulation::nextSample(const Camera& camera) {
  Camera jittered = camera;
  jittered.sampleIndex = next_;  // new light samples with each new sub-pixel offset
  jittered.jitterPx = subpixelJitter(next_);
  if (camera.aperture > 0.0f) jittered.lensUv = lensSample(next_);  // and a new point of the lens
  if (camera.shutter > 0.0f) jittered.timeU = timeSample(next_);   // and a new time in the shutter
  ++next_;
  return jittered;
}

void Accumulation::add(const ImageF& linear, const std::vector<std::uint8_t>* only) {
  const std::size_t n = sum_.size();
  if (linear.rgb.size() != n || (only != nullptr && only->size() != n)) return;
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
  return adaptiveRound(lo_, hi_, count_, settings_.width, settings_.height, settings_.aaThreshold, settings_.rayScale,
                       refine, traced);
}

const ImageF& Accumulation::mean() {
  mean_.width = settings_.width;
  mean_.height = settings_.height;
  mean_.rgb.resize(sum_.size());
  for (std::size_t i = 0; i < sum_.size(); ++i)
    mean_.rgb[i] = count_[i] > 0 ? glm::vec3(sum_[i] / static_cast<double>(count_[i])) : glm::vec3(0.0f);
  return mean_;
}

int Accumulation::mostSamples() const {
  return count_.empty() ? 0 : static_cast<int>(*std::max_element(count_.begin(), count_.end()));
}

}  // namespace tandem
