// tandem-game: "Marble Mirrors", the engine's sample game. Roll a glass marble through a hall of mirrors
// and collect every gem before the clock runs out (docs/game.md).
//
//   tandem-game [--size WxH] [--preset NAME] [--shadows M] [--reflections M] [--refraction M] ...
//   tandem-game --headless --frames N --capture OUT.png --script INPUT [--size WxH] [--preset NAME] ...
//
// Windowed and headless runs share one loop (Session::step / Session::render): only where input comes
// from (GLFW or a script), the clock (wall or fixed) and the HUD differ.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>

#include <CLI/CLI.hpp>

#include "Game.h"
#include "Hud.h"
#include "Input.h"
#include "Level.h"
#include "SceneBuilder.h"
#include "Script.h"
#include "Toggles.h"
#include "tandem/Context.h"
#include "tandem/Image.h"
#include "tandem/ImageMetrics.h"
#include "tandem/Renderer.h"

namespace marble {
namespace {

struct Options {
  bool headless = false;
  int frames = 0;  // 0 = until quit (window); headless needs >= 1
  std::string capture;
  std::string script;
  std::string size;
  std::string preset = "hybrid-fast";
  std::string shading, shadows, reflections, refraction;
  int depth = -1;
  int scale = 0;
  int threads = 0;
  int probesPerFrame = 2;
  std::string reuse = "on";
  std::string pipeline = "auto";
  float targetFps = 0.0f;
  std::vector<std::string> aa{"off"};
  int accumulate = 16;
  int lightSamples = tandem::FrameSettings{}.lightSamples;
  int lightSamplesPastFilter = tandem::FrameSettings{}.lightSamplesPastFilter;
  std::string radiosity = "off";
  std::string denoise = "off";
  std::string frameLog;
  int errorEvery = 0;
  std::string errorTruth = "requested";
  bool checkReuse = false;
  double dt = 1.0 / 60.0;
  bool noVsync = false;
  bool fullscreen = false;
  std::string shotDir = ".";
};

/// The last frame's radiosity solution for the closing `game:` line (empty when none was shown).
std::string radiosityLine(const tandem::RadiosityStats& r) {
  if (!r.active) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf, " radiosity-shots=%llu radiosity-unshot=%.4f radiosity-converged=%d",
                static_cast<unsigned long long>(r.shots), static_cast<double>(r.residual), r.converged ? 1 : 0);
  return buf;
}

int fail(const std::string& message) {
  std::cerr << "tandem-game: " << message << "\n";
  return 1;
}

bool parseSize(const std::string& s, int& w, int& h) {
  char x = 0, extra = 0;
  return std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) == 3 && (x == 'x' || x == 'X') && w >= 1 &&
         h >= 1 && w <= 16384 && h <= 16384;
}

std::string fpsText(float fps) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(fps));
  return buf;
}

// ---- GLFW key codes to the names scripts use (Input.h). ----
std::string keyName(int key) {
  if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return std::string(1, static_cast<char>('A' + (key - GLFW_KEY_A)));
  if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return std::string(1, static_cast<char>('0' + (key - GLFW_KEY_0)));
  if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) {
    std::string f = "F";
    f += std::to_string(key - GLFW_KEY_F1 + 1);
    return f;
  }
  switch (key) {
    case GLFW_KEY_SPACE: return "SPACE";
    case GLFW_KEY_ENTER: return "ENTER";
    case GLFW_KEY_ESCAPE: return "ESCAPE";
    case GLFW_KEY_TAB: return "TAB";
    case GLFW_KEY_BACKSPACE: return "BACKSPACE";
    case GLFW_KEY_LEFT: return "LEFT";
    case GLFW_KEY_RIGHT: return "RIGHT";
    case GLFW_KEY_UP: return "UP";
    case GLFW_KEY_DOWN: return "DOWN";
    case GLFW_KEY_LEFT_SHIFT: return "LSHIFT";
    case GLFW_KEY_RIGHT_SHIFT: return "RSHIFT";
    case GLFW_KEY_LEFT_CONTROL: return "LCTRL";
    case GLFW_KEY_RIGHT_CONTROL: return "RCTRL";
    case GLFW_KEY_MINUS: return "MINUS";
    case GLFW_KEY_EQUAL: return "EQUAL";
    case GLFW_KEY_LEFT_BRACKET: return "LBRACKET";
    case GLFW_KEY_RIGHT_BRACKET: return "RBRACKET";
    case GLFW_KEY_COMMA: return "COMMA";
    case GLFW_KEY_PERIOD: return "PERIOD";
    case GLFW_KEY_KP_ADD: return "EQUAL";
    case GLFW_KEY_KP_SUBTRACT: return "MINUS";
    default: return {};
  }
}

/// Everything one game session holds; the window and headless drivers call step() and render().
class Session {
 public:
  Session(tandem::GlContext& ctx, std::unique_ptr<tandem::Renderer> renderer, ViewState view, double dt,
          std::vector<ScriptEvent> script, std::string shotDir)
      : ctx_(ctx),
        renderer_(std::move(renderer)),
        game_(makeHallOfMirrors()),
        view_(std::move(view)),
        dt_(dt),
        script_(std::move(script)),
        shotDir_(std::move(shotDir)) {
    rig_.yaw = game_.level().startCameraYaw;
  }

  tandem::Result<void> init() {
    BuiltScene built = buildScene(game_);
    handles_ = built.handles;
    camera_ = built.scene.camera;
    return renderer_->setScene(std::move(built.scene));
  }

