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

namespace tandem {

class RadiosityJob {
 public:
  RadiosityJob() = default;
  ~RadiosityJob();
  RadiosityJob(const RadiosityJob&) = delete;
  RadiosityJob& operator=(const RadiosityJob&) = delete;

  /// What the solution depends on changed (an instance moved, a light changed, a new scene): the next sync
  /// starts again from the scene as it is then.
  /// `sceneReplaced`: the solution shown so far belongs to another scene and is dropped at once; otherwise
  /// (something moved) it stays on screen until the new solve publishes.
  void invalidate(bool sceneReplaced);
  /// Brings the solution to `settings` for `scene`: in the background (radiosityBackground), starts a solve
  /// when none runs for this scene and these options and hands back the latest solution it published;
  /// otherwise solves on this thread, when the scene or options changed, until radiosityError or
  /// radiosityShots. True when field() changed since the last call.
  bool sync(const Scene& scene, const FrameSettings& settings);
  /// Stops a solve and frees the solution (radiosity turned off).
  void release();
  /// The latest solution (null before the first is published).
  std::shared_ptr<const RadiosityField> field() const { return shown_; }
  RadiosityStats stats() const;

 private:
  struct Options {
    int patches = 0;
    float error = 0.0f;
    int shots = 0;
    bool operator==(const Options&) const = default;
  };
  struct Shared;  // what the solving thread and the frame's thread share
  void stop();
  static void solve(Shared& shared, const Scene& scene, Options options, bool background);

  std::shared_ptr<Shared> shared_;
  std::thread worker_;
  // Solves told to stop that may still be finishing a shot: joined once done (or at destruction), so a
  // restart never waits for one.
  struct Retired {
    std::thread thread;
    std::shared_ptr<Shared> shared;
  };
  std::vector<Retired> retired_;
  bool stale_ = true;
  Options options_;
  bool background_ = false;
  std::shared_ptr<const RadiosityField> shown_;
};

}  // namespace tandem
