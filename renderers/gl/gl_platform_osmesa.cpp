// OSMesa: a context inside the process, on Mesa's llvmpipe, with a 1×1 default framebuffer
// OSMesaMakeCurrent insists on (renders go to framebuffer objects).

// osmesa.h pulls in GL/gl.h; it only declares, nothing here calls a GL symbol directly.
#include <GL/osmesa.h>

#include <array>
#include <mutex>

#include "renderers/gl/gl_platform.h"
#include "base/error.h"

namespace svr::gl {
namespace {

// OSMesa keeps process-wide state (its state-tracker manager and screen) that it sets up on the
// first context creation; creation and destruction are serialised so two renderers starting on
// two threads never race on it. Rendering itself runs unserialised, one context per thread.
std::mutex& lifecycleMutex() {
  static std::mutex m;
  return m;
}

class OsmesaPlatform final : public GlPlatform {
 public:
  OsmesaPlatform() {
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                              OSMESA_STENCIL_BITS, 0, OSMESA_ACCUM_BITS, 0,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 4,
                              OSMESA_CONTEXT_MINOR_VERSION, 5, 0};
    const std::lock_guard lock(lifecycleMutex());
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_)
      throw Error(
          "gl: OSMesaCreateContextAttribs could not create an OpenGL 4.5 core context "
          "(OSMesa needs Mesa's llvmpipe; see GALLIUM_DRIVER and LIBGL_DEBUG=verbose)");
  }
  ~OsmesaPlatform() override {
    const std::lock_guard lock(lifecycleMutex());
    OSMesaDestroyContext(context_);
  }
  GlPlatformKind kind() const override { return GlPlatformKind::kOsmesa; }
  void makeCurrent() override {
    if (!OSMesaMakeCurrent(context_, pixel_.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw Error("gl: OSMesaMakeCurrent failed (is the context current on another thread?)");
  }
  void release() noexcept override { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }
  void* proc(const char* name) const override {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
  }
  std::string describe() const override { return "OSMesa"; }

 private:
  OSMesaContext context_ = nullptr;
  std::array<unsigned char, 4> pixel_{};
};

}  // namespace

std::unique_ptr<GlPlatform> makeOsmesaPlatform() { return std::make_unique<OsmesaPlatform>(); }

}  // namespace svr::gl
