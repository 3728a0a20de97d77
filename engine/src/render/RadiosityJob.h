#pragma once
// The frame's radiosity solution (FrameSettings::radiosity; docs/radiosity.md): a cache derived from the
// scene like the GL copy and the Embree scene, solved by rt::RadiositySolver on a copy of the scene with an
// Embree scene of its own, so that a background solve never races the frame's ray pass or its commits.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "core/Radiosity.h"
#include "tandem/FrameStats.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

#include "render/SceneChanges.h"

namespace tandem {

class RadiosityJob {
 public:
  RadiosityJob() = default;
  ~RadiosityJob();
  RadiosityJob(const RadiosityJob&) = delete;
  RadiosityJob& operator=(const RadiosityJob&) = delete;

  /// What the scene's changes mean for the solution. The geometry (a static instance moved, or a new scene):
  /// the next sync starts again from the scene as it is then; a replaced scene's solution is dropped at once
  /// and its solve stopped; after a move the old solution stays on screen until the new solve publishes,
  /// and in the background a solve that has not published yet is let run until it does (a static instance
  /// moved every frame still shows solutions). Dynamic instances are not in the solution. Only the lights:
  /// in the background the running solve takes the new lights (at most ~10 times a second) and carries its
  /// solution over (RadiositySolver::relight); before the frame, the next sync solves again.
  void apply(const SceneChanges& changes);
  /// Brings the solution to `settings` for `scene`: in the background (radiosityBackground), starts a solve
  /// when none runs for this scene and these options and hands back the latest solution it published;
  /// otherwise solves on this thread (on `threads` TBB threads, 0: all), when the scene or options changed,
  /// until radiosityError or radiosityShots. True when field() changed since the last call.
  bool sync(const Scene& scene, const FrameSettings& settings, int threads = 0);
  /// Stops a solve and frees the solution (radiosity turned off).
  void release();
  /// Whether a solve runs or a solution is held (what release() would free).
  bool holds() const { return shared_ != nullptr || shown_ != nullptr; }
  /// The latest solution (null before the first is published).
  std::shared_ptr<const RadiosityField> field() const { return shown_; }
  /// What the solution field() holds is: its patches, shots, residual, solve time (published with it).
  RadiosityStats stats() const { return shownStats_; }

 private:
  struct Options {
    int patches = 0;
    float error = 0.0f;
    int shots = 0;
    bool refine = true;
    bool operator==(const Options&) const = default;
  };
  struct Shared;  // what the solving thread and the frame's thread share
  void stop();
  static void solve(Shared& shared, Scene scene, Options options, bool background);

  bool stale_ = true;
  bool replaced_ = false;
  bool lightsStale_ = false;
  Options options_;
  bool background_ = false;
  std::shared_ptr<Shared> shared_;
  std::thread worker_;
  // Solves told to stop that may still be finishing a step: joined once done (or at destruction), so a
  // restart never waits for one.
  struct Retired {
    std::thread thread;
    std::shared_ptr<Shared> shared;
  };
  std::vector<Retired> retired_;
  std::shared_ptr<const RadiosityField> shown_;
  RadiosityStats shownStats_;
};

}  // namespace tandem