  /// A second renderer, for --error-every: the same scene drawn with the requested settings and no budget,
  /// to measure what the budget's choice costs the image.
  tandem::Result<void> initTruth() {
    auto r = tandem::Renderer::create(ctx_);
    if (!r) return r.error();
    truth_ = std::move(*r);
    return truth_->setScene(renderer_->scene());
  }

  /// A second renderer, for --check-reuse: every frame drawn again with reuse off.
  tandem::Result<void> initTwin() {
    auto r = tandem::Renderer::create(ctx_);
    if (!r) return r.error();
    twin_ = std::move(*r);
    return twin_->setScene(renderer_->scene());
  }

  /// The last frame drawn again by the twin, every ray traced, and compared to the bit: the pixels whose
  /// linear or display values differ, and the twin's ray counts.
  struct ReuseCheck {
    std::size_t differing = 0;
    tandem::RayCounts rays;
  };
  tandem::Result<ReuseCheck> checkReuse(int w, int h) {
    syncScene(*twin_, game_, handles_);
    tandem::FrameSettings s = view_.settings;
    s.width = w;
    s.height = h;
    s.reuseRays = false;
    const tandem::FrameStats st = twin_->render(camera_, s);
    if (!st.error.empty()) return tandem::Error{st.error};
    ReuseCheck c;
    c.rays = st.rays;
    const tandem::ImageF a = renderer_->readLinear(), b = twin_->readLinear();
    const tandem::Image da = renderer_->readImage(), db = twin_->readImage();
    if (a.rgb.size() != b.rgb.size() || da.rgba.size() != db.rgba.size())
      return tandem::Error{"the twin's frame has another size"};
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
      const bool linear = std::memcmp(&a.rgb[i], &b.rgb[i], sizeof(glm::vec3)) != 0;
      const bool display = std::memcmp(&da.rgba[4 * i], &db.rgba[4 * i], 4) != 0;
      c.differing += linear || display ? 1 : 0;
    }
    return c;
  }

  /// FLIP of the last frame against the same instant drawn as requested, without the budget.
  /// `converged`: against the requested settings' converged image instead (no filter, 16 light and lobe samples,
  /// 32 jittered frames at this instant): what the frame's sampling and reconstruction cost it in all.
  tandem::Result<double> errorAgainstRequested(int w, int h, bool converged) {
    syncScene(*truth_, game_, handles_);
    tandem::FrameSettings s = view_.settings;
    s.width = w;
    s.height = h;
    // The request as the budget resolved it: a budget turns accumulation off (FrameSettings::resolved).
    if (s.targetMs > 0.0f) s.accumulate = 0;
    s.targetMs = 0.0f;
    s.reuseRays = false;
    s.probesPerFrame = 0;  // drawn only every Nth frame: its probes must not lag behind the game
    int frames = 1;
    if (converged) {
      s.denoise = false;
      s.aa = tandem::AntiAlias::Off;
      s.lightSamples = s.glossSamples = 16;
      s.accumulate = frames = 32;
    }
    for (int i = 0; i < frames; ++i) {
      const tandem::FrameStats st = truth_->render(camera_, s);
      if (!st.error.empty()) return tandem::Error{st.error};
    }
    auto f = tandem::flip(renderer_->readImage(), truth_->readImage());
    if (!f) return f.error();
    return f->mean;
  }

  /// A key's down edge, from GLFW or the script: toggles, then the window-level actions.
  void keyDown(const std::string& key) {
    switch (view_.onKey(key)) {
      case WindowAction::Restart: game_.reset(); break;
      case WindowAction::Pause: paused_ = !paused_; break;
      case WindowAction::Screenshot: wantShot_ = true; break;
      case WindowAction::Quit: quit_ = true; break;
      case WindowAction::Vsync: ctx_.setVsync(view_.vsync); break;
      case WindowAction::Fullscreen: wantFullscreen_ = true; break;
      case WindowAction::None: break;
    }
  }

  /// One fixed simulation step: scripted input for this instant, camera, then the game.
  void step() {
    script_.advance(clock_, input_, [this](const std::string& k) { keyDown(k); });
    const MoveIntent intent = moveIntent(input_);
    rig_.update(static_cast<float>(dt_), input_.mouseDelta, intent.orbit, input_.scroll);
    input_.consumeDeltas();
    // Paused, the world stands still (the camera may still orbit): with nothing in view changing, the
    // renderer's accumulation converges to an anti-aliased frame (FrameSettings::accumulate).
    if (!paused_) game_.step(static_cast<float>(dt_), intent, rig_.yaw);
    clock_ += dt_;
  }

  /// Moves the animated instances and lights, then renders at `w`×`h`.
  tandem::FrameStats render(int w, int h) {
    syncScene(*renderer_, game_, handles_);
    const glm::vec3 target = game_.marblePos() + glm::vec3(0.0f, 0.3f, 0.0f);
    camera_.targetW = target;
    camera_.posW = rig_.eye(target, game_.level().halfSize);
    tandem::FrameSettings s = view_.settings;
    s.width = w;
    s.height = h;
    view_.settings.width = w;  // so the HUD shows the size actually rendered
    view_.settings.height = h;
    return renderer_->render(camera_, s);
  }

  /// Writes the last frame; returns the path or an error.
  tandem::Result<std::string> saveFrame(const std::string& path) {
    tandem::Image img = renderer_->readImage();
    if (auto r = tandem::writePng(path, img); !r) return r.error();
    return path;
  }
  std::string nextShotPath(const char* suffix) {
    char name[64];
    std::snprintf(name, sizeof name, "marble-%03d%s.png", shotIndex_, suffix);
    return (std::filesystem::path(shotDir_) / name).string();
  }

  std::string settingsLine() const {
    const tandem::FrameSettings& s = view_.settings;
    std::ostringstream o;
    o << "preset=" << view_.preset << " shadows=" << tandem::shadowModeName(s)
      << " reflections=" << tandem::toString(s.reflections) << " refraction=" << tandem::toString(s.refraction)
      << " shading=" << view_.shadingName() << " depth=" << s.maxDepth << " scale=" << s.rayScale
      << " budget=" << (view_.targetFps > 0.0f ? fpsText(view_.targetFps) : std::string("off"))
      << " aa=" << tandem::toString(s.aa) << (s.aa != tandem::AntiAlias::Off ? std::to_string(s.aaSamples) : std::string())
      << " accumulate=" << s.accumulate << " light-samples=" << s.lightSamples
      << (s.denoise ? " past-filter=" + std::to_string(s.unfilteredLightSamples()) : std::string())
      << " radiosity=" << (s.radiosity ? "on" : "off") << " denoise=" << (s.denoise ? "on" : "off")
      << " pipeline=" << (s.pipelined ? "on" : "off");
    return o.str();
  }

  tandem::GlContext& ctx_;
  std::unique_ptr<tandem::Renderer> renderer_;
  std::unique_ptr<tandem::Renderer> truth_;  // --error-every only
  std::unique_ptr<tandem::Renderer> twin_;   // --check-reuse only
  Game game_;
  ViewState view_;
  CameraRig rig_;
  InputState input_;
  double dt_;
  bool paused_ = false;  // TAB: the game's world does not step
  double clock_ = 0.0;  // session time: keeps running across restarts, so script times stay absolute
  ScriptPlayer script_;
  std::string shotDir_;
  SceneHandles handles_;
  tandem::Camera camera_;
  int shotIndex_ = 0;
  bool wantShot_ = false;
  bool wantFullscreen_ = false;
  bool quit_ = false;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void printTimes(const std::vector<tandem::FrameStats>& frames, const std::vector<double>& loopMs, int w, int h) {
  if (frames.empty()) return;
  std::vector<double> total, rays, raster, composite;
  for (const auto& f : frames) {
    total.push_back(f.totalMs);
    rays.push_back(f.raysMs);
    raster.push_back(f.rasterMs);
    composite.push_back(f.compositeMs);
  }
  const tandem::FrameStats& last = frames.back();
  // The hitches a player feels: the slowest frame after the first (which sets everything up), and the
  // shader programs compiled after the first frame.
  std::size_t worst = frames.size() > 1 ? 1 : 0;
  int compiles = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].totalMs > frames[worst].totalMs) worst = i;
    compiles += frames[i].shaderCompiles;
  }
  // Over the run: the shadow rays traced and (hybrid shadows) those the light-space maps and the tile
  // shafts answered.
  unsigned long long shadowRays = 0, shadowByMap = 0, shadowKept = 0, shadowByShaft = 0;
  for (const auto& f : frames)
    shadowRays += f.rays.shadow, shadowByMap += f.rays.shadowByMap, shadowKept += f.rays.shadowKept,
        shadowByShaft += f.rays.shadowByShaft;
  std::printf("times: size=%dx%d frames=%zu median_ms total=%.2f raster=%.2f rays=%.2f composite=%.2f loop=%.2f "
              "rays_per_frame=%llu worst_after_first_ms=%.2f worst_frame=%zu compiles_after_first=%d "
              "shadow_rays=%llu shadow_by_map=%llu shadow_kept=%llu shadow_by_shaft=%llu\n",
              w, h, frames.size(), median(total), median(raster), median(rays), median(composite), median(loopMs),
              static_cast<unsigned long long>(last.rays.total()), frames[worst].totalMs, worst, compiles, shadowRays,
              shadowByMap, shadowKept, shadowByShaft);
  // Every stage's median (they add up to the frame but for `untimed`), and the GPU's time of the GL ones.
  std::printf("stages: median_ms");
  for (const tandem::FrameStage& stage : tandem::kFrameStages) {
    std::vector<double> v;
    for (const auto& f : frames) v.push_back(f.*stage.cpu);
    std::printf(" %s=%.2f", stage.name, median(v));
  }
  std::vector<double> untimed, gpu;
  for (const auto& f : frames) {
    untimed.push_back(f.untimedMs());
    if (f.gpu.valid) gpu.push_back(f.gpu.totalMs());
  }
  std::printf(" untimed=%.2f gpu_total=%.2f\n", median(untimed), median(gpu));
  // The budget over the run: how often a frame kept within 10 % of its target (pipelined, the interval
  // between frames: a frame's latency spans two), and how often it moved.
  std::size_t budgeted = 0, within = 0, changes = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const tandem::BudgetStats& b = frames[i].budget;
    if (!b.active) continue;
    ++budgeted;
    const double shownMs = frames[i].pipelined && frames[i].intervalMs > 0 ? frames[i].intervalMs : frames[i].totalMs;
    within += shownMs <= 1.1 * b.targetMs ? 1 : 0;
    changes += i > 0 && frames[i - 1].budget.active && frames[i - 1].budget.step != b.step ? 1 : 0;
  }
  if (budgeted > 0)
    std::printf("budget: target_ms=%.2f frames=%zu within_10pct=%.3f changes=%zu last_step=%d steps=%d "
                "reachable=%d\n",
                last.budget.targetMs, budgeted, static_cast<double>(within) / static_cast<double>(budgeted), changes,
                last.budget.step, last.budget.steps, last.budget.reachable ? 1 : 0);
}

