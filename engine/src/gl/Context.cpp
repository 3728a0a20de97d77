// GL contexts: one class per platform (EGL, OSMesa, GLFW), each owning its native handles. No GL call
// is made before a context is current and its entry points are loaded.
#include "tandem/Context.h"

#include <dlfcn.h>

#include "gl/Gl.h"  // before any other GL header: glad refuses to follow gl.h

#include <EGL/egl.h>
#include <EGL/eglext.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstring>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "gl/EglDevices.h"
#include "tandem/Log.h"

namespace tandem {
namespace gl {

namespace {
const void* loadedFor = nullptr;
int version = 0;
}  // namespace

void forgetGlLoader(const void* owner) {
  if (owner == loadedFor) loadedFor = nullptr;
}

int loadGl(const void* owner, ProcLoader loader) {
  if (owner != loadedFor || version == 0) {
    version = gladLoadGL(loader);
    loadedFor = version != 0 ? owner : nullptr;
  }
  return version;
}

}  // namespace gl

namespace {

std::string hex(long v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%lX", v);
  return buf;
}

const char* eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
  }
}

Error eglFailure(const std::string& platform, const std::string& step) {
  EGLint code = eglGetError();
  return Error{platform + ": " + step + " failed (" + eglErrorName(code) + ", " + hex(code) + ")"};
}

bool hasExtension(const char* list, const char* name) { return gl::hasEglExtension(list, name); }

const char* glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s != nullptr ? reinterpret_cast<const char*>(s) : "?";
}

std::mutex& debugHandlerMutex() {
  static std::mutex m;
  return m;
}
std::function<void(const GlDebugMessage&)>& debugHandler() {
  static std::function<void(const GlDebugMessage&)> handler;
  return handler;
}

void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint id, GLenum severity, GLsizei length, const GLchar* message,
                              const void*) {
  LogLevel level = severity == GL_DEBUG_SEVERITY_HIGH     ? LogLevel::Error
                   : severity == GL_DEBUG_SEVERITY_MEDIUM ? LogLevel::Warning
                   : type == GL_DEBUG_TYPE_ERROR          ? LogLevel::Error
                                                          : LogLevel::Debug;
  std::string text = "GL debug " + std::to_string(id) + ": ";
  text.append(message, length >= 0 ? static_cast<std::size_t>(length) : std::strlen(message));
  log(level, text);
  std::function<void(const GlDebugMessage&)> handler;
  {
    std::lock_guard<std::mutex> lock(debugHandlerMutex());
    handler = debugHandler();
  }
  if (!handler) return;
  GlDebugMessage m;
  m.kind = type == GL_DEBUG_TYPE_ERROR                ? GlDebugMessage::Kind::Error
           : type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR ? GlDebugMessage::Kind::UndefinedBehavior
           : type == GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR ? GlDebugMessage::Kind::Deprecated
           : type == GL_DEBUG_TYPE_PORTABILITY        ? GlDebugMessage::Kind::Portability
           : type == GL_DEBUG_TYPE_PERFORMANCE        ? GlDebugMessage::Kind::Performance
                                                      : GlDebugMessage::Kind::Other;
  m.high = severity == GL_DEBUG_SEVERITY_HIGH;
  m.id = id;
  m.text = std::move(text);
  handler(m);
}

// Called with the context current and the loader run: checks the version and profile the caller asked
// for (drivers may hand out an older or compatibility context) and installs the debug output.
Result<void> finishGlSetup(const std::string& platform, int loaded, const ContextDesc& desc) {
  if (loaded == 0) return Error{platform + ": loading the GL entry points with glad failed"};
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  if (major * 100 + minor < desc.glMajor * 100 + desc.glMinor)
    return Error{platform + ": got OpenGL " + std::to_string(major) + "." + std::to_string(minor) + " (" +
                 glString(GL_RENDERER) + "), need " + std::to_string(desc.glMajor) + "." +
                 std::to_string(desc.glMinor) + " core"};
  if ((profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0)
    return Error{platform + ": the context is not a core profile (" + glString(GL_VERSION) + ")"};
  if (desc.debug) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  }
  return {};
}

