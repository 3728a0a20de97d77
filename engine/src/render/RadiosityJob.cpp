#include "render/RadiosityJob.h"

#include <algorithm>
#include <climits>
#include <optional>
#include <string>

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <tbb/task_arena.h>

#include "core/Timer.h"
#include "rt/EmbreeScene.h"
#include "rt/Radiosity.h"
#include "tandem/Log.h"

namespace tandem {

namespace {
// Every published solution gets a version of its own, across jobs and restarts: the GL copy and the frame's
// reuse compare versions, never pointers.
std::atomic<std::uint64_t> nextVersion{1};
}  // namespace

struct RadiosityJob::Shared {
  std::mutex mutex;
  std::condition_variable wake;  // new lights or stop, for a solve that has converged
  std::shared_ptr<const RadiosityField> published;
  RadiosityStats stats;
  std::optional<std::vector<Light>> pendingLights;  // the background solve takes them at its next shot
  std::atomic<bool> stop{false};
  std::atomic<bool> done{false};
  std::atomic<bool> publishedOnce{false};
  Scene scene;  // the background solve's copy
};

RadiosityJob::~RadiosityJob() {
  stop();
  for (Retired& r : retired_) r.thread.join();
}

void RadiosityJob::invalidate(bool sceneReplaced) {
  stale_ = true;
  if (sceneReplaced) shown_.reset();
}

void RadiosityJob::lightsChanged() { lightsStale_ = true; }

void RadiosityJob::stop() {
  if (shared_) {
    std::lock_guard lock(shared_->mutex);
    shared_->stop = true;
    shared_->wake.notify_all();
  }
  if (worker_.joinable()) retired_.push_back({std::move(worker_), shared_});
  shared_.reset();
  // Join the solves that have finished; the others are left to finish their shot.
  for (auto it = retired_.begin(); it != retired_.end();) {
    if (it->shared->done) {
      it->thread.join();
      it = retired_.erase(it);
    } else {
      ++it;
    }
  }
}

void RadiosityJob::release() {
  stop();
  shown_.reset();
  stale_ = true;
  lightsStale_ = false;
}

void RadiosityJob::solve(Shared& shared, const Scene& full, Options options, bool background) {
  const Timer timer;
  // Dynamic instances stay out of the solution, as patches and as blockers: a game moves them every frame,
  // and a solve restarted at every move would never show anything. The ambient term lights them.
  std::vector<std::uint32_t> solved;
  Scene scene;
  scene.meshes = full.meshes;
  scene.materials = full.materials;
  scene.textures = full.textures;
  scene.lights = full.lights;
  scene.camera = full.camera;
  bool anyDynamic = false;
  for (std::size_t i = 0; i < full.instances.size(); ++i) {
    if (full.instances[i].dynamic) {
      anyDynamic = true;
    } else {
      solved.push_back(static_cast<std::uint32_t>(i));
      scene.instances.push_back(full.instances[i]);
    }
  }
  auto failed = [&](const std::string& why) {
    logError("radiosity: " + why + "; the frame keeps the ambient term");
    std::lock_guard lock(shared.mutex);
    shared.stats.converged = true;
    shared.done = true;
  };
  auto device = rt::EmbreeDevice::create();
  if (!device) return failed(device.error().message);
  auto embree = rt::EmbreeScene::build(**device, scene);
  if (!embree) return failed(embree.error().message);
  rt::RadiosityOptions solverOptions;
  solverOptions.targetPatches = options.patches;
  rt::RadiositySolver solver(scene, **embree, solverOptions);
  auto publish = [&](bool converged) {
    auto field = std::make_shared<RadiosityField>(anyDynamic ? solver.field().forInstances(solved, full.instances.size())
                                                             : solver.field());
    field->version = nextVersion.fetch_add(1);
    std::lock_guard lock(shared.mutex);
    shared.published = std::move(field);
    shared.stats.active = true;
    shared.stats.converged = converged;
    shared.stats.patches = static_cast<int>(solver.patchCount());
    shared.stats.shots = solver.shots();
    shared.stats.residual = solver.residual();
    shared.stats.solveMs = timer.ms();
    shared.publishedOnce = true;
  };
  auto finished = [&] {
    const long long left = options.shots > 0 ? options.shots - static_cast<long long>(solver.shots()) : LLONG_MAX;
    return left <= 0 || solver.residual() <= options.error;
  };
  if (!background) {
    while (!finished() && solver.shoot(1, options.error) == 1) {
    }
    publish(true);
    shared.done = true;
    return;
  }
  // In the background the frames see the solution about 10 times a second, and once more when it converges;
  // then the solve waits for new lights (or the end).
  Timer sincePublished;
  bool current = false;  // the published solution is this state's last
  while (!shared.stop) {
    std::optional<std::vector<Light>> lights;
    {
      std::unique_lock lock(shared.mutex);
      if (current && !shared.pendingLights)
        shared.wake.wait(lock, [&] { return shared.stop.load() || shared.pendingLights.has_value(); });
      if (shared.stop) break;
      lights.swap(shared.pendingLights);
    }
    if (lights) {
      scene.lights = std::move(*lights);
      solver.relight(scene);
      current = false;
    }
    const bool done = finished() || solver.shoot(1, options.error) == 0;
    if (done || sincePublished.ms() >= 100.0) {
      publish(done);
      sincePublished.reset();
      current = done;
    }
  }
  shared.done = true;
}

bool RadiosityJob::sync(const Scene& scene, const FrameSettings& settings) {
  const Options options{settings.radiosityPatches, settings.radiosityError, settings.radiosityShots};
  const bool sameRequest = shared_ && options == options_ && background_ == settings.radiosityBackground;
  // A background solve that has shown nothing yet goes on despite a move: restarting it at every frame of
  // a moving static instance would never show a solution.
  const bool letItPublish = sameRequest && background_ && !shared_->publishedOnce && !shared_->done;
  if ((stale_ || !sameRequest) && !letItPublish) {
    stop();
    shared_ = std::make_shared<Shared>();
    options_ = options;
    background_ = settings.radiosityBackground;
    stale_ = false;
    lightsStale_ = false;
    if (background_) {
      shared_->scene = scene;
      worker_ = std::thread([shared = shared_, options] {
        // The frame comes first: the solve runs at a lower priority, on half the cores (one of two), so a
        // game's frames keep their pace while it works.
#ifdef __linux__
        (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
#endif
        const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        tbb::task_arena arena(std::max(1, cores / 2));
        arena.execute([&] { solve(*shared, shared->scene, options, true); });
      });
    } else {
      solve(*shared_, scene, options, false);
    }
  } else if (lightsStale_ && !stale_) {
    if (background_) {
      std::lock_guard lock(shared_->mutex);
      shared_->pendingLights = scene.lights;
      shared_->stats.converged = false;
      shared_->wake.notify_all();
      lightsStale_ = false;
    } else {
      stale_ = true;  // before the frame: solve again now
      lightsStale_ = false;
      return sync(scene, settings);
    }
  }
  std::shared_ptr<const RadiosityField> latest;
  {
    std::lock_guard lock(shared_->mutex);
    latest = shared_->published;
  }
  if (!latest || latest == shown_) return false;
  shown_ = std::move(latest);
  return true;
}

RadiosityStats RadiosityJob::stats() const {
  if (!shared_) return {};
  std::lock_guard lock(shared_->mutex);
  RadiosityStats s = shared_->stats;
  s.active = shown_ != nullptr;
  return s;
}

}  // namespace tandem
