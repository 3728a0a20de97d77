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
  std::condition_variable wake;  // new lights or stop, for a solve that waits
  std::shared_ptr<const RadiosityField> published;
  RadiosityStats stats;  // the published solution's
  std::optional<std::vector<Light>> pendingLights;  // the background solve takes them at its next step
  std::atomic<bool> stop{false};
  std::atomic<bool> done{false};
  std::atomic<bool> publishedOnce{false};
};

RadiosityJob::~RadiosityJob() {
  stop();
  for (Retired& r : retired_) r.thread.join();
}

void RadiosityJob::apply(const SceneChanges& changes) {
  if (changes.replaced || changes.staticMoved) stale_ = true;
  if (changes.replaced) {
    replaced_ = true;
    shown_.reset();
    shownStats_ = {};
  }
  if (changes.lights) lightsStale_ = true;
}

void RadiosityJob::stop() {
  if (shared_) {
    std::lock_guard lock(shared_->mutex);
    shared_->stop = true;
    shared_->wake.notify_all();
  }
  if (worker_.joinable()) retired_.push_back({std::move(worker_), shared_});
  shared_.reset();
  // Join the solves that have finished; the others are left to finish their step.
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
  shownStats_ = {};
  stale_ = true;
  lightsStale_ = false;
}

void RadiosityJob::solve(Shared& shared, Scene scene, Options options, bool background) {
  const Timer timer;
  // Dynamic instances stay out of the solution, as patches and as blockers: a game moves them every frame,
  // and a solve restarted at every move would never show anything. The ambient term lights them.
  const std::size_t instanceCount = scene.instances.size();
  std::vector<std::uint32_t> solved;
  for (std::size_t i = 0; i < instanceCount; ++i)
    if (!scene.instances[i].dynamic) solved.push_back(static_cast<std::uint32_t>(i));
  const bool anyDynamic = solved.size() != instanceCount;
  if (anyDynamic)
    std::erase_if(scene.instances, [](const Instance& instance) { return instance.dynamic; });
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
  solverOptions.cancel = &shared.stop;
  auto solver = std::make_unique<rt::RadiositySolver>(scene, **embree, solverOptions);
  std::size_t earlierShots = 0;  // the coarse solve's, once refined
  std::size_t capFrom = 0;       // the shots the cap counts from: the last relight's
  bool refined = !options.refine;
  auto publish = [&](bool converged) {
    if (shared.stop) return;  // an abandoned solver's state is not a solution
    auto field = std::make_shared<RadiosityField>(anyDynamic ? solver->field().forInstances(solved, instanceCount)
                                                             : solver->field());
    field->version = nextVersion.fetch_add(1);
    std::lock_guard lock(shared.mutex);
    shared.published = std::move(field);
    shared.stats.active = true;
    shared.stats.converged = converged;
    shared.stats.patches = static_cast<int>(solver->patchCount());
    shared.stats.shots = earlierShots + solver->shots();
    shared.stats.residual = solver->residual();
    shared.stats.solveMs = timer.ms();
    shared.publishedOnce = true;
  };
  auto finished = [&] {
    const std::size_t shots = earlierShots + solver->shots();
    const long long left = options.shots > 0 ? options.shots - static_cast<long long>(shots - capFrom) : LLONG_MAX;
    return left <= 0 || solver->residual() <= options.error;
  };
  // Adaptive refinement, once the first solve is done: the triangles where the solution steps steeply get
  // finer grids and the solve starts again on them (docs/radiosity.md). False when nothing needed it.
  auto refine = [&] {
    refined = true;
    std::vector<int> segments = solver->refinedSegments(rt::RadiositySolver::kRefineStep,
                                                        rt::RadiositySolver::kRefineGrowth * (solver->patchCount() / 2));
    if (segments == solver->segments()) return false;
    earlierShots += solver->shots();
    capFrom = earlierShots;
    solverOptions.segments = std::move(segments);
    solver = std::make_unique<rt::RadiositySolver>(scene, **embree, solverOptions);
    return true;
  };
  if (!background) {
    do {
      while (!finished() && solver->shoot(1, options.error) == 1) {
      }
    } while (!refined && refine());
    publish(true);
    shared.done = true;
    return;
  }
  // In the background the frames see the solution about 10 times a second, and once more when it converges;
  // then the solve waits for new lights (or the end). New lights are taken at most ~10 times a second too: a
  // game that moves its lights every frame would otherwise spend the solve gathering their direct light.
  Timer sincePublished, sinceRelit;
  bool current = false;   // the published solution is this state's last
  bool refining = false;  // the refined grid's solve runs: the coarse solution stays until it is done
  while (!shared.stop) {
    std::optional<std::vector<Light>> lights;
    {
      std::unique_lock lock(shared.mutex);
      if (current && !shared.pendingLights)
        shared.wake.wait(lock, [&] { return shared.stop.load() || shared.pendingLights.has_value(); });
      if (shared.stop) break;
      if (current || sinceRelit.ms() >= 100.0) lights.swap(shared.pendingLights);
    }
    if (lights) {
      scene.lights = std::move(*lights);
      solver->relight(scene);
      capFrom = earlierShots + solver->shots();
      sinceRelit.reset();
      current = false;
    }
    const bool done = finished() || solver->shoot(1, options.error) == 0;
    if (done && !refined) {
      // The coarse solution stays on screen while the refined one is solved (its first shots would show less).
      publish(false);
      sincePublished.reset();
      if (refine()) {
        refining = true;
        continue;
      }
    }
    if (done) refining = false;
    if (done || (!refining && sincePublished.ms() >= 100.0)) {
      publish(done);
      sincePublished.reset();
      current = done;
    }
  }
  shared.done = true;
}