std::string describeCurrent(const std::string& platform) {
  return platform + ", " + glString(GL_RENDERER) + ", OpenGL " + glString(GL_VERSION);
}

// The context of ours last bound on this thread (nullptr: none, or it was destroyed). EGL, OSMesa and GLX all
// bind through Mesa's one GL dispatch, but each keeps its own record of what is current: binding an OSMesa
// context leaves EGL still believing its own is current, and eglMakeCurrent of that one is then skipped as a
// no-op, leaving the thread's GL on the OSMesa context, or on none once that is destroyed (every call fails
// silently: a shader compile fails with an empty log). Each make-current below first releases a context its
// API still records as current when another of ours was bound since.
thread_local GlContext* tBound = nullptr;

// The contexts alive in the process: a context destroyed on another thread than the one that bound it last
// leaves that thread's tBound behind, which is then only compared, never called, unless it is still alive.
std::mutex liveMutex;
std::set<const GlContext*> liveContexts;
void born(const GlContext* c) {
  std::lock_guard lock(liveMutex);
  liveContexts.insert(c);
}
void gone(const GlContext* c) {
  std::lock_guard lock(liveMutex);
  liveContexts.erase(c);
}
// A context of ours bound on this thread since `self` was, to be bound again once `self`'s destruction has
// unbound the thread's GL (nullptr: none, or no longer alive).
GlContext* boundSince(const GlContext* self) {
  if (tBound == self || tBound == nullptr) return nullptr;
  std::lock_guard lock(liveMutex);
  return liveContexts.count(tBound) != 0 ? tBound : nullptr;
}

// ---------------------------------------------------------------------------------------------------
// EGL (device and surfaceless platforms)
// ---------------------------------------------------------------------------------------------------

// eglGetPlatformDisplay returns the same EGLDisplay to every caller, and eglTerminate would destroy the
// contexts of all of them, so displays are reference-counted across GlContexts.
std::mutex displayMutex;
std::map<EGLDisplay, int> displayRefs;

void retainDisplay(EGLDisplay d) {
  std::lock_guard lock(displayMutex);
  ++displayRefs[d];
}

void releaseDisplay(EGLDisplay d) {
  std::lock_guard lock(displayMutex);
  if (--displayRefs[d] == 0) {
    displayRefs.erase(d);
    eglTerminate(d);
  }
}

GLADapiproc eglLoader(const char* name) { return reinterpret_cast<GLADapiproc>(eglGetProcAddress(name)); }

class EglContext final : public GlContext {
 public:
  EglContext(ContextKind kind, std::string platform) : GlContext(kind), platform_(std::move(platform)) { born(this); }
  ~EglContext() override {
    gone(this);
    gl::forgetGlLoader(this);
    GlContext* other = boundSince(this);
    if (tBound == this) tBound = nullptr;
    if (display_ == EGL_NO_DISPLAY) return;
    const bool released = eglGetCurrentContext() == context_;
    if (released) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    releaseDisplay(display_);
    // EGL's release unbound the thread's GL, which was another of ours (bound since): bound again.
    if (released && other != nullptr) other->makeCurrent();
  }

