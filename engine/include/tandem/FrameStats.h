#pragma once
// What one frame cost: time per stage (milliseconds, wall clock) and rays of each kind, or why it was not drawn.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tandem/Settings.h"

namespace tandem {

struct RayCounts {
  std::uint64_t primary = 0;     // exact primary hits recomputed on the CPU (or camera rays in reference mode)
  std::uint64_t shadow = 0;
  std::uint64_t reflection = 0;
  std::uint64_t refraction = 0;
  /// Hybrid shadows: shadow rays the light-space maps answered instead (not traced, not in total()).
  std::uint64_t shadowByMap = 0;
  /// Reuse across frames (FrameSettings::reuseRays): shadow rays whose answer was kept from the frame
  /// before, the camera still and nothing that moved near them (not traced, not in total()).
  std::uint64_t shadowKept = 0;
  /// Hybrid shadows' tile shafts (docs/shadows.md "Tile shafts"): shadow tests (a point and a light)
  /// answered lit together with the rest of their tile's towards the light, nothing else able to meet any
  /// of them: not traced, not even set up, so a point whose light could not reach it (which needs no ray)
  /// counts here too.
  std::uint64_t shadowByShaft = 0;
  /// Exact solids (docs/csg.md): camera rays traced for the pixels the raster drew with an exact solid's
  /// proxy (the resolved pixels), each finding the solid's exact hit or what lies behind it.
  std::uint64_t resolved = 0;
  std::uint64_t total() const { return primary + shadow + reflection + refraction + resolved; }
  RayCounts& operator+=(const RayCounts& o) {
    primary += o.primary, shadow += o.shadow, reflection += o.reflection, refraction += o.refraction;
    shadowByMap += o.shadowByMap, shadowKept += o.shadowKept, shadowByShaft += o.shadowByShaft, resolved += o.resolved;
    return *this;
  }
};

/// The frame-time budget's choice for a frame (FrameSettings::targetMs, docs/budget.md).
struct BudgetStats {
  bool active = false;       // targetMs > 0 on a hybrid frame
  int step = 0;              // 0: the settings as requested; 1 .. steps-1: cheaper, by expected error
  int steps = 0;             // the choices the budget had for these settings and this scene
  int rayScale = 1;          // what the frame was drawn with
  int maxDepth = 0;
  EffectMode shadows = EffectMode::Off, reflections = EffectMode::Off, refraction = EffectMode::Off;
  bool hybridShadows = false;
  bool denoise = false;      // one light and lobe sample a frame, filtered (FrameSettings::denoise), in place
                             // of the request's samples raw
  double targetMs = 0;
  double predictedMs = 0;    // what the cost model expected (0 before it had measured a frame)
  double expectedError = 0;  // FLIP this choice adds over the requested settings (the error table)
  bool reachable = true;     // false: even the cheapest choice is predicted over the target
};
/// "1/2 d2 refraction raster" for a step > 0 (" filtered" after it where the filter runs in place of the
/// request's samples), "as requested" for step 0, "" when inactive.
std::string describeBudget(const BudgetStats& b);

/// The radiosity solution a frame showed (FrameSettings::radiosity; docs/radiosity.md).
struct RadiosityStats {
  bool active = false;     // the frame showed a solution
  bool converged = false;  // the solve has stopped: at radiosityError or radiosityShots
  int patches = 0;         // patch sides
  std::uint64_t shots = 0;
  float residual = 1.0f;   // unshot light over the light that entered
  double solveMs = 0;      // time the solve has taken so far (its own thread's, in the background)
};

/// The GPU's own time of the frame's GL stages (timer queries, GL_TIME_ELAPSED), read back a frame or more
/// later so that nothing waits for them: the latest frame whose queries had all finished. On llvmpipe the GL
/// is CPU work too; on a GPU the difference from the CPU stage is what a pipelined frame can hide.
struct GpuStageTimes {
  bool valid = false;   // false until a frame's queries have come back (or where the GL has no timer queries)
  int framesAgo = 0;    // how many render() calls before this one drew the frame they measured
  double shadowsMs = 0, probesMs = 0, rasterMs = 0, uploadMs = 0, compositeMs = 0, accumulateMs = 0;
  double totalMs() const { return shadowsMs + probesMs + rasterMs + uploadMs + compositeMs + accumulateMs; }
};

struct FrameStats {
  // Every part of a frame is in one of these stages (wall clock, ms), in the order a frame runs them; their
  // sum is the frame's total but for the timers' own cost (untimedMs(); tests hold it under 2 %).
  double planMs = 0;        // the frame's decisions: the scene's facts, the frame-time budget's choice, the plan
  double prepareMs = 0;     // the frame's targets, the GL copy and Embree scene brought up to date, radiosity
  double syncMs = 0;        // each sample's GL copy of what moves under an open shutter (motion blur)
  double shadowsMs = 0;     // raster shadow maps drawn (only when their lights or what they see changed)
  double probesMs = 0;      // reflection probes drawn (likewise, or a few a frame: probesPerFrame)
  double rasterMs = 0;      // the visibility G-buffer pass, including glFinish
  double readbackMs = 0;    // G-buffer channels to memory for the ray pass
  double raysMs = 0;        // the CPU ray pass (with the exact solids' resolve step)
  double uploadMs = 0;      // ray results to GL textures
  double compositeMs = 0;   // shading + composite + tone map, including glFinish
  double accumulateMs = 0;  // anti-aliasing and accumulation: each sample's linear frame read and summed, the mean shown
  double bookkeepingMs = 0; // what later frames need of this one: the history reuse and tracePixel read, the budget's learning
  double presentMs = 0;     // swap or capture
  double totalMs = 0;
  /// The sum of the stages above, and what of the total lies outside them.
  double stagesMs() const {
    return planMs + prepareMs + syncMs + shadowsMs + probesMs + rasterMs + readbackMs + raysMs + uploadMs +
           compositeMs + accumulateMs + bookkeepingMs + presentMs;
  }
  double untimedMs() const { return totalMs - stagesMs(); }
  GpuStageTimes gpu;
  /// Adds a sample's stage times and rays (a frame of several samples: anti-aliasing, adaptive rounds);
  /// the rest (grid, threads, maps) becomes the sample's.
  void addSample(const FrameStats& sample);
  RayCounts rays;
  int rayWidth = 0;        // resolution the ray pass ran at
  int rayHeight = 0;
  int threads = 0;         // worker threads of the ray pass
  /// Hybrid shadows: the part of raysMs spent building the light-space maps (after the geometry or a light
  /// changed; 0 on a frame that kept them), and the bytes they hold.
  double shadowMapsMs = 0;
  std::size_t shadowMapBytes = 0;
  /// Hybrid shadows proved in the GL (FrameSettings::shadowProofs): the GL's pass answered the primary hits'
  /// rays it could (in rays.shadowByMap with the CPU's answers) before the ray pass; its time is rasterMs'.
  bool shadowsProvedInGl = false;
  /// Reflection probes drawn in this frame (six views of the scene each; probesMs their time) and the probes the
  /// scene has (FrameSettings::probeLimit at most; objects past it share).
  int probesDrawn = 0;
  int probes = 0;
  /// Shader programs compiled during this frame: a variant first needed by a new scene, view or preset
  /// (each a stall of up to a second on a software GL). Zero in a steady game loop.
  int shaderCompiles = 0;
  /// The ray results are the last frame's (FrameSettings::reuseRays: nothing they depend on changed):
  /// `rays` is then all zero, since nothing was traced, and the readback and ray pass cost nothing.
  bool raysReused = false;
  /// The spatiotemporal filter (FrameSettings::denoise) reconstructed this frame from its one noisy sample and
  /// the last frames' (reprojected, rejected where unseen, clamped): what is shown is an estimate, not the
  /// rays' answers as traced (raysReused, above, is reuse: the same answers to the bit); also while an
  /// accumulation at rest still blends the filtered frame into the mean of the samples drawn since.
  /// `denoiseMs`: the filter's part of compositeMs.
  bool denoised = false;
  double denoiseMs = 0;
  /// Anti-aliasing and accumulation (FrameSettings::aa, accumulate): the sub-pixel samples this call drew
  /// (each a whole frame: the stage times and ray counts above are their sums; 0 when it showed an
  /// accumulation that had converged), the pixel-samples among them the adaptive rounds re-shaded, and the
  /// samples per pixel the shown frame averages (its most-sampled pixel's).
  int samples = 1;
  std::uint64_t refinedPixels = 0;
  int accumulated = 1;
  /// FrameSettings::targetMs: the choice this frame was drawn with.
  BudgetStats budget;
  RadiosityStats radiosity;
  /// Throughput mode (FrameSettings::pipelined, docs/pipeline.md). `pipelined`: the call ran in it and these
  /// stats are those of the frame it showed (drawn partly by the call before: its plan, raster and read-back
  /// there, its rays on their own threads in between, its upload and composite here); totalMs is then its
  /// latency, from the start of the call that began it to its composite here, which also holds the next
  /// frame's raster and the application's time between the calls, so untimedMs() is not the frame's own.
  /// `pipelineFilling`: the call began a frame and had none to show (the pipeline's first frame, or the first
  /// after a latency-mode frame): every stage is zero and readImage() holds what it held. `pipelineDrained`:
  /// the call had to complete the frame in flight before drawing its own (a new scene, other settings, proofs in
  /// the GL), so nothing of the two overlapped. `raysWaitMs`: how long the call waited for the shown frame's
  /// rays after its own GL work (0: the rays had finished first).
  bool pipelined = false;
  bool pipelineFilling = false;
  bool pipelineDrained = false;
  double raysWaitMs = 0;
  /// Milliseconds from the return of the previous render() call to the return of this one: the frame
  /// interval the application sees, in both modes (0 on a renderer's first call).
  double intervalMs = 0;