// ---- Headless: fixed dt, scripted input, no wall clock in the simulation. ----
int runHeadless(Session& s, const Options& o, int w, int h) {
  std::vector<tandem::FrameStats> stats;
  std::vector<double> loopMs;
  std::ofstream log;
  if (!o.frameLog.empty()) {
    log.open(o.frameLog);
    if (!log) return fail("--frame-log: cannot write '" + o.frameLog + "'");
    // Every stage of the frame (they add up to total_ms but for untimed_ms), the GPU's time of the GL ones,
    // the game's own work around the frame (simulation, input) and the whole loop.
    log << "frame,total_ms";
    for (const tandem::FrameStage& stage : tandem::kFrameStages) log << "," << stage.name << "_ms";
    log << ",untimed_ms";
    for (const tandem::FrameStage& stage : tandem::kFrameStages)
      if (stage.gpu != nullptr) log << ",gpu_" << stage.name << "_ms";
    log << ",gpu_frames_ago,game_ms,loop_ms,rays,rays_reused,shader_compiles,target_ms,step,steps,choice,predicted_ms,"
           "expected_flip,flip,denoise_ms\n";
  }
  if (o.errorEvery > 0)
    if (auto r = s.initTruth(); !r) return fail(r.error().message);
  if (o.checkReuse)
    if (auto r = s.initTwin(); !r) return fail(r.error().message);
  // --check-reuse over the run: frames compared, those identical to the bit, the rays traced with reuse
  // and without it, and the shadow answers kept.
  std::size_t checked = 0, identical = 0, differing = 0, budgetFrames = 0;
  unsigned long long raysWith = 0, raysWithout = 0, shadowWith = 0, shadowWithout = 0, kept = 0, still = 0;
  // One frame-log line: the frame shown (in throughput mode the one before the frame drawn), its stages.
  auto logFrame = [&](int f, const tandem::FrameStats& st, double gameMs, double loop, const std::string& flip) {
    log << f << "," << st.totalMs;
    for (const tandem::FrameStage& stage : tandem::kFrameStages) log << "," << st.*stage.cpu;
    log << "," << st.untimedMs();
    for (const tandem::FrameStage& stage : tandem::kFrameStages)
      if (stage.gpu != nullptr) {
        log << ",";
        if (st.gpu.valid) log << st.gpu.*stage.gpu;
      }
    log << "," << (st.gpu.valid ? std::to_string(st.gpu.framesAgo) : std::string()) << "," << gameMs << "," << loop
        << "," << st.rays.total() << "," << (st.raysReused ? 1 : 0) << "," << st.shaderCompiles << ","
        << st.budget.targetMs << "," << st.budget.step << "," << st.budget.steps << ",\""
        << tandem::describeBudget(st.budget) << "\"," << st.budget.predictedMs << "," << st.budget.expectedError << ","
        << flip << "," << st.denoiseMs << "\n";
  };
  for (int f = 0; f < o.frames && !s.quit_; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    s.step();
    const double gameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const tandem::FrameStats drawn = s.render(w, h);
    if (drawn.pipelineFilling) {
      // Throughput mode's first call: its frame is shown by the next one (nothing to log or compare yet).
      loopMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      continue;
    }
    stats.push_back(drawn);
    double errorMs = 0.0;  // the second renderer's time, left out of the loop's
    if (o.checkReuse) {
      const tandem::FrameStats& st = stats.back();
      const auto e0 = std::chrono::steady_clock::now();
      if (st.budget.active) {
        ++budgetFrames;  // the twin's budget would choose on its own clock: nothing to compare
      } else {
        auto c = s.checkReuse(w, h);
        if (!c) return fail("--check-reuse: " + c.error().message);
        ++checked;
        identical += c->differing == 0 ? 1 : 0;
        differing += c->differing;
        raysWith += st.rays.total();
        raysWithout += c->rays.total();
        shadowWith += st.rays.shadow;
        shadowWithout += c->rays.shadow;
        kept += st.rays.shadowKept;
        still += st.raysReused ? 1 : 0;
      }
      errorMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - e0).count();
    }
    if (log.is_open()) {
      // After the frame's own timing: the error frame is drawn by the second renderer, outside it.
      std::string flip;
      if (o.errorEvery > 0 && f % o.errorEvery == 0) {
        const auto e0 = std::chrono::steady_clock::now();
        auto e = s.errorAgainstRequested(w, h, o.errorTruth == "converged");
        errorMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - e0).count();
        if (!e) return fail("--error-every: " + e.error().message);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6f", *e);
        flip = buf;
      }
      const double loop =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - errorMs;
      logFrame(f, stats.back(), gameMs, loop, flip);
    }
    if (s.wantShot_) {  // a scripted P: same files as in a window, minus the HUD copy
      s.wantShot_ = false;
      auto r = s.saveFrame(s.nextShotPath(""));
      ++s.shotIndex_;
      if (!r) return fail(r.error().message);
    }
    loopMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() -
                     errorMs);
  }
  // Throughput mode: the frame still in flight, shown (and logged) before the capture.
  if (const auto t0 = std::chrono::steady_clock::now(); std::optional<tandem::FrameStats> done = s.renderer_->finish()) {
    if (!done->error.empty()) return fail(done->error);
    stats.push_back(*done);
    const double loop = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (log.is_open()) logFrame(o.frames, *done, 0.0, loop, "");
  }
  if (log.is_open() && !log.flush()) return fail("--frame-log: cannot write '" + o.frameLog + "'");
  if (!o.capture.empty())
    if (auto r = s.saveFrame(o.capture); !r) return fail(r.error().message);
  std::printf("game: %s frames=%zu %s accumulated=%d%s\n", s.game_.stateLine().c_str(), stats.size(),
              s.settingsLine().c_str(), stats.empty() ? 0 : stats.back().accumulated,
              stats.empty() ? "" : radiosityLine(stats.back().radiosity).c_str());
  printTimes(stats, loopMs, w, h);
  if (o.checkReuse) {
    auto saved = [](unsigned long long with, unsigned long long without) {
      return without > 0 ? 1.0 - static_cast<double>(with) / static_cast<double>(without) : 0.0;
    };
    std::printf("reuse: frames=%zu identical=%zu differing_pixels=%zu still_frames=%llu rays=%llu "
                "rays_without_reuse=%llu saved=%.4f shadow_rays=%llu shadow_rays_without_reuse=%llu "
                "shadow_saved=%.4f shadow_kept=%llu budget_frames_unchecked=%zu\n",
                checked, identical, differing, still, raysWith, raysWithout, saved(raysWith, raysWithout), shadowWith,
                shadowWithout, saved(shadowWith, shadowWithout), kept, budgetFrames);
    if (identical != checked) return fail("--check-reuse: " + std::to_string(checked - identical) +
                                          " frames differ from the same frames traced whole");
  }
  return 0;
}