  // Takes an initialised display (retained) and makes a configless, surfaceless core context on it.
  // The platform names it in errors and describe(): for a device, which one ("EGL device 0 of 2 (...)").
  Result<void> init(EGLDisplay display, const ContextDesc& desc) {
    display_ = display;
    retainDisplay(display_);
    const char* exts = eglQueryString(display_, EGL_EXTENSIONS);
    if (!hasExtension(exts, "EGL_KHR_surfaceless_context"))
      return Error{platform_ + ": the display lacks EGL_KHR_surfaceless_context"};
    if (!eglBindAPI(EGL_OPENGL_API)) return eglFailure(platform_, "eglBindAPI(EGL_OPENGL_API)");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(exts, "EGL_KHR_no_config_context")) {
      const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(display_, want, &config, 1, &count)) return eglFailure(platform_, "eglChooseConfig");
      if (count == 0) return Error{platform_ + ": no EGL config renders OpenGL"};
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                              desc.glMajor,
                              EGL_CONTEXT_MINOR_VERSION,
                              desc.glMinor,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_CONTEXT_OPENGL_DEBUG,
                              desc.debug ? EGL_TRUE : EGL_FALSE,
                              EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, attribs);
    if (context_ == EGL_NO_CONTEXT)
      return eglFailure(platform_, "eglCreateContext(OpenGL " + std::to_string(desc.glMajor) + "." +
                                       std::to_string(desc.glMinor) + " core)");
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      return eglFailure(platform_, "eglMakeCurrent");
    tBound = this;
    auto done = finishGlSetup(platform_, gl::loadGl(this, eglLoader), desc);
    if (!done) return done;
    description_ = describeCurrent(platform_);
    return {};
  }

  void makeCurrent() override {
    if (tBound != this && eglGetCurrentContext() == context_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);  // (tBound: EGL's record is stale)
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      logError(eglFailure(platform_, "eglMakeCurrent").message);
      return;
    }
    tBound = this;
    gl::loadGl(this, eglLoader);
  }
  std::string describe() const override { return description_; }

 private:
  std::string platform_;
  std::string description_;
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

// A string a device may answer (only asked when it lists the extension that defines `name`: asking for
// another is EGL_BAD_PARAMETER). "" when it has none; the error is cleared, so it cannot name a later step.
std::string deviceString(PFNEGLQUERYDEVICESTRINGEXTPROC query, EGLDeviceEXT device, EGLint name) {
  const char* value = query(device, name);
  if (value == nullptr) {
    eglGetError();
    return {};
  }
  return value;
}

Result<std::unique_ptr<GlContext>> createEglDevice(const ContextDesc& desc) {
  const std::string platform = "EGL device";
  if (auto exts = gl::checkEglDeviceClientExtensions(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS)); !exts)
    return Error{platform + ": " + exts.error().message};
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryDeviceString =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!queryDevices || !queryDeviceString || !getPlatformDisplay)
    return Error{platform + ": eglQueryDevicesEXT, eglQueryDeviceStringEXT or eglGetPlatformDisplayEXT is missing"};
  EGLint count = 0;
  if (!queryDevices(0, nullptr, &count)) return eglFailure(platform, "eglQueryDevicesEXT");
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  if (count > 0 && !queryDevices(count, devices.data(), &count)) return eglFailure(platform, "eglQueryDevicesEXT");
  devices.resize(static_cast<std::size_t>(count));

  std::vector<gl::EglDeviceInfo> infos;
  for (EGLDeviceEXT device : devices) {
    gl::EglDeviceInfo info;
    info.extensions = deviceString(queryDeviceString, device, EGL_EXTENSIONS);
    const char* exts = info.extensions.c_str();
    std::string node;
    if (hasExtension(exts, "EGL_EXT_device_drm_render_node"))
      node = deviceString(queryDeviceString, device, EGL_DRM_RENDER_NODE_FILE_EXT);
    if (node.empty() && hasExtension(exts, "EGL_EXT_device_drm"))
      node = deviceString(queryDeviceString, device, EGL_DRM_DEVICE_FILE_EXT);
    std::string renderer;
    if (hasExtension(exts, "EGL_EXT_device_query_name")) renderer = deviceString(queryDeviceString, device, EGL_RENDERER_EXT);
    info.name = node.empty() || renderer.empty() ? node + renderer : node + ", " + renderer;
    infos.push_back(std::move(info));
  }
  auto chosen = gl::hardwareEglDevices(infos);
  if (!chosen) return Error{platform + ": " + chosen.error().message};

  // The first hardware device that gives a context; the others are tried only when it fails.
  // Each attempt's failure names the device ("EGL device 1 of 2 (/dev/dri/renderD129): eglInitialize
  // failed (...)"), as describe() names the one chosen.
  std::string tried;
  for (std::size_t index : *chosen) {
    const std::string which = "EGL " + gl::describeEglDevice(index, infos);
    EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[index], nullptr);
    if (display == EGL_NO_DISPLAY) {
      tried += (tried.empty() ? ": " : "; ") + eglFailure(which, "eglGetPlatformDisplayEXT").message;
      continue;
    }
    if (!eglInitialize(display, nullptr, nullptr)) {
      tried += (tried.empty() ? ": " : "; ") + eglFailure(which, "eglInitialize").message;
      continue;
    }
    auto ctx = std::make_unique<EglContext>(ContextKind::EglDevice, which);
    auto ok = ctx->init(display, desc);
    if (ok) return std::unique_ptr<GlContext>(std::move(ctx));
    tried += (tried.empty() ? ": " : "; ") + ok.error().message;
  }
  return Error{platform + ": no hardware EGL device gave a context" + tried};
}

