#pragma once
// RayTracer's state, for the two files that run passes on it: RayTracer.cpp (the frame's) and
// RayTracerBench.cpp (the bench's re-trace). Its own type, not RayTracer::Impl, so that this header
// need not include RayTracer.h.
#include <memory>

#include <tbb/task_arena.h>

#include "rt/EmbreeScene.h"
#include "rt/RayReuse.h"
#include "rt/ShadowCertainty.h"
#include "rt/TileShafts.h"
#include "tandem/Progress.h"

namespace tandem::rt {

struct RayTracerState {
  int threads = 1;
  tbb::task_arena arena;
  std::unique_ptr<EmbreeDevice> device;
  std::unique_ptr<EmbreeScene> scene;
  RayPassProgressCallback progress;  // setProgressCallback
  std::shared_ptr<const RadiosityField> radiosity;  // setRadiosity
  std::vector<ReuseBox> meshBounds;  // object space, per mesh of the scene (reuse across frames)
  std::vector<int> planes;  // per mesh of the scene: axisPlane (hybrid shadows' tile shafts)
  // Hybrid shadows' light-space maps: built by the first pass that needs them after the geometry
  // (setScene, updateTransforms) or a light changed.
  ShadowCertainty shadowMaps;
  bool shadowMapsStale = true;
  std::size_t shadowMapBuilds = 0;
  double lastShadowMapMs = 0.0;  // the last pass's build of them (0: none)
};

}  // namespace tandem::rt