// ---- Window: GLFW input, wall clock with a fixed-step accumulator, ImGui HUD. ----
struct WindowInput {
  Session* session = nullptr;
  Hud* hud = nullptr;
  glm::dvec2 lastCursor{0.0};
  bool haveCursor = false;
};

WindowInput* inputOf(GLFWwindow* w) { return static_cast<WindowInput*>(glfwGetWindowUserPointer(w)); }

void onKey(GLFWwindow* w, int key, int, int action, int) {
  WindowInput* in = inputOf(w);
  if (!in || !in->session) return;
  const std::string name = keyName(key);
  if (name.empty()) return;
  if (action == GLFW_PRESS) {
    if (in->hud && in->hud->wantsKeyboard()) return;
    in->session->input_.held.insert(name);
    in->session->keyDown(name);
  } else if (action == GLFW_RELEASE) {
    in->session->input_.held.erase(name);  // always, so a key never sticks when focus moves to the HUD
  }
}

void onCursor(GLFWwindow* w, double x, double y) {
  WindowInput* in = inputOf(w);
  if (!in || !in->session) return;
  const glm::dvec2 p(x, y);
  const bool dragging = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS ||
                        glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  if (in->haveCursor && dragging && !(in->hud && in->hud->wantsMouse()))
    in->session->input_.mouseDelta += glm::vec2(p - in->lastCursor);
  in->lastCursor = p;
  in->haveCursor = true;
}