Result<std::unique_ptr<GlContext>> createEglSurfaceless(const ContextDesc& desc) {
  const std::string platform = "EGL surfaceless";
  const char* clientExts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(clientExts, "EGL_MESA_platform_surfaceless"))
    return Error{platform + ": EGL_MESA_platform_surfaceless not supported"};
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!getPlatformDisplay) return Error{platform + ": eglGetPlatformDisplayEXT is missing"};
  EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) return eglFailure(platform, "eglGetPlatformDisplayEXT");
  if (!eglInitialize(display, nullptr, nullptr)) return eglFailure(platform, "eglInitialize");
  auto ctx = std::make_unique<EglContext>(ContextKind::EglSurfaceless, platform);
  auto ok = ctx->init(display, desc);
  if (!ok) return ok.error();
  return std::unique_ptr<GlContext>(std::move(ctx));
}

// ---------------------------------------------------------------------------------------------------
// OSMesa, loaded at run time: libOSMesa exports its own gl* symbols, which must not be linked into the
// process beside libGL / libOpenGL.
// ---------------------------------------------------------------------------------------------------

constexpr int kOsmesaFormat = 0x22;
constexpr int kOsmesaRgba = 0x1908;
constexpr int kOsmesaDepthBits = 0x30;
constexpr int kOsmesaStencilBits = 0x31;
constexpr int kOsmesaAccumBits = 0x32;
constexpr int kOsmesaProfile = 0x33;
constexpr int kOsmesaCoreProfile = 0x34;
constexpr int kOsmesaContextMajor = 0x36;
constexpr int kOsmesaContextMinor = 0x37;

struct OsMesaApi {
  using Context = void*;
  Context (*createContextAttribs)(const int* attribs, Context share) = nullptr;
  unsigned char (*makeCurrent)(Context, void* buffer, GLenum type, int width, int height) = nullptr;
  void (*destroyContext)(Context) = nullptr;
  GLADapiproc (*getProcAddress)(const char* name) = nullptr;
  void* library = nullptr;
};

// The library stays loaded for the life of the process: glad's pointers may still point into it.
Result<const OsMesaApi*> osMesaApi() {
  static OsMesaApi api;
  static std::string failure;
  static std::once_flag once;
  std::call_once(once, [] {
    api.library = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (api.library == nullptr) {
      const char* why = dlerror();
      failure = std::string("OSMesa: dlopen(libOSMesa.so.8) failed: ") + (why ? why : "?");
      return;
    }
    auto sym = [](const char* name) { return dlsym(api.library, name); };
    api.createContextAttribs = reinterpret_cast<decltype(api.createContextAttribs)>(sym("OSMesaCreateContextAttribs"));
    api.makeCurrent = reinterpret_cast<decltype(api.makeCurrent)>(sym("OSMesaMakeCurrent"));
    api.destroyContext = reinterpret_cast<decltype(api.destroyContext)>(sym("OSMesaDestroyContext"));
    api.getProcAddress = reinterpret_cast<decltype(api.getProcAddress)>(sym("OSMesaGetProcAddress"));
    if (!api.createContextAttribs || !api.makeCurrent || !api.destroyContext || !api.getProcAddress)
      failure = "OSMesa: libOSMesa.so.8 lacks OSMesaCreateContextAttribs / MakeCurrent / GetProcAddress";
  });
  if (!failure.empty()) return Error{failure};
  return &api;
}

