// tandem-render: renders a scene headless to a PNG or JPEG and prints the per-stage times (median over frames).
//   tandem-render [SCENE] -o OUT.png [--size WxH] [--preset NAME] [--shading MODEL] [--frames N] [--stats OUT.json]
//                 [--trace-pixel X,Y]
// SCENE is a JSON scene file, a .gltf/.glb, or omitted for the embedded Whitted scene. With no --preset
// the scene's render.preset applies, else cli::kDefaultPreset (hybrid-full); the summary names which.
// --trace-pixel prints that pixel's ray tree (Renderer::tracePixel) on stdout after the frame.
// Exit 0 on success; non-zero with a one-line error on any bad input.
#include <algorithm>
#include <functional>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "CliCommon.h"
#include "Progress.h"
#include "tandem/Context.h"
#include "tandem/Log.h"
#include "tandem/PixelTrace.h"
#include "tandem/Renderer.h"
#include "tandem/SceneFile.h"

using namespace tandem;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The columns of the summary and of --stats: every stage (kFrameStages), what lies outside them, the total.
struct Column {
  std::string name;
  std::function<double(const FrameStats&)> cpu;
  std::function<double(const GpuStageTimes&)> gpu;  // empty: no GPU time
};
std::vector<Column> columns() {
  std::vector<Column> c;
  for (const FrameStage& s : kFrameStages) {
    Column col{s.name, [f = s.cpu](const FrameStats& st) { return st.*f; }, {}};
    if (s.gpu != nullptr) col.gpu = [g = s.gpu](const GpuStageTimes& t) { return t.*g; };
    c.push_back(std::move(col));
  }
  c.push_back({"untimed", [](const FrameStats& st) { return st.untimedMs(); }, {}});
  c.push_back({"total", [](const FrameStats& st) { return st.totalMs; }, [](const GpuStageTimes& t) { return t.totalMs(); }});
  return c;
}

