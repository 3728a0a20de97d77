// The Renderer's API around the frame: creation, the scene and its mutators (each records what it changed
// in Impl::changes, render/SceneChanges.h), resize, tracePixel and the output. The frame itself: Renderer.cpp.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "core/Finite.h"
#include "render/RendererImpl.h"

namespace tandem {

Result<std::unique_ptr<Renderer>> Renderer::create(GlContext& context, const RendererDesc& desc) {
  context.makeCurrent();
  // (a thread whose GL is bound to no context answers every call with nothing: say so here, not as a failed
  // shader compile)
  if (glGetString(GL_VERSION) == nullptr)
    return Error{"Renderer: the GL context (" + context.describe() + ") is not current on this thread after "
                 "makeCurrent(): the GL answers no GL_VERSION"};
  auto impl = std::make_unique<Impl>();
  impl->context = &context;
  auto tracer = rt::RayTracer::create(desc.threads);
  if (!tracer) return Error{"Renderer: " + tracer.error().message};
  impl->tracer = std::move(*tracer);
  impl->tracer->setProgressCallback(desc.progress);
  auto visibility = gl::VisibilityPass::create();
  if (!visibility) return Error{"Renderer: " + visibility.error().message};
  impl->visibilityPass = std::move(*visibility);
  auto shade = gl::ShadePass::create();
  if (!shade) return Error{"Renderer: " + shade.error().message};
  impl->shadePass = std::move(*shade);
  auto output = gl::OutputPass::create();
  if (!output) return Error{"Renderer: " + output.error().message};
  impl->outputPass = std::move(*output);
  impl->limits = gl::queryFrameLimits();
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;

Result<void> Renderer::setScene(Scene scene) {
  auto valid = validateScene(scene);
  if (!valid) return Error{"Renderer::setScene: " + valid.error().message + " (the previous scene stays)"};
  impl_->scene = std::move(scene);
  impl_->changes.replaced = true;
  return {};
}

const Scene& Renderer::scene() const { return impl_->scene; }

void Renderer::setInstanceTransform(std::uint32_t instance, const glm::mat4& worldFromObject) {
  Impl& r = *impl_;
  assert(instance < r.scene.instances.size() && "Renderer::setInstanceTransform: instance out of range");
  if (!allFinite(worldFromObject)) {
    logWarning("Renderer::setInstanceTransform: instance " + std::to_string(instance) +
               " given a NaN or infinite transform; kept the previous one");
    return;
  }
  Instance& inst = r.scene.instances[instance];
  // A game may set every transform every frame: one that did not change leaves the caches, the shadow maps
  // and the last frame's rays valid.
  if (inst.worldFromObject == worldFromObject) return;
  inst.worldFromObject = worldFromObject;
  (inst.dynamic ? r.changes.dynamicMoved : r.changes.staticMoved) = true;
}

void Renderer::setInstanceMotion(std::uint32_t instance, glm::vec3 velocity, glm::vec3 angularVelocity) {
  Impl& r = *impl_;
  assert(instance < r.scene.instances.size() && "Renderer::setInstanceMotion: instance out of range");
  auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(velocity) || !finite(angularVelocity)) {
    logWarning("Renderer::setInstanceMotion: instance " + std::to_string(instance) +
               " given a NaN or infinite motion; kept the previous one");
    return;
  }
  Instance& inst = r.scene.instances[instance];
  if (inst.velocity == velocity && inst.angularVelocity == angularVelocity) return;
  inst.velocity = velocity;
  inst.angularVelocity = angularVelocity;
  r.changes.dynamicMoved = true;  // motion is drawn, never solved for
}

void Renderer::setLight(std::uint32_t light, const Light& value) {
  Impl& r = *impl_;
  assert(light < r.scene.lights.size() && "Renderer::setLight: light out of range");
  const Result<void> valid = validateLight(value, "Renderer::setLight: light " + std::to_string(light));
  int direct = 0;
  for (std::size_t i = 0; i < r.scene.lights.size(); ++i)
    direct += (i == light ? value.type : r.scene.lights[i].type) != LightType::Ambient ? 1 : 0;
  if (!valid || direct > kMaxLights) {
    logWarning((valid ? "Renderer::setLight: light " + std::to_string(light) + " would exceed the light limit"
                      : valid.error().message) +
               "; kept the previous one");
    return;
  }
  if (r.scene.lights[light] == value) return;  // unchanged: as for setInstanceTransform
  r.scene.lights[light] = value;
  r.changes.lights = true;
}

// The frame's GL targets at width × height (resize, and the prepare stage of a frame of another size).
Result<void> Renderer::Impl::allocateFrame(int width, int height) {
  if (width == targetWidth && height == targetHeight) return {};
  if (width == failedWidth && height == failedHeight) return Error{failure};
  targetWidth = targetHeight = 0;
  accum.release();  // its samples and its shown mean were in the targets replaced here
  auto fail = [&](std::string why) -> Result<void> {
    outputPass.release();
    shadePass.releaseFrame();
    visibilityPass.release();
    failedWidth = width;
    failedHeight = height;
    failure = why;
    return Error{std::move(why)};
  };
  // The driver's limits first: they are what the hardware can do, and cost no allocation to check.
  if (auto within = gl::checkFrameLimits(width, height, limits); !within) return fail(within.error().message);
  if (width > kMaxFrameSide || height > kMaxFrameSide)
    return fail((width > kMaxFrameSide ? "width " + std::to_string(width) : "height " + std::to_string(height)) +
                " exceeds kMaxFrameSide = " + std::to_string(kMaxFrameSide));
  const std::string needs = "the frame's GL targets need " +
                            gl::formatBytes(gl::OutputPass::targetBytes(width, height) +
                                            gl::VisibilityPass::targetBytes(width, height)) +
                            "; ";
  // The composite pass first: its RGBA32F radiance is the largest texture, so a driver that cannot hold
  // the size refuses it before anything else is allocated.
  shadePass.releaseFrame();  // its depth copy is made again at the new size by the first frame that needs it
  if (auto made = outputPass.resize(width, height); !made) return fail(needs + made.error().message);
  if (auto made = visibilityPass.resize(width, height); !made) return fail(needs + made.error().message);
  targetWidth = width;
  targetHeight = height;
  failedWidth = failedHeight = 0;
  failure.clear();
  return {};
}

Result<void> Renderer::resize(int width, int height) {
  Impl& r = *impl_;
  if (width < 1 || height < 1)
    return Error{"frame size " + std::to_string(width) + "x" + std::to_string(height) + ": must be at least 1x1"};
  r.failedWidth = r.failedHeight = 0;  // asked again: try again (memory may have been freed since)
  r.drain();  // the frame in flight is composited at the size it was drawn
  return r.allocateFrame(width, height);
}

Result<PixelTrace> Renderer::tracePixel(int x, int y) {
  Impl& r = *impl_;
  r.drain();  // throughput mode: the frame in flight is the last frame, shown first
  r.applyChanges();
  const FrameHistory& f = r.last;
  if (!f.drawn) return Error{"tracePixel: no frame to trace (none rendered yet, or the last one was not drawn)"};
  if (f.sceneChanged)
    return Error{"tracePixel: the scene changed since the last frame (setScene, setInstanceTransform or setLight); "
                 "render a frame, then trace it"};
  if (f.plan.settings.gi == GlobalIllumination::Path)
    return Error{"tracePixel: a path-traced reference frame (FrameSettings::gi) has no ray tree"};
  const int width = f.plan.settings.width, height = f.plan.settings.height;
  if (x < 0 || y < 0 || x >= width || y >= height)
    return Error{"tracePixel: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                 std::to_string(width) + "x" + std::to_string(height) + " frame"};
  // A frame without rays did not need the Embree scene; the trace does (the scene is the frame's: unchanged).
  if (!r.caches.syncRays(r.scene, f.camera.shutter, *r.tracer))
    return Error{"tracePixel: the ray pass cannot use this scene (Embree refused it)"};

  PixelTrace trace;
  if (f.plan.reference) {
    trace = r.tracer->tracePixelReference(r.scene, f.camera, f.plan.settings, x, y);
  } else {
    // The ids the ray pass read back, or (a frame without a ray pass) the visibility pass's, still the frame's.
    rt::VisibilityBuffer idsNow;
    const rt::VisibilityBuffer* visibility = &r.visibility;
    if (!f.plan.rayPass) {
      idsNow.width = width;
      idsNow.height = height;
      r.visibilityPass.readIds(idsNow.ids);
      visibility = &idsNow;
    }
    const int scale = std::max(1, f.plan.raySettings.rayScale);
    trace = r.tracer->tracePixel(r.scene, f.camera, f.plan.raySettings, *visibility, x / scale, y / scale);
    trace.x = x;
    trace.y = y;
  }
  trace.settings = f.plan.settings;
  trace.rayPass = f.plan.rayPass;

  // What the frame's pixel has that the rays do not: the GL's parts the trace names but does not recompute.
  const TraceNode* primary = trace.roots.empty() ? nullptr : &trace.nodes[static_cast<std::size_t>(trace.roots.front())];
  const bool onSurface = primary && primary->hit;
  if (f.plan.settings.debugView != DebugView::Final)
    trace.notes.push_back("the frame shows the " + std::string(toString(f.plan.settings.debugView)) +
                          " debug view, not this colour");
  if (!f.plan.reference && trace.rayScale > 1)
    trace.notes.push_back("the ray pass ran at 1/" + std::to_string(trace.rayScale) +
                          " resolution: the frame shades its local term at (" + std::to_string(x) + ", " +
                          std::to_string(y) + ") and upsamples the grid's reflected and transmitted radiance there; "
                          "this trace is of the grid pixel's rays, at pixel (" + std::to_string(trace.tracedX) +
                          ", " + std::to_string(trace.tracedY) + ")");
  if (onSurface && f.shadowMaps)
    trace.notes.push_back("shadows are raster: the frame takes the primary hit's light visibility from the shadow "
                          "maps, which the trace does not model (its local term counts every light as visible)");
  if (onSurface && (f.probeEffects & gl::kProbeReflect))
    trace.notes.push_back("reflections are raster: the frame's primary hit reflects a probe, which the trace does not model");
  if (onSurface && (f.probeEffects & gl::kProbeRefract))
    trace.notes.push_back((f.probeEffects & gl::kProbeBehind)
                              ? "refraction is raster: the frame's primary hit refracts a probe, or sees through to the "
                                "view behind see-through surfaces (IOR 1), which the trace does not model"
                              : "refraction is raster: the frame's primary hit refracts a probe, which the trace does not model");
  if (onSurface && !f.plan.reference) {
    const ShadingModel model = f.plan.settings.shadingOverride.value_or(r.scene.materials[primary->material].shading);
    if (model == ShadingModel::Toon)
      trace.notes.push_back("toon shading: the frame may draw a silhouette outline over this pixel");
  }
  return trace;
}

std::optional<FrameStats> Renderer::finish() {
  Impl& r = *impl_;
  std::optional<FrameStats> done = r.drain();
  if (done) {
    done->gpu = r.gpuTimers.endFrame();
    done->intervalMs = r.sinceLastCall ? r.sinceLastCall->ms() : 0.0;
    r.sinceLastCall.emplace();
  }
  return done;
}

void Renderer::present(int framebufferWidth, int framebufferHeight) {
  impl_->outputPass.present(framebufferWidth, framebufferHeight);
}

Image Renderer::readImage() { return impl_->outputPass.readImage(); }

ImageF Renderer::readLinear() { return impl_->outputPass.readLinear(); }

bool Renderer::hardwareGl() const { return !impl_->limits.software; }

ResourceStats Renderer::resources() const {
  ResourceStats r;
  r.glObjects = gl::liveObjectCount();
  r.embreeBytes = impl_->tracer ? impl_->tracer->embreeBytes() : 0;
  r.embreeHandles = rt::liveEmbreeHandles();
  return r;
}

}  // namespace tandem