bool RadiosityJob::sync(const Scene& scene, const FrameSettings& settings, int threads) {
  const Options options{settings.radiosityPatches, settings.radiosityError, settings.radiosityShots,
                        settings.radiosityRefine};
  const bool sameRequest = shared_ && options == options_ && background_ == settings.radiosityBackground;
  // A background solve that has shown nothing yet goes on despite a move: restarting it at every frame of
  // a moving static instance would never show a solution. Not for a new scene: its solution is another's.
  const bool letItPublish = sameRequest && background_ && !replaced_ && !shared_->publishedOnce && !shared_->done;
  if ((stale_ || !sameRequest) && !letItPublish) {
    stop();
    shared_ = std::make_shared<Shared>();
    options_ = options;
    background_ = settings.radiosityBackground;
    stale_ = replaced_ = lightsStale_ = false;
    if (background_) {
      worker_ = std::thread([shared = shared_, options, copy = scene]() mutable {
        // The frame comes first: the solve runs at a lower priority, on half the cores (one of two), so a
        // game's frames keep their pace while it works.
#ifdef __linux__
        (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
#endif
        const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        tbb::task_arena arena(std::max(1, cores / 2), 1, tbb::task_arena::priority::low);
        arena.execute([&] { solve(*shared, std::move(copy), options, true); });
      });
    } else {
      tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
      arena.execute([&] { solve(*shared_, scene, options, false); });
    }
  } else if (lightsStale_ && !stale_) {
    if (!background_) {
      stale_ = true;  // before the frame: solve again now
      return sync(scene, settings, threads);
    }
    std::lock_guard lock(shared_->mutex);
    shared_->pendingLights = scene.lights;
    shared_->wake.notify_all();
    lightsStale_ = false;
    shownStats_.converged = false;
  }
  std::lock_guard lock(shared_->mutex);
  if (!shared_->published || shared_->published == shown_) return false;
  shown_ = shared_->published;
  shownStats_ = shared_->stats;
  return true;
}

}  // namespace tandem