int fail(const std::string& message) {
  std::cerr << "tandem-render: " << message << "\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Render a scene headless with Tandem and print per-stage times"};
  std::string scenePath, outPath = "out.png", statsPath, contextName = "headless";
  int frames = 1;
  int threads = 0;
  bool quiet = false;
  std::optional<std::string> tracePixel;
  double progressAfter = 2.0;
  std::string reuse = "off";
  std::string pipeline = "off";
  cli::FrameOptions frameOptions;
  app.add_option("scene", scenePath, "Scene: .json, .gltf or .glb (default: the embedded Whitted scene)");
  app.add_option("-o,--output", outPath, "Output image: .png, or .jpg / .jpeg for JPEG")->capture_default_str();
  app.add_option("--frames", frames, "Frames to render; times are medians over them (>= 1)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--stats", statsPath, "Write the per-stage medians and ray counts as JSON (default: none)");
  app.add_option("--threads", threads, "Ray-pass threads (0 = all)")->check(CLI::Range(0, 1024))->capture_default_str();
  app.add_option("--context", contextName, "headless | egl-device | surfaceless | osmesa")->capture_default_str();
  app.add_flag("-q,--quiet", quiet,
               "Print errors only: no progress line, no summary, no warnings (a glTF's skipped parts, coplanar "
               "faces; the log's level set to errors) (default: all three)");
  app.add_option("--reuse", reuse,
                 "on | off: with on, a frame whose camera, scene and ray settings equal the last frame's reuses its "
                 "rays (FrameSettings::reuseRays; the renderer's and the game's default). Off here by default: "
                 "--frames times every frame's full cost with the camera standing still")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--pipeline", pipeline,
                 "on | off: throughput mode (FrameSettings::pipelined, docs/pipeline.md): each frame's rays trace "
                 "while the next frame is rasterized, one frame of latency; the same images. Off (latency mode) "
                 "by default here: the summary then times each frame alone")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app.add_option("--progress-after", progressAfter,
                 "Seconds a render runs before a progress line (percent, elapsed, ETA) appears on stderr")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--trace-pixel", tracePixel,
                 "X,Y: after the frame, print that pixel's ray tree on stdout (every ray, hit, light, weight and the "
                 "sum that makes the pixel; row 0 at the top; printed under --quiet too) (default: none)");
  std::optional<float> aperture, focusDistance, shutter;
  app.add_option("--aperture", aperture,
                 "Depth of field: the camera's lens diameter in world units, >= 0 (0: a pinhole); each sample of "
                 "--aa or --accumulate sees through a new point of the lens, the reference through one per pixel "
                 "sample (default: the scene camera's aperture)");
  app.add_option("--focus-distance", focusDistance,
                 "Depth of field: distance along the view of the plane in focus, > 0 (default: the scene camera's "
                 "focusDistance, else the target's distance)");
  app.add_option("--shutter", shutter,
                 "Motion blur: seconds the camera's shutter stays open, >= 0 (0: none); instances with a scene "
                 "`motion` move meanwhile, each sample of --aa or --accumulate at a new time, the reference at one "
                 "per pixel sample (default: the scene camera's shutter)");
  std::optional<std::string> environment;
  std::optional<float> environmentIntensity, environmentRotation;
  app.add_option("--environment", environment,
                 "What rays leaving the scene see, whose light is also the ambient term's (docs/environment.md): sky "
                 "(the default sky), none (the scene's background colour, lighting nothing) or an equirectangular "
                 "Radiance .hdr image (default: the scene's: the sky for glTF files; a JSON scene's environment, else "
                 "its background)");
  app.add_option("--environment-intensity", environmentIntensity,
                 "Scales the environment's radiance, >= 0 (a sky or an image: the scene's or --environment's) "
                 "(default: the scene's, else 1)");
  app.add_option("--environment-rotation", environmentRotation,
                 "Turns the environment about +Y, in degrees, counter-clockwise seen from above (a sky or an image: "
                 "the scene's or --environment's) (default: the scene's, else 0)");
  cli::addFrameOptions(app, frameOptions);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    return fail(e.what());
  }
  // Errors only, the engine's log included: a script that asks for quiet reads stderr as "something failed".
  if (quiet) setLogLevel(LogLevel::Error);
  // Refused before the scene loads and renders: a long render should not end in "unsupported extension".
  if (auto format = imageFormatForPath(outPath); !format) return fail("-o: " + format.error().message);
  ContextDesc desc;
  if (contextName == "headless") desc.kind = ContextKind::Headless;
  else if (contextName == "egl-device") desc.kind = ContextKind::EglDevice;
  else if (contextName == "surfaceless") desc.kind = ContextKind::EglSurfaceless;
  else if (contextName == "osmesa") desc.kind = ContextKind::OSMesa;
  else return fail("--context: expected headless, egl-device, surfaceless or osmesa, got '" + contextName + "'");

  Result<Scene> scene = loadAnyScene(scenePath);
  if (!scene) return fail(scene.error().message);
  if (aperture) {
    if (!std::isfinite(*aperture) || *aperture < 0.0f)
      return fail("--aperture: must be a finite lens diameter >= 0, got " + std::to_string(*aperture));
    if (*aperture > 0.0f && scene->camera.orthographic)
      return fail("--aperture: the scene's camera is orthographic and has no lens, got --aperture " +
                  std::to_string(*aperture));
    scene->camera.aperture = *aperture;
  }
  if (shutter) {
    if (!std::isfinite(*shutter) || *shutter < 0.0f)
      return fail("--shutter: must be a finite number of seconds >= 0, got " + std::to_string(*shutter));
    scene->camera.shutter = *shutter;
  }
  if (focusDistance) {
    if (!std::isfinite(*focusDistance) || !(*focusDistance > 0.0f))
      return fail("--focus-distance: must be a finite distance > 0, got " + std::to_string(*focusDistance));
    scene->camera.focusDistance = *focusDistance;
  }

  if (environment) {
    Environment e;  // none: the background colour
    if (*environment == "sky") {
      e.kind = Environment::Kind::Sky;
    } else if (*environment != "none") {
      Result<std::shared_ptr<const EnvironmentMap>> map = loadEnvironmentMap(*environment);
      if (!map) return fail("--environment: " + map.error().message);
      e.kind = Environment::Kind::Map;
      e.map = std::move(*map);
    }
    scene->environment = std::move(e);
  }
  // Each changes a sky or an image (the scene's or --environment's): refused where there is none, as every flag
  // the render would ignore, and out of its range.
  auto environmentValue = [&](const std::string& flag, const std::optional<float>& value, float lo, float hi,
                              const std::string& range, const std::string& verb, float& into) -> std::string {
    if (!value) return {};
    if (scene->environment.kind == Environment::Kind::Background)
      return flag + ": the scene has no sky or image to " + verb + " (--environment sky or FILE.hdr gives one)";
    if (!std::isfinite(*value) || *value < lo || *value > hi)
      return flag + ": must be a finite " + range + ", got " + std::to_string(*value);
    into = *value;
    return {};
  };
  for (const std::string& refused :
       {environmentValue("--environment-intensity", environmentIntensity, 0.0f, 1e6f, "scale in 0..1e6", "scale",
                         scene->environment.intensity),
        environmentValue("--environment-rotation", environmentRotation, -360.0f, 360.0f,
                         "angle in -360..360 degrees", "turn", scene->environment.rotationDeg)})
    if (!refused.empty()) return fail(refused);

  Result<cli::ResolvedFrame> resolved = cli::resolveFrame(frameOptions, scene->render);
  if (!resolved) return fail(resolved.error().message);
  FrameSettings settings = resolved->settings;
  settings.reuseRays = reuse == "on";
  settings.pipelined = pipeline == "on";
  // Checked against the frame before anything renders, like every other value.
  std::optional<glm::ivec2> tracedPixel;
  if (tracePixel) {
    if (settings.gi == GlobalIllumination::Path)
      return fail("--trace-pixel: a path-traced reference (--gi path) has no ray tree to print, got --trace-pixel " +
                  *tracePixel);
    auto pixel = cli::parseTracePixel(*tracePixel, settings.width, settings.height);
    if (!pixel) return fail(pixel.error().message);
    tracedPixel = *pixel;
  }

  auto context = createGlContext(desc);
  if (!context) return fail(context.error().message);

  // A terminal gets one line redrawn in place; a pipe or log file gets a line now and then.
  std::unique_ptr<cli::ProgressLine> progress;
  if (!quiet) progress = std::make_unique<cli::ProgressLine>(stderr, isatty(fileno(stderr)) != 0, progressAfter, frames);
  RendererDesc rdesc;
  rdesc.threads = threads;
  if (progress) rdesc.progress = [line = progress.get()](const RayPassProgress& p) { line->onRayPass(p); };
  auto renderer = Renderer::create(**context, rdesc);
  if (!renderer) return fail(renderer.error().message);
  Camera camera = scene->camera;
  std::string sceneName = scenePath.empty() ? std::string("default (whitted.json)") : scenePath;
  int areaLights = 0;
  for (const Light* l : scene->directLights()) areaLights += isAreaLight(l->type) ? 1 : 0;
  if (auto r = (*renderer)->setScene(std::move(*scene)); !r) return fail(r.error().message);

  // A size the GL cannot hold is refused here with the limit or the allocation it hit, before any frame
  // (rendering it would give a black image).
  std::string sizeSource = frameOptions.size ? "--size " + *frameOptions.size
                                             : "frame size " + std::to_string(settings.width) + "x" +
                                                   std::to_string(settings.height) + " (the scene's render size)";
  if (auto ok = (*renderer)->resize(settings.width, settings.height); !ok)
    return fail(sizeSource + ": " + ok.error().message);

  // --accumulate N: the written image is the converged one, N frames' samples.
  if (settings.accumulate > 1) frames = std::max(frames, settings.accumulate);
  // Throughput mode: a call shows the frame before its own (none the first time), and finish() the last.
  std::vector<FrameStats> stats;
  std::vector<double> intervals;  // between render() calls, the first left out (it has no call before it)
  int drained = 0;
  auto shown = [&](const FrameStats& st) {
    if (!st.error.empty()) return false;
    if (!st.pipelineFilling) stats.push_back(st);
    drained += st.pipelineDrained ? 1 : 0;
    return true;
  };
  for (int i = 0; i < frames; ++i) {
    if (progress) progress->beginFrame(i);
    const FrameStats st = (*renderer)->render(camera, settings);
    if (!shown(st)) return fail(st.error);
    if (i > 0) intervals.push_back(st.intervalMs);
  }
  if (std::optional<FrameStats> done = (*renderer)->finish(); done && !shown(*done)) return fail(done->error);
  if (progress) progress->finish();
  Image image = (*renderer)->readImage();
  if (auto r = writeImage(outPath, image); !r) return fail(r.error().message);

  // The ray counts of the last frame that traced (a reused frame traces nothing).
  const FrameStats& last = stats.back();
  int reused = 0, denoised = 0;
  std::vector<double> denoiseMs;
  const FrameStats* traced = &stats.front();
  for (const FrameStats& s : stats) {
    reused += s.raysReused ? 1 : 0;
    if (!s.raysReused) traced = &s;
    if (s.denoised) {
      ++denoised;
      denoiseMs.push_back(s.denoiseMs);
    }
  }
  nlohmann::json j;
  const std::vector<Column> cols = columns();
  bool anyGpu = false;
  for (const Column& c : cols) {
    std::vector<double> v, g;
    for (const FrameStats& s : stats) {
      v.push_back(c.cpu(s));
      if (c.gpu && s.gpu.valid) g.push_back(c.gpu(s.gpu));
    }
    j["stages_ms"][c.name] = {{"median", median(v)},
                              {"min", *std::min_element(v.begin(), v.end())},
                              {"max", *std::max_element(v.begin(), v.end())}};
    // The GPU's time of the GL stages (timer queries, each frame's read a frame or more later).
    if (!g.empty()) {
      anyGpu = true;
      j["gpu_ms"][c.name] = {{"median", median(g)},
                             {"min", *std::min_element(g.begin(), g.end())},
                             {"max", *std::max_element(g.begin(), g.end())}};
    }
  }
  if (!quiet) {
    std::string preset = "preset " + resolved->preset + " (" + resolved->presetSource + ")";
    for (std::size_t i = 0; i < resolved->changedBy.size(); ++i)
      preset += (i == 0 ? ", changed by " : ", ") + resolved->changedBy[i];
    // A frame without ray effects runs no ray pass (rayWidth 0): say so rather than "ray pass 0x0".
    std::string rayPass = last.rayWidth > 0 ? "ray pass " + std::to_string(last.rayWidth) + "x" +
                                                  std::to_string(last.rayHeight) + " on " +
                                                  std::to_string(last.threads) + " thread(s)"
                                            : std::string("no ray pass");
    std::printf("tandem-render: %s, %dx%d, %d frame(s), %s\n", sceneName.c_str(), settings.width, settings.height,
                frames, preset.c_str());
    std::printf("  %s\n", (*context)->describe().c_str());
    std::printf("  %s; %s\n", cli::describeSettings(settings).c_str(), rayPass.c_str());
    std::printf("  %-11s %10s %10s %10s%s\n", "stage", "median ms", "min ms", "max ms", anyGpu ? "    GPU ms" : "");
    for (const Column& c : cols) {
      const nlohmann::json& ms = j["stages_ms"][c.name];
      std::printf("  %-11s %10.2f %10.2f %10.2f", c.name.c_str(), ms["median"].get<double>(), ms["min"].get<double>(),
                  ms["max"].get<double>());
      if (anyGpu && j["gpu_ms"].contains(c.name)) std::printf(" %9.2f", j["gpu_ms"][c.name]["median"].get<double>());
      std::printf("\n");
    }
    std::printf("  rays/frame: primary %llu, shadow %llu, reflection %llu, refraction %llu\n",
                static_cast<unsigned long long>(traced->rays.primary), static_cast<unsigned long long>(traced->rays.shadow),
                static_cast<unsigned long long>(traced->rays.reflection),
                static_cast<unsigned long long>(traced->rays.refraction));
    if (traced->rays.resolved > 0)
      std::printf("  exact solids: %llu pixels of their proxies resolved by camera rays\n",
                  static_cast<unsigned long long>(traced->rays.resolved));
    if (settings.hybridShadows && settings.shadows == EffectMode::Ray) {
      // The maps are built by the first frame (and again after a move or a light change).
      double buildMs = 0;
      for (const FrameStats& s : stats) buildMs = std::max(buildMs, s.shadowMapsMs);
      std::printf("  hybrid shadows: %llu shadow tests answered by tile shafts and %llu rays by the light-space maps instead "
                  "(the primary hits' proved %s); maps %.1f MB, built in %.1f ms (first frame)\n",
                  static_cast<unsigned long long>(traced->rays.shadowByShaft),
                  static_cast<unsigned long long>(traced->rays.shadowByMap),
                  traced->shadowsProvedInGl ? "in the GL" : "by the ray pass",
                  static_cast<double>(traced->shadowMapBytes) / 1e6, buildMs);
    }
    if (settings.aa != AntiAlias::Off || settings.accumulate > 1) {
      std::uint64_t refined = 0;
      int samples = 0;
      for (const FrameStats& s : stats) refined += s.refinedPixels, samples += s.samples;
      std::printf("  anti-aliasing: %d sample(s) drawn over the run, the image averages up to %d per pixel", samples,
                  last.accumulated);
      if (settings.aa == AntiAlias::Adaptive)
        std::printf("; the adaptive rounds re-sampled %llu pixel-samples (%.2f frames' worth)",
                    static_cast<unsigned long long>(refined),
                    static_cast<double>(refined) / (static_cast<double>(settings.width) * settings.height));
      std::printf("\n");
    }
    if (areaLights > 0)
      std::printf("  area lights: %d, %d sample(s) each per point and frame%s%s\n", areaLights, settings.lightSamples,
                  settings.shadows == EffectMode::Ray ? ", a shadow ray each" : "",
                  denoised > 0 && settings.unfilteredLightSamples() != settings.lightSamples
                      ? (", " + std::to_string(settings.unfilteredLightSamples()) +
                         " past the primary hit and in the probes in the filtered frames")
                            .c_str()
                      : "");
    if (last.radiosity.active)
      std::printf("  radiosity: %d patches, %llu shots, unshot light %.4f of what entered, solved in %.0f ms (in "
                  "the first frame's prepare)\n",
                  last.radiosity.patches, static_cast<unsigned long long>(last.radiosity.shots),
                  static_cast<double>(last.radiosity.residual), last.radiosity.solveMs);
    if (reused > 0)
      std::printf("  %d of %d frame(s) reused the frame before's rays (--reuse on: nothing moved)\n", reused, frames);
    if (denoised > 0)
      std::printf("  %d of %d frame(s) filtered (--denoise on): the filter's median %.2f ms, part of composite\n",
                  denoised, frames, median(denoiseMs));
    if (!intervals.empty())
      std::printf("  interval between frames: median %.2f ms (%.1f fps)%s\n", median(intervals),
                  1000.0 / std::max(median(intervals), 1e-3),
                  settings.pipelined ? "; throughput mode: total is each frame's latency, a frame's stages overlap "
                                       "the next one's raster"
                                     : "");
    if (drained > 0)
      std::printf("  %d frame(s) completed before the next was drawn (the scene, the settings or the size changed)\n",
                  drained);
    if (last.budget.active) {
      int changes = 0;
      for (std::size_t i = 1; i < stats.size(); ++i) changes += stats[i].budget.step != stats[i - 1].budget.step;
      std::printf("  budget %.1f ms: last frame step %d of %d (%s), predicted %.1f ms, expected FLIP %+.4f; "
                  "%d change(s) over the run%s\n",
                  last.budget.targetMs, last.budget.step, last.budget.steps, describeBudget(last.budget).c_str(),
                  last.budget.predictedMs, last.budget.expectedError, changes,
                  last.budget.reachable ? "" : "; the target is out of reach (cheapest choice predicted over it)");
    }
  }
  if (!statsPath.empty()) {
    j["scene"] = sceneName;
    j["width"] = settings.width;
    j["height"] = settings.height;
    j["preset"] = resolved->preset;
    j["frames"] = frames;
    j["threads"] = last.threads;
    j["context"] = (*context)->describe();
    j["settings"] = {{"shadows", shadowModeName(settings)},
                     {"reflections", toString(settings.reflections)},
                     {"refraction", toString(settings.refraction)},
                     {"maxDepth", settings.maxDepth},
                     {"rayScale", settings.rayScale},
                     {"reference", settings.reference},
                     {"referenceSpp", settings.referenceSpp}};
    // Compiles after the first frame are stalls a game would see mid-run; a steady loop has none.
    int laterCompiles = 0;
    for (std::size_t i = 1; i < stats.size(); ++i) laterCompiles += stats[i].shaderCompiles;
    j["shader_compiles"] = {{"first_frame", stats.front().shaderCompiles}, {"later_frames", laterCompiles}};
    j["rays"] = {{"primary", traced->rays.primary},
                 {"shadow", traced->rays.shadow},
                 {"reflection", traced->rays.reflection},
                 {"refraction", traced->rays.refraction},
                 {"shadow_by_map", traced->rays.shadowByMap},
                 {"shadow_by_shaft", traced->rays.shadowByShaft},
                 {"resolved", traced->rays.resolved}};
    if (settings.hybridShadows && settings.shadows == EffectMode::Ray) {
      double buildMs = 0;
      for (const FrameStats& s : stats) buildMs = std::max(buildMs, s.shadowMapsMs);
      j["hybrid_shadows"] = {{"map_bytes", traced->shadowMapBytes}, {"build_ms_max", buildMs}};
    }
    if (settings.aa != AntiAlias::Off || settings.accumulate > 1) {
      std::uint64_t refined = 0;
      int samples = 0;
      for (const FrameStats& s : stats) refined += s.refinedPixels, samples += s.samples;
      j["antialiasing"] = {{"aa", toString(settings.aa)},         {"aa_samples", settings.aaSamples},
                           {"aa_threshold", settings.aaThreshold}, {"accumulate", settings.accumulate},
                           {"samples_drawn", samples},             {"refined_pixel_samples", refined},
                           {"accumulated", last.accumulated}};
    }
    if (areaLights > 0)
      j["area_lights"] = {{"count", areaLights},
                          {"light_samples", settings.lightSamples},
                          {"light_samples_past_filter", denoised > 0 ? settings.unfilteredLightSamples()
                                                                                     : settings.lightSamples}};
    if (last.radiosity.active)
      j["radiosity"] = {{"patches", last.radiosity.patches},
                        {"shots", last.radiosity.shots},
                        {"residual", last.radiosity.residual},
                        {"solve_ms", last.radiosity.solveMs},
                        {"error_target", settings.radiosityError},
                        {"shot_cap", settings.radiosityShots},
                        {"refine", settings.radiosityRefine}};
    j["reuse"] = settings.reuseRays;
    j["pipelined"] = settings.pipelined;
    if (!intervals.empty())
      j["interval_ms"] = {{"median", median(intervals)},
                          {"min", *std::min_element(intervals.begin(), intervals.end())},
                          {"max", *std::max_element(intervals.begin(), intervals.end())}};
    if (settings.pipelined) {
      std::vector<double> waits;
      for (const FrameStats& s : stats) waits.push_back(s.raysWaitMs);
      j["pipeline"] = {{"drained_frames", drained}, {"rays_wait_ms_median", median(waits)}};
    }
    j["frames_reusing_rays"] = reused;
    j["denoise"] = settings.denoise;
    if (denoised > 0) j["denoise_ms_median"] = median(denoiseMs);
    j["frames_denoised"] = denoised;
    if (last.budget.active) {
      nlohmann::json steps = nlohmann::json::array();
      for (const FrameStats& s : stats) steps.push_back(s.budget.step);
      j["budget"] = {{"target_ms", last.budget.targetMs},       {"steps", last.budget.steps},
                     {"step", last.budget.step},                {"choice", describeBudget(last.budget)},
                     {"predicted_ms", last.budget.predictedMs}, {"expected_flip", last.budget.expectedError},
                     {"reachable", last.budget.reachable},      {"denoise", last.budget.denoise},
                     {"step_per_frame", steps}};
    }
    std::ofstream f(statsPath);
    if (!f) return fail("--stats: cannot write " + statsPath);
    f << j.dump(2) << "\n";
    if (!f) return fail("--stats: cannot write " + statsPath);
  }
  if (tracedPixel) {
    // After the summary: the last frame's pixel, re-traced (the frame itself paid nothing for it).
    auto trace = (*renderer)->tracePixel(tracedPixel->x, tracedPixel->y);
    if (!trace) return fail("--trace-pixel: " + trace.error().message);
    std::fputs(toText(*trace, (*renderer)->scene()).c_str(), stdout);
  }
  return 0;
}
