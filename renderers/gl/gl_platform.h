#pragma once
// Where an offscreen OpenGL 4.5 core context comes from (issue 18): OSMesa (Mesa's llvmpipe in
// the process, no device at all) or EGL's device platform (EGL_EXT_platform_device: a GPU's
// driver where one is present, Mesa's software device otherwise), both headless. A platform
// object owns one context; GlContext (gl_context.h) loads the GL entry points through proc()
// and does everything else the same way on both.
//
// Neither platform links libGL or libOpenGL: their gl* symbols would shadow OSMesa's, and calls
// would go silently nowhere (design.md §5). Every GL function comes from proc().

#include <memory>
#include <string>

namespace svr::gl {

enum class GlPlatformKind { kOsmesa, kEgl };

// "osmesa", "egl".
const char* platformName(GlPlatformKind kind);
// The platform `gl.platform=auto` means: EGL when it enumerates a hardware device (a GPU, not
// Mesa's software device), OSMesa otherwise. Asked once per process.
GlPlatformKind defaultPlatform();
// "auto", "osmesa", "egl" (the gl backend's option); svr::Error for anything else.
GlPlatformKind platformOf(const std::string& name);

class GlPlatform {
 public:
  virtual ~GlPlatform() = default;
  virtual GlPlatformKind kind() const = 0;
  // Binds the context to the calling thread; svr::Error when the platform refuses.
  virtual void makeCurrent() = 0;
  virtual void release() noexcept = 0;
  // A GL entry point by name ("glGetString"), or null.
  virtual void* proc(const char* name) const = 0;
  // What the context runs on, beyond GL_RENDERER: "EGL 1.5 (Mesa Project), software device".
  virtual std::string describe() const = 0;
};

// A 4.5 core context on that platform. Throws svr::Error saying why none could be made (the
// platform not built in, no device, no 4.5 core context).
std::unique_ptr<GlPlatform> makeOsmesaPlatform();
std::unique_ptr<GlPlatform> makeEglPlatform();
std::unique_ptr<GlPlatform> makePlatform(GlPlatformKind kind);

}  // namespace svr::gl