const OsMesaApi* gOsMesa = nullptr;
GLADapiproc osMesaLoader(const char* name) { return gOsMesa->getProcAddress(name); }

class OsMesaContext final : public GlContext {
 public:
  explicit OsMesaContext(const OsMesaApi& api) : GlContext(ContextKind::OSMesa), api_(api) { born(this); }
  ~OsMesaContext() override {
    gone(this);
    gl::forgetGlLoader(this);
    if (tBound == this) tBound = nullptr;
    if (context_ != nullptr) api_.destroyContext(context_);
  }

  Result<void> init(const ContextDesc& desc) {
    const int attribs[] = {kOsmesaFormat,       kOsmesaRgba,       kOsmesaDepthBits,    0,
                           kOsmesaStencilBits,  0,                 kOsmesaAccumBits,    0,
                           kOsmesaProfile,      kOsmesaCoreProfile, kOsmesaContextMajor, desc.glMajor,
                           kOsmesaContextMinor, desc.glMinor,      0};
    context_ = api_.createContextAttribs(attribs, nullptr);
    if (context_ == nullptr)
      return Error{"OSMesa: OSMesaCreateContextAttribs(OpenGL " + std::to_string(desc.glMajor) + "." +
                   std::to_string(desc.glMinor) + " core) returned no context"};
    if (!makeCurrentNoLoad()) return Error{"OSMesa: OSMesaMakeCurrent failed"};
    tBound = this;
    gOsMesa = &api_;
    auto done = finishGlSetup("OSMesa", gl::loadGl(this, osMesaLoader), desc);
    if (!done) return done;
    description_ = describeCurrent("OSMesa");
    return {};
  }

  void makeCurrent() override {
    // (OSMesaMakeCurrent binds whatever OSMesa records as current: no release needed first)
    if (!makeCurrentNoLoad()) {
      logError("OSMesa: OSMesaMakeCurrent failed");
      return;
    }
    tBound = this;
    gOsMesa = &api_;
    gl::loadGl(this, osMesaLoader);
  }
  std::string describe() const override { return description_; }

 private:
  // Rendering goes to framebuffer objects; the context only needs some colour buffer of its own.
  bool makeCurrentNoLoad() { return api_.makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize) != 0; }

  static constexpr int kSize = 16;
  const OsMesaApi& api_;
  void* context_ = nullptr;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(kSize * kSize * 4);
  std::string description_;
};

Result<std::unique_ptr<GlContext>> createOsMesa(const ContextDesc& desc) {
  auto api = osMesaApi();
  if (!api) return api.error();
  auto ctx = std::make_unique<OsMesaContext>(**api);
  auto ok = ctx->init(desc);
  if (!ok) return ok.error();
  return std::unique_ptr<GlContext>(std::move(ctx));
}

// ---------------------------------------------------------------------------------------------------
// GLFW window
// ---------------------------------------------------------------------------------------------------

std::mutex glfwMutex;
int glfwUsers = 0;
std::string glfwLastError;

void glfwErrorCallback(int code, const char* description) {
  glfwLastError = std::string(description ? description : "?") + " (" + hex(code) + ")";
}

GLADapiproc glfwLoader(const char* name) { return glfwGetProcAddress(name); }