void onScroll(GLFWwindow* w, double, double dy) {
  WindowInput* in = inputOf(w);
  if (!in || !in->session || (in->hud && in->hud->wantsMouse())) return;
  in->session->input_.scroll += static_cast<float>(dy);
}

/// The default framebuffer as an image (the frame with the HUD on it), read after the HUD is drawn.
tandem::Result<void> saveWindow(const std::string& path, int w, int h) {
  auto bindFramebuffer = reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(glfwGetProcAddress("glBindFramebuffer"));
  auto readBuffer = reinterpret_cast<PFNGLREADBUFFERPROC>(glfwGetProcAddress("glReadBuffer"));
  auto pixelStore = reinterpret_cast<PFNGLPIXELSTOREIPROC>(glfwGetProcAddress("glPixelStorei"));
  auto readPixels = reinterpret_cast<PFNGLREADPIXELSPROC>(glfwGetProcAddress("glReadPixels"));
  if (!bindFramebuffer || !readBuffer || !pixelStore || !readPixels)
    return tandem::Error{"screenshot: GL functions unavailable"};
  bindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  readBuffer(GL_BACK);
  pixelStore(GL_PACK_ALIGNMENT, 1);
  tandem::Image img;
  img.width = w;
  img.height = h;
  img.rgba.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  readPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.rgba.data());
  // GL rows run bottom-up; Image rows top-down.
  const std::size_t row = static_cast<std::size_t>(w) * 4;
  for (int y = 0; y < h / 2; ++y)
    std::swap_ranges(img.rgba.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)),
                     img.rgba.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y + 1)),
                     img.rgba.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(h - 1 - y)));
  for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
  return tandem::writePng(path, img);
}

void setFullscreen(GLFWwindow* window, bool on, glm::ivec4& windowed) {
  if (on) {
    glfwGetWindowPos(window, &windowed.x, &windowed.y);
    glfwGetWindowSize(window, &windowed.z, &windowed.w);
    GLFWmonitor* monitor = glfwGetPrimaryMonitor();
    const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
    if (!mode) return;
    glfwSetWindowMonitor(window, monitor, 0, 0, mode->width, mode->height, mode->refreshRate);
  } else {
    glfwSetWindowMonitor(window, nullptr, windowed.x, windowed.y, windowed.z, windowed.w, 0);
  }
}