  /// Empty when the frame was drawn. Otherwise why it was not: the GL could not hold this frame size
  /// (a limit it exceeds, or an allocation the driver refused, named as Renderer::resize names them).
  /// readImage() is then empty when the frame's own targets failed, else it keeps the last frame drawn.
  std::string error;
};

/// The stages in the order a frame runs them, by the names tandem-render's --stats, the bench and the game's
/// frame log give them; `gpu` is the stage's GPU time where it has one (nullptr: CPU work only).
struct FrameStage {
  const char* name;
  double FrameStats::*cpu;
  double GpuStageTimes::*gpu;
};
inline constexpr FrameStage kFrameStages[] = {
    {"plan", &FrameStats::planMs, nullptr},
    {"prepare", &FrameStats::prepareMs, nullptr},
    {"sync", &FrameStats::syncMs, nullptr},
    {"shadows", &FrameStats::shadowsMs, &GpuStageTimes::shadowsMs},
    {"probes", &FrameStats::probesMs, &GpuStageTimes::probesMs},
    {"raster", &FrameStats::rasterMs, &GpuStageTimes::rasterMs},
    {"readback", &FrameStats::readbackMs, nullptr},
    {"rays", &FrameStats::raysMs, nullptr},
    {"upload", &FrameStats::uploadMs, &GpuStageTimes::uploadMs},
    {"composite", &FrameStats::compositeMs, &GpuStageTimes::compositeMs},
    {"accumulate", &FrameStats::accumulateMs, &GpuStageTimes::accumulateMs},
    {"bookkeeping", &FrameStats::bookkeepingMs, nullptr},
    {"present", &FrameStats::presentMs, nullptr},
};

}  // namespace tandem
