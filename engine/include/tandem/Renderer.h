#pragma once
// The Renderer: one frame, top to bottom — prepare → raster → readback → rays → composite → present.
// It owns the GL objects and the Embree scene derived from the Scene it is given.
//
//   auto ctx = createGlContext({});
//   auto renderer = Renderer::create(**ctx);
//   (*renderer)->setScene(std::move(scene));
//   if (auto ok = (*renderer)->resize(settings.width, settings.height); !ok) { /* ok.error().message */ }
//   FrameStats stats = (*renderer)->render(scene.camera, settings);
//   Image frame = (*renderer)->readImage();
//   if (auto trace = (*renderer)->tracePixel(640, 360)) std::puts(toText(*trace, (*renderer)->scene()).c_str());
//
// Not thread-safe: call it from the thread whose GL context is current. The ray pass uses its own
// worker threads internally.
#include <memory>
#include <optional>

#include "tandem/Context.h"
#include "tandem/FrameStats.h"
#include "tandem/Image.h"
#include "tandem/PixelTrace.h"
#include "tandem/Progress.h"
#include "tandem/Result.h"
#include "tandem/Scene.h"
#include "tandem/Settings.h"

namespace tandem {

/// What the renderer holds right now: the soak test checks these stay flat across scene reloads.
struct ResourceStats {
  std::size_t glObjects = 0;    // live GL objects (buffers, textures, framebuffers, programs, ...)
  std::size_t embreeBytes = 0;  // bytes Embree reports in use (device memory monitor)
  std::size_t embreeHandles = 0;  // Embree devices and scenes alive in the process (one per BLAS, top level, device)
};

struct RendererDesc {
  int threads = 0;  // ray-pass worker threads; 0 = all hardware threads
  /// Optional: told as each tile of a frame's ray pass finishes (Progress.h says from which threads; in
  /// throughput mode, FrameSettings::pipelined, also after render() has returned).
  /// Frames without a ray pass (every effect raster or off) make no calls, nor do frames that reuse the
  /// last frame's rays (FrameSettings::reuseRays).
  RayPassProgressCallback progress = {};
};

class Renderer {
 public:
  static Result<std::unique_ptr<Renderer>> create(GlContext& context, const RendererDesc& desc = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Validates and installs a scene. On error the previous scene stays and the error names the reason.
  Result<void> setScene(Scene scene);
  const Scene& scene() const;
  /// Moves an instance (static or dynamic); the next frame updates the GL instance buffer and Embree's top
  /// level only: no mesh's BVH is rebuilt. Shadow maps and probes are re-rendered (the scene changed).
  /// Setting the transform (or, with setLight, the light) it already has changes nothing.
  void setInstanceTransform(std::uint32_t instance, const glm::mat4& worldFromObject);
  /// Motion blur: how an instance moves while the camera's shutter is open (Instance::velocity in world units
  /// per second, angularVelocity in radians per second about its origin; docs/motion-blur.md). A game sets it
  /// with the transform each frame; non-finite values are refused (logged, the old motion kept).
  void setInstanceMotion(std::uint32_t instance, glm::vec3 velocity, glm::vec3 angularVelocity);
  void setLight(std::uint32_t light, const Light& value);

  /// Makes the frame's GL targets for width × height now, so that a size the GL cannot hold is an error
  /// here, where it can be handled, rather than a black frame. The error names what stops it: a driver
  /// limit and its value ("width 16385 exceeds GL_MAX_TEXTURE_SIZE = 16384"; GL_MAX_FRAMEBUFFER_WIDTH /
  /// HEIGHT, GL_MAX_VIEWPORT_DIMS), kMaxFrameSide, or the texture the driver refused and the memory the
  /// frame needs (GL_OUT_OF_MEMORY: llvmpipe refuses any texture over 2 GiB, i.e. frames over 2^27 pixels).
  /// The targets are then released. render() resizes by itself when the size changes; call this where the
  /// size comes from outside (a window resize, a command-line flag) and before the first frame.
  Result<void> resize(int width, int height);
  /// Renders one frame into the renderer's offscreen target (in throughput mode, FrameSettings::pipelined:
  /// begins this frame and shows the one before; FrameStats are then the shown frame's). With settings.targetMs > 0 the frame is drawn
  /// with the settings or a cheaper choice that fits the target (FrameStats::budget says which;
  /// docs/budget.md). Bad settings are clamped; the one failure
  /// is a frame size the GL cannot hold: nothing is drawn and FrameStats::error says why (the same
  /// message resize() gives; a size that failed is not tried again by render() until resize() is called
  /// or another size is rendered).
  FrameStats render(const Camera& camera, const FrameSettings& settings);
  /// Throughput mode (FrameSettings::pipelined): completes the frame still in flight (waits for its rays,
  /// composites and presents it) and returns its stats; nullopt when none is. Call it before capturing the
  /// last frame of a sequence, or where the application needs the frame it last asked for on screen. render()
  /// in latency mode, resize() and tracePixel() do it themselves. The scene's mutators and setScene() may be
  /// called while a frame is in flight: its rays see the scene as it was when it was drawn.
  std::optional<FrameStats> finish();
  /// The ray tree of pixel (x, y) of the last frame (row 0 at the top, as readImage): the frame's ray
  /// pass re-run for that one pixel, with its camera, settings and visibility, recording every ray, hit,
  /// light, weight and the sum that makes the pixel (tandem/PixelTrace.h; toText prints it). For a
  /// debugging tool or a key binding in a game: the frame itself pays nothing for it, the call costs
  /// about one pixel's rays (plus, after a frame without ray effects, the id read-back and the Embree
  /// scene that frame did not need). With rayScale > 1 it traces the ray-grid pixel that covers (x, y).
  /// Errors: no frame drawn yet, the scene changed since (the frame's ids would be stale), (x, y) outside
  /// the frame, a scene Embree refused. Call it from the GL context's thread, like render().
  Result<PixelTrace> tracePixel(int x, int y);
  /// Draws the last frame into the default framebuffer (windows), size in pixels.
  void present(int framebufferWidth, int framebufferHeight);
  /// The last frame shown (or its debug view), 8-bit sRGB, top row first: in throughput mode
  /// (FrameSettings::pipelined) the frame before the last one render() was asked for, until finish().
  Image readImage();
  /// The last frame shown in linear radiance before the tone map.
  ImageF readLinear();
  ResourceStats resources() const;
  /// Whether the GL rasterizes on a GPU (false for a software rasterizer such as llvmpipe, whose raster and
  /// composite share the CPU with the ray pass): where throughput mode (FrameSettings::pipelined) pays.
  bool hardwareGl() const;

  struct Impl;

 private:
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace tandem
