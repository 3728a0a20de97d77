#pragma once
// A frame stage's time: the frame (Renderer.cpp) and throughput mode (PipelinedFrame.cpp) time each stage
// call into its FrameStats field with it. Internal to render/.
#include <type_traits>

#include "core/Timer.h"

namespace tandem {

/// Runs (part of) a stage and adds its time to the stage's `ms`; returns what the stage returns.
template <class F>
auto timed(double& ms, F&& stage) {
  Timer clock;
  if constexpr (std::is_void_v<decltype(stage())>) {
    stage();
    ms += clock.ms();
  } else {
    auto result = stage();
    ms += clock.ms();
    return result;
  }
}

}  // namespace tandem