int runWindow(Session& s, const Options& o) {
  GLFWwindow* window = s.ctx_.window();
  if (!window) return fail("the window context has no GLFW window");
  WindowInput in;
  in.session = &s;
  glfwSetWindowUserPointer(window, &in);
  // Ours first: ImGui's backend chains to callbacks installed before it.
  glfwSetKeyCallback(window, onKey);
  glfwSetCursorPosCallback(window, onCursor);
  glfwSetScrollCallback(window, onScroll);
  Hud hud(window);
  in.hud = &hud;
  s.ctx_.setVsync(s.view_.vsync);
  glm::ivec4 windowed(100, 100, 1280, 720);
  if (s.view_.fullscreen) setFullscreen(window, true, windowed);
  {
    // The help overlay covers the stats in a small window: there it starts hidden (F1 shows it).
    int fbW = 0, fbH = 0;
    s.ctx_.framebufferSize(fbW, fbH);
    if (fbW < 1100) s.view_.showHelp = false;
  }

  std::string message;
  std::string contextName = s.ctx_.describe();
  tandem::FrameStats stats;
  std::vector<tandem::FrameStats> allStats;
  std::vector<double> loopMs;
  double frameMs = 0.0;
  int frames = 0;
  int lastW = 0, lastH = 0;
  auto last = std::chrono::steady_clock::now();
  double accumulator = 0.0;
  while (!glfwWindowShouldClose(window) && !s.quit_) {
    glfwPollEvents();
    if (s.wantFullscreen_) {
      s.wantFullscreen_ = false;
      setFullscreen(window, s.view_.fullscreen, windowed);
    }
    int fbW = 0, fbH = 0;
    s.ctx_.framebufferSize(fbW, fbH);
    if (fbW <= 0 || fbH <= 0) {
      // Minimised: nothing to draw into. Sleep on events and pause the game clock.
      glfwWaitEventsTimeout(0.1);
      last = std::chrono::steady_clock::now();
      continue;
    }
    const auto now = std::chrono::steady_clock::now();
    // Clamp a long hitch (window drag, debugger) so the marble does not jump through a second of physics.
    accumulator += std::min(0.25, std::chrono::duration<double>(now - last).count());
    last = now;
    while (accumulator >= s.dt_) {
      s.step();
      accumulator -= s.dt_;
    }
    const int w = std::max(1, fbW * s.view_.renderScalePct / 100);
    const int h = std::max(1, fbH * s.view_.renderScalePct / 100);
    // Throughput mode's first call shows no frame: the HUD keeps the stats it had.
    if (tandem::FrameStats drawn = s.render(w, h); !drawn.pipelineFilling) stats = std::move(drawn);
    const auto p0 = std::chrono::steady_clock::now();
    s.renderer_->present(fbW, fbH);
    const double presentMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - p0).count();

    HudInfo info;
    info.game = &s.game_;
    info.view = &s.view_;
    info.paused = s.paused_;
    info.stats = stats;
    info.frameMs = frameMs;
    info.presentMs = presentMs;
    info.framebufferW = fbW;
    info.framebufferH = fbH;
    info.context = contextName.c_str();
    info.message = message.c_str();
    hud.draw(info);

    const bool lastFrame = o.frames > 0 && frames + 1 >= o.frames;
    if (s.wantShot_ || (lastFrame && !o.capture.empty())) {
      const bool scripted = !s.wantShot_;
      s.wantShot_ = false;
      const std::string framePath = scripted ? o.capture : s.nextShotPath("");
      std::string windowPath = framePath;
      windowPath.insert(windowPath.size() - (windowPath.size() >= 4 ? 4 : 0), "-window");
      if (!scripted) ++s.shotIndex_;
      auto a = s.saveFrame(framePath);
      auto b = saveWindow(windowPath, fbW, fbH);
      message = !a ? a.error().message : !b ? b.error().message : "saved " + framePath + " and " + windowPath;
      std::printf("%s\n", message.c_str());
      // The HUD shows just the file name: a full path would stretch the stats window across the frame.
      if (a && b) message = "saved " + std::filesystem::path(framePath).filename().string() + " (+ -window)";
      if (scripted && (!a || !b)) return fail(message);
    }
    s.ctx_.swapBuffers();
    frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - now).count();
    allStats.push_back(stats);
    loopMs.push_back(frameMs);
    lastW = w;
    lastH = h;
    if (++frames >= o.frames && o.frames > 0) break;
  }
  glfwSetWindowUserPointer(window, nullptr);
  std::printf("game: %s frames=%d %s accumulated=%d%s\n", s.game_.stateLine().c_str(), frames, s.settingsLine().c_str(),
              allStats.empty() ? 0 : allStats.back().accumulated,
              allStats.empty() ? "" : radiosityLine(allStats.back().radiosity).c_str());
  printTimes(allStats, loopMs, lastW, lastH);
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app{"Marble Mirrors: roll a glass marble through a hall of mirrors and collect every gem"};
  Options o;
  app.add_flag("--headless", o.headless, "Run offscreen (EGL / OSMesa) with scripted input and a fixed step");
  app.add_option("--frames", o.frames, "Frames to run, then exit (required headless; 0 = until quit)")
      ->check(CLI::Range(0, 10000000));
  app.add_option("--capture", o.capture, "Write the last frame to this PNG (windowed: also OUT-window.png)");
  app.add_option("--script", o.script, "Scripted input file (docs/game.md)");
  app.add_option("--size", o.size, "Frame size headless / window size, WxH (default 640x360 / 1280x720)");
  app.add_option("--preset", o.preset, "raster | hybrid-fast | hybrid-full | reference (default hybrid-fast)");
  app.add_option("--shading", o.shading, "Override every material: flat | gouraud | phong | toon");
  app.add_option("--shadows", o.shadows, "off | raster | ray | hybrid");
  app.add_option("--reflections", o.reflections, "off | raster | ray");
  app.add_option("--refraction", o.refraction, "off | raster | ray");
  app.add_option("--depth", o.depth, "Recursion depth 0..16")->check(CLI::Range(0, 16));
  app.add_option("--scale", o.scale, "Ray-pass scale divisor 1, 2 or 4");
  app.add_option("--threads", o.threads, "Ray-pass threads (0 = all)")->check(CLI::Range(0, 1024));
  app.add_option("--probes-per-frame", o.probesPerFrame,
                 "Raster reflections: probes re-rendered per frame while things move (0 = all, exact)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--reuse", o.reuse,
                 "on | off: a frame where nothing moved reuses the last frame's rays (FrameSettings::reuseRays)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--pipeline", o.pipeline,
                 "on | off | auto: throughput mode (FrameSettings::pipelined, docs/pipeline.md), each frame's rays traced "
                 "while the next frame is rasterized, one frame of latency; auto: on where the GL is a GPU (on a "
                 "software GL both sides share the CPU and it gains nothing)")
      ->check(CLI::IsMember({"on", "off", "auto"}))
      ->capture_default_str();
  app.add_option("--target-fps", o.targetFps,
                 "Frame-time budget in frames per second, 0.1..1000 (FrameSettings::targetMs; key B cycles it)")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--aa", o.aa,
                 "Anti-aliasing: off | ssaa [N] | adaptive [N] (FrameSettings::aa; default off: the game accumulates "
                 "instead)")
      ->expected(1, 2);
  app.add_option("--accumulate", o.accumulate,
                 "While the marble and the camera rest, each frame adds new sub-pixel samples, up to N frames (0 or 1: "
                 "off; FrameSettings::accumulate)")
      ->check(CLI::Range(0, 65536))
      ->capture_default_str();
  app.add_option("--light-samples", o.lightSamples,
                 "Samples per area light per pixel and frame (the hall's key light is a sphere light: soft shadows; "
                 "FrameSettings::lightSamples)")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  app.add_option("--light-samples-past-filter", o.lightSamplesPastFilter,
                 "With --denoise on: samples per area light, at least --light-samples, at every ray hit past the "
                 "primary hit (the mirrors', whose light the filter does not smooth) and in the probes the marble "
                 "refracts (FrameSettings::lightSamplesPastFilter)")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  app.add_option("--radiosity", o.radiosity,
                 "off | on: the hall's diffuse interreflection from a radiosity solution solved in the background, "
                 "the HUD showing its progress (key G; FrameSettings::radiosity, radiosityBackground)")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
  app.add_option("--denoise", o.denoise,
                 "off | on: the spatiotemporal filter (key N; FrameSettings::denoise, docs/denoise.md): each frame "
                 "draws new light samples at a new sub-pixel offset, reprojects the last frames' and smooths what "
                 "is still noisy; with accumulation at rest the exact mean takes over")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
  app.add_option("--frame-log", o.frameLog,
                 "Headless: one CSV row per frame (stage times, rays, the budget's choice; tandem-bench --budget)");
  app.add_option("--error-every", o.errorEvery,
                 "Headless with --frame-log: every Nth frame, FLIP against the same instant drawn as requested "
                 "without the budget (a second renderer)")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--error-truth", o.errorTruth,
                 "requested | converged: --error-every measures against the same instant drawn as requested, or "
                 "against its converged image (no filter, 16 light and lobe samples, 32 jittered frames: what "
                 "sampling and the filter cost the frame; docs/denoise.md)")
      ->check(CLI::IsMember({"requested", "converged"}))
      ->capture_default_str();
  app.add_flag("--check-reuse", o.checkReuse,
               "Headless: draw every frame again with reuse off (a second renderer) and compare them to the bit; "
               "prints the rays reuse saved, fails if a frame differs");
  app.add_option("--dt", o.dt, "Fixed simulation step in seconds (default 1/60)")->check(CLI::Range(0.001, 0.1));
  app.add_flag("--no-vsync", o.noVsync, "Start with vsync off");
  app.add_flag("--fullscreen", o.fullscreen, "Start fullscreen");
  app.add_option("--shots", o.shotDir, "Folder for screenshots (P / F12), default the working directory");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    return fail(e.what());
  }

  int w = o.headless ? 640 : 1280, h = o.headless ? 360 : 720;
  if (!o.size.empty() && !parseSize(o.size, w, h)) return fail("--size: expected WxH, got '" + o.size + "'");
  if (o.headless && o.frames < 1) return fail("--headless needs --frames N (N >= 1)");
  if (!o.headless && !o.frameLog.empty()) return fail("--frame-log: headless runs only (add --headless)");
  if (o.errorEvery > 0 && o.frameLog.empty()) return fail("--error-every: needs --frame-log FILE");
  if (o.checkReuse && !o.headless) return fail("--check-reuse: headless runs only (add --headless)");
  if (o.checkReuse && o.targetFps > 0.0f)
    return fail("--check-reuse: not with --target-fps (the twin's budget would choose on its own clock)");
  if (o.checkReuse && o.reuse == "off") return fail("--check-reuse: needs reuse on");
  // Both compare the frame shown with the same instant drawn by a second renderer: in throughput mode the
  // frame shown is the one before.
  if (o.pipeline == "on" && (o.checkReuse || o.errorEvery > 0))
    return fail(std::string(o.checkReuse ? "--check-reuse" : "--error-every") +
                ": not with --pipeline on (it compares the frame shown with the instant just drawn, a frame later "
                "in throughput mode)");

  ViewState view;
  if (!view.applyPreset(o.preset))
    return fail("--preset: unknown preset '" + o.preset + "' (raster, hybrid-fast, hybrid-full, reference)");
  auto effect = [&](const char* flag, const std::string& v, tandem::EffectMode& out) {
    if (v.empty()) return true;
    auto m = tandem::parseEffectMode(v);
    if (!m) {
      fail(std::string(flag) + ": expected off, raster or ray, got '" + v + "'");
      return false;
    }
    out = *m;
    view.preset = "custom";
    return true;
  };
  if (!o.shadows.empty()) {
    if (!tandem::applyShadowMode(o.shadows, view.settings))
      return fail("--shadows: expected off, raster, ray or hybrid, got '" + o.shadows + "'");
    view.preset = "custom";
  }
  if (!effect("--reflections", o.reflections, view.settings.reflections) ||
      !effect("--refraction", o.refraction, view.settings.refraction))
    return 1;
  if (!o.shading.empty()) {
    auto m = tandem::parseShadingModel(o.shading);
    if (!m) return fail("--shading: expected flat, gouraud, phong or toon, got '" + o.shading + "'");
    view.settings.shadingOverride = *m;
  }
  // A game's trade: a mirror's probe may lag a few frames behind moving marbles (FrameSettings).
  view.settings.probesPerFrame = o.probesPerFrame;
  view.settings.reuseRays = o.reuse == "on";
  if (o.depth >= 0) {
    view.settings.maxDepth = o.depth;
    view.preset = "custom";
  }
  if (o.scale != 0) {
    if (o.scale != 1 && o.scale != 2 && o.scale != 4) return fail("--scale: must be 1, 2 or 4");
    view.settings.rayScale = o.scale;
    view.preset = "custom";
  }
  if (auto mode = tandem::parseAntiAlias(o.aa.front())) {
    view.settings.aa = *mode;
    view.settings.aaSamples = *mode == tandem::AntiAlias::Adaptive ? 16 : 4;
    if (o.aa.size() == 2) {
      char* end = nullptr;
      const long n = std::strtol(o.aa[1].c_str(), &end, 10);
      if (*mode == tandem::AntiAlias::Off || end == o.aa[1].c_str() || *end != '\0' || n < 1 || n > 256)
        return fail("--aa: ssaa and adaptive take a sample count 1..256, got '" + o.aa[1] + "'");
      view.settings.aaSamples = static_cast<int>(n);
    }
  } else {
    return fail("--aa: expected off, ssaa [N] or adaptive [N], got '" + o.aa.front() + "'");
  }
  if (view.settings.aa != tandem::AntiAlias::Off && o.targetFps > 0.0f)
    return fail("--aa: a frame-time budget has no anti-aliasing step yet (drop --target-fps or --aa)");
  if (view.settings.aa != tandem::AntiAlias::Off && o.denoise == "on")
    return fail("--denoise: a frame of several samples (--aa) is not filtered (drop --aa or --denoise)");
  view.settings.accumulate = o.accumulate;
  view.settings.lightSamples = o.lightSamples;
  view.settings.lightSamplesPastFilter = o.lightSamplesPastFilter;
  // The hall's radiosity is solved on a thread of its own while the game runs: the frames never wait for it.
  view.settings.radiosity = o.radiosity == "on";
  view.settings.radiosityBackground = true;
  view.settings.denoise = o.denoise == "on";
  if (!std::isfinite(o.targetFps)) return fail("--target-fps: must be 0.1..1000 frames per second");
  view.setTargetFps(o.targetFps);
  view.vsync = !o.noVsync;
  view.fullscreen = o.fullscreen;
  view.showHelp = !o.headless;

  std::vector<ScriptEvent> events;
  if (!o.script.empty()) {
    std::ifstream f(o.script);
    if (!f) return fail("--script: cannot read '" + o.script + "'");
    std::stringstream text;
    text << f.rdbuf();
    ScriptParse parsed = parseScript(text.str());
    if (!parsed.ok()) return fail(o.script + ": " + parsed.error);
    events = std::move(parsed.events);
  }

  tandem::ContextDesc desc;
  desc.kind = o.headless ? tandem::ContextKind::Headless : tandem::ContextKind::Window;
  desc.width = w;
  desc.height = h;
  desc.title = "Tandem: Marble Mirrors";
  desc.vsync = view.vsync;
  auto ctx = tandem::createGlContext(desc);
  if (!ctx) return fail(ctx.error().message);
  tandem::RendererDesc rdesc;
  rdesc.threads = o.threads;
  auto renderer = tandem::Renderer::create(**ctx, rdesc);
  if (!renderer) return fail(renderer.error().message);
  view.settings.pipelined =
      o.pipeline == "on" || (o.pipeline == "auto" && (*renderer)->hardwareGl() && !o.checkReuse && o.errorEvery == 0);

  Session session(**ctx, std::move(*renderer), view, o.dt, std::move(events), o.shotDir);
  if (auto r = session.init(); !r) return fail(r.error().message);
  return o.headless ? runHeadless(session, o, w, h) : runWindow(session, o);
}

}  // namespace
}  // namespace marble

int main(int argc, char** argv) { return marble::run(argc, argv); }
