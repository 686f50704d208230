// EGL's device platform (EGL_EXT_platform_device): a context on an enumerated device without
// any surface (EGL_KHR_surfaceless_context, EGL_KHR_no_config_context). A GPU's device is
// preferred; Mesa's software device (llvmpipe) serves otherwise, so the same path runs here
// and on a machine with a GPU. Built when libEGL was found (SVR_GL_EGL, renderers/gl/CMakeLists).

#include <fmt/format.h>

#include <mutex>

#include "renderers/gl/gl_platform.h"
#include "base/error.h"

#if SVR_GL_EGL
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstring>
#include <vector>
#endif

namespace svr::gl {

#if SVR_GL_EGL
namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return fmt::format("EGL error 0x{:x}", e);
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = std::strstr(list, name); p; p = std::strstr(p + 1, name))
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// The devices EGL enumerates, hardware ones first.
struct Device {
  EGLDeviceEXT device;
  bool software;
};
std::vector<Device> enumerateDevices() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasExtension(client, "EGL_EXT_device_enumeration") ||
      !hasExtension(client, "EGL_EXT_platform_device"))
    throw Error(fmt::format("gl: EGL lacks device enumeration (EGL_EXT_device_enumeration, "
                            "EGL_EXT_platform_device); its client extensions: {}",
                            client && *client ? client
                                              : "none: no EGL vendor library answered (is "
                                                "libegl-mesa0 installed?)"));
  const auto query = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(
      eglGetProcAddress("eglQueryDevicesEXT"));
  const auto device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  EGLint n = 0;
  if (!query || !device_string || !query(0, nullptr, &n) || n <= 0)
    throw Error("gl: EGL enumerates no device (is libegl-mesa0 installed?)");
  std::vector<EGLDeviceEXT> ids(n);
  query(n, ids.data(), &n);
  std::vector<Device> out;
  for (int i = 0; i < n; ++i)
    out.push_back({ids[i], hasExtension(device_string(ids[i], EGL_EXTENSIONS),
                                        "EGL_MESA_device_software")});
  std::stable_partition(out.begin(), out.end(), [](const Device& d) { return !d.software; });
  return out;
}

// eglInitialize and eglTerminate act on a display for the whole process, so the display of
// the chosen device is opened once, shared by every context and kept until the process ends:
// terminating it unloads Mesa's driver, and what the driver keeps of compiled shaders (a few
// hundred bytes) would then be reported as leaked from an unknown module, where
// LeakSanitizer suppressions cannot name it.
struct SharedDisplay {
  std::mutex mutex;
  EGLDisplay display = EGL_NO_DISPLAY;
  bool software = false;
  std::string description;
};
SharedDisplay& sharedDisplay() {
  static SharedDisplay d;
  return d;
}

class EglPlatform final : public GlPlatform {
 public:
  EglPlatform() {
    SharedDisplay& shared = sharedDisplay();
    const std::lock_guard lock(shared.mutex);
    if (shared.display == EGL_NO_DISPLAY) open(shared);
    display_ = shared.display;
    describe_ = shared.description;
    const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
    for (const char* needed : {"EGL_KHR_surfaceless_context", "EGL_KHR_no_config_context"})
      if (!hasExtension(extensions, needed))
        throw Error(fmt::format("gl: the EGL display ({}) lacks {}", describe_, needed));
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    if (!eglBindAPI(EGL_OPENGL_API) ||
        (context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes)) ==
            EGL_NO_CONTEXT) {
      const EGLint error = eglGetError();
      throw Error(fmt::format("gl: EGL could not create an OpenGL 4.5 core context on {}: {}",
                              describe_, eglErrorName(error)));
    }
  }
  ~EglPlatform() override {
    const std::lock_guard lock(sharedDisplay().mutex);
    eglDestroyContext(display_, context_);
  }
  GlPlatformKind kind() const override { return GlPlatformKind::kEgl; }
  void makeCurrent() override {
    if (!eglBindAPI(EGL_OPENGL_API) ||
        !eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw Error(fmt::format("gl: eglMakeCurrent failed: {} (is the context current on "
                              "another thread?)",
                              eglErrorName(eglGetError())));
  }
  void release() noexcept override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  void* proc(const char* name) const override {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
  }
  std::string describe() const override { return describe_; }

 private:
  static void open(SharedDisplay& shared) {
    const auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) throw Error("gl: EGL has no eglGetPlatformDisplayEXT");
    std::string failures;
    for (const Device& device : enumerateDevices()) {
      EGLDisplay display = get_display(EGL_PLATFORM_DEVICE_EXT, device.device, nullptr);
      EGLint major = 0, minor = 0;
      if (display != EGL_NO_DISPLAY && eglInitialize(display, &major, &minor)) {
        const char* vendor = eglQueryString(display, EGL_VENDOR);
        shared.display = display;
        shared.software = device.software;
        shared.description = fmt::format("EGL {}.{} ({}), {} device", major, minor,
                                         vendor ? vendor : "?",
                                         device.software ? "software" : "hardware");
        return;
      }
      failures += fmt::format("{}{} device: {}", failures.empty() ? "" : "; ",
                              device.software ? "software" : "hardware",
                              eglErrorName(eglGetError()));
    }
    throw Error(fmt::format("gl: no EGL device could be initialised ({})", failures));
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string describe_;
};

bool hardwareDeviceEnumerated() {
  try {
    for (const Device& d : enumerateDevices())
      if (!d.software) return true;
  } catch (const Error&) {
  }
  return false;
}

}  // namespace

std::unique_ptr<GlPlatform> makeEglPlatform() { return std::make_unique<EglPlatform>(); }

GlPlatformKind defaultPlatform() {
  static const GlPlatformKind kind =
      hardwareDeviceEnumerated() ? GlPlatformKind::kEgl : GlPlatformKind::kOsmesa;
  return kind;
}

#else

std::unique_ptr<GlPlatform> makeEglPlatform() {
  throw Error("gl: the EGL platform is not built in (libEGL was not found when svr was "
              "configured: install libegl-dev and configure again)");
}

GlPlatformKind defaultPlatform() { return GlPlatformKind::kOsmesa; }

#endif

}  // namespace svr::gl
