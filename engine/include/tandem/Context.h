#pragma once
// An OpenGL 4.5 core context, chosen by the application. No GL header here: the interface is plain.
//
//   auto ctx = createGlContext({.kind = ContextKind::Headless});
//   if (!ctx) { std::cerr << ctx.error().message << "\n"; return 1; }
//
// Headless tries, in order: the EGL device platform (a real GPU), EGL surfaceless (Mesa), OSMesa.
// describe() names the platform and, for the device platform, the device chosen.
// A context is current on the thread that created it; it is not thread-safe.
#include <functional>
#include <memory>
#include <string>

#include "tandem/Result.h"

struct GLFWwindow;

namespace tandem {

enum class ContextKind {
  Headless,        // EGL device → EGL surfaceless → OSMesa, the first that gives GL 4.5 core
  EglDevice,       // the EGL device platform only: the first EGL device that is not a software renderer
                   // (Mesa's llvmpipe device is skipped) and gives a context. Needs EGL_EXT_platform_device
                   // and EGL_EXT_device_base (or EGL_EXT_device_enumeration + EGL_EXT_device_query).
  EglSurfaceless,  // EGL_MESA_platform_surfaceless only
  OSMesa,          // OSMesa only (software)
  Window,          // a GLFW window
};

struct ContextDesc {
  ContextKind kind = ContextKind::Headless;
  int glMajor = 4;  // requested core version; tests ask for impossible ones to check the failure path
  int glMinor = 5;
  int width = 1280;  // window size (Window only)
  int height = 720;
  std::string title = "Tandem";
  bool vsync = true;
  bool debug = false;  // KHR_debug output to the log (and to setGlDebugHandler's handler), synchronous; the
                       // passes also check, before each draw, that every sampler has what it declares bound
};

/// One KHR_debug message of a context made with ContextDesc::debug: from the driver, or from Tandem's own
/// check of the texture bindings before a draw (source "application", type undefined behaviour).
struct GlDebugMessage {
  enum class Kind { Error, UndefinedBehavior, Deprecated, Portability, Performance, Other };
  Kind kind = Kind::Other;
  bool high = false;  // severity high
  unsigned id = 0;
  std::string text;
};
/// Called for every such message on the thread whose GL call raised it (besides the log); one per process,
/// empty to remove. Tests use it to fail on errors and undefined behaviour.
void setGlDebugHandler(std::function<void(const GlDebugMessage&)> handler);

class GlContext {
 public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  virtual void makeCurrent() = 0;
  /// Presents the default framebuffer (windows); a no-op headless.
  virtual void swapBuffers() {}
  /// The window, for input; nullptr headless.
  virtual GLFWwindow* window() { return nullptr; }
  /// Size of the default framebuffer (windows) in pixels; 0×0 when minimised or headless.
  virtual void framebufferSize(int& width, int& height) { width = height = 0; }
  virtual void setVsync(bool) {}
  /// e.g. "EGL surfaceless, Mesa llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6" or
  /// "EGL device 0 of 2 (/dev/dri/renderD128, NVIDIA GeForce RTX 4090), NVIDIA GeForce RTX 4090/PCIe/SSE2, ..."
  /// (the device's DRM node and name where it gives them).
  virtual std::string describe() const = 0;
  ContextKind kind() const { return kind_; }

 protected:
  explicit GlContext(ContextKind kind) : kind_(kind) {}

 private:
  ContextKind kind_;
};

/// Creates a context and makes it current, with the GL functions loaded. On failure the error names
/// what failed and the EGL / GLFW / OSMesa error.
Result<std::unique_ptr<GlContext>> createGlContext(const ContextDesc& desc);

}  // namespace tandem