class GlfwContext final : public GlContext {
 public:
  GlfwContext() : GlContext(ContextKind::Window) { born(this); }
  ~GlfwContext() override {
    gone(this);
    gl::forgetGlLoader(this);
    GlContext* other = boundSince(this);
    if (tBound == this) tBound = nullptr;
    // (GLFW detaches a window's context that is current before destroying it, unbinding the thread's GL)
    const bool released = window_ != nullptr && glfwGetCurrentContext() == window_;
    if (window_ != nullptr) glfwDestroyWindow(window_);
    if (initialised_) {
      std::lock_guard lock(glfwMutex);
      if (--glfwUsers == 0) glfwTerminate();
    }
    if (released && other != nullptr) other->makeCurrent();
  }

  Result<void> init(const ContextDesc& desc) {
    {
      std::lock_guard lock(glfwMutex);
      glfwSetErrorCallback(glfwErrorCallback);
      if (glfwUsers == 0 && !glfwInit()) return Error{"GLFW: glfwInit failed: " + glfwLastError};
      ++glfwUsers;
      initialised_ = true;
    }
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, desc.glMajor);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, desc.glMinor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, desc.debug ? GLFW_TRUE : GLFW_FALSE);
    window_ = glfwCreateWindow(std::max(desc.width, 1), std::max(desc.height, 1), desc.title.c_str(), nullptr, nullptr);
    if (window_ == nullptr)
      return Error{"GLFW: glfwCreateWindow (OpenGL " + std::to_string(desc.glMajor) + "." +
                   std::to_string(desc.glMinor) + " core) failed: " + glfwLastError};
    glfwMakeContextCurrent(window_);
    tBound = this;
    auto done = finishGlSetup("GLFW window", gl::loadGl(this, glfwLoader), desc);
    if (!done) return done;
    glfwSwapInterval(desc.vsync ? 1 : 0);
    description_ = describeCurrent("GLFW window");
    return {};
  }

  void makeCurrent() override {
    if (tBound != this && glfwGetCurrentContext() == window_) glfwMakeContextCurrent(nullptr);  // (as EGL's)
    glfwMakeContextCurrent(window_);
    tBound = this;
    gl::loadGl(this, glfwLoader);
  }
  void swapBuffers() override { glfwSwapBuffers(window_); }
  GLFWwindow* window() override { return window_; }
  void framebufferSize(int& width, int& height) override { glfwGetFramebufferSize(window_, &width, &height); }
  void setVsync(bool on) override {
    makeCurrent();
    glfwSwapInterval(on ? 1 : 0);
  }
  std::string describe() const override { return description_; }

 private:
  GLFWwindow* window_ = nullptr;
  bool initialised_ = false;
  std::string description_;
};

Result<std::unique_ptr<GlContext>> createGlfw(const ContextDesc& desc) {
  auto ctx = std::make_unique<GlfwContext>();
  auto ok = ctx->init(desc);
  if (!ok) return ok.error();
  return std::unique_ptr<GlContext>(std::move(ctx));
}

}  // namespace

void setGlDebugHandler(std::function<void(const GlDebugMessage&)> handler) {
  std::lock_guard<std::mutex> lock(debugHandlerMutex());
  debugHandler() = std::move(handler);
}

Result<std::unique_ptr<GlContext>> createGlContext(const ContextDesc& desc) {
  switch (desc.kind) {
    case ContextKind::EglDevice: return createEglDevice(desc);
    case ContextKind::EglSurfaceless: return createEglSurfaceless(desc);
    case ContextKind::OSMesa: return createOsMesa(desc);
    case ContextKind::Window: return createGlfw(desc);
    case ContextKind::Headless: break;
  }
  std::string failures;
  for (auto create : {createEglDevice, createEglSurfaceless, createOsMesa}) {
    auto ctx = create(desc);
    if (ctx) {
      if (!failures.empty()) log(LogLevel::Debug, "headless context: skipped" + failures);
      return ctx;
    }
    failures += "\n  " + ctx.error().message;
  }
  return Error{"no headless OpenGL " + std::to_string(desc.glMajor) + "." + std::to_string(desc.glMinor) +
               " core context:" + failures};
}

}  // namespace tandem
