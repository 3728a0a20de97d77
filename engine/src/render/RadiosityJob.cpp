#include "render/RadiosityJob.h"

#include <algorithm>
#include <climits>
#include <string>

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
  std::shared_ptr<const RadiosityField> published;
  RadiosityStats stats;
  std::atomic<bool> stop{false};
  std::atomic<bool> done{false};
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

void RadiosityJob::stop() {
  if (shared_) shared_->stop = true;
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
}

void RadiosityJob::solve(Shared& shared, const Scene& scene, Options options, bool background) {
  const Timer timer;
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
    auto field = std::make_shared<RadiosityField>(solver.field());
    field->version = nextVersion.fetch_add(1);
    std::lock_guard lock(shared.mutex);
    shared.published = std::move(field);
    shared.stats.active = true;
    shared.stats.converged = converged;
    shared.stats.patches = static_cast<int>(solver.patchCount());
    shared.stats.shots = solver.shots();
    shared.stats.residual = solver.residual();
    shared.stats.solveMs = timer.ms();
  };
  // In the background the frames see the solution about 10 times a second (a solve that is restarted
  // sooner, by something that keeps moving, leaves the last one on screen); otherwise once, converged.
  Timer sincePublished;
  bool publishedOnce = false;
  while (!shared.stop) {
    const long long left = options.shots > 0 ? options.shots - static_cast<long long>(solver.shots()) : LLONG_MAX;
    if (left <= 0 || solver.residual() <= options.error) break;
    if (solver.shoot(1, options.error) == 0) break;
    if (background && sincePublished.ms() >= 100.0) {
      publish(false);
      publishedOnce = true;
      sincePublished.reset();
    }
  }
  if (!shared.stop || !publishedOnce) publish(!shared.stop);
  shared.done = true;
}

bool RadiosityJob::sync(const Scene& scene, const FrameSettings& settings) {
  const Options options{settings.radiosityPatches, settings.radiosityError, settings.radiosityShots};
  if (stale_ || !shared_ || !(options == options_) || background_ != settings.radiosityBackground) {
    stop();
    shared_ = std::make_shared<Shared>();
    options_ = options;
    background_ = settings.radiosityBackground;
    stale_ = false;
    if (background_) {
      shared_->scene = scene;
      worker_ = std::thread([shared = shared_, options] { solve(*shared, shared->scene, options, true); });
    } else {
      solve(*shared_, scene, options, false);
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
