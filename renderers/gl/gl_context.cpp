#include "renderers/gl/gl_context.h"

#include <fmt/format.h>

#include <cstdio>
#include <vector>

#include "base/error.h"

namespace svr::gl {
namespace {

const char* errorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: return "unknown GL error";
  }
}

}  // namespace

struct GlContext::Impl {
  std::unique_ptr<GlPlatform> platform;
  GlApi api;
  GlLimits limits;
  std::string description;
  // KHR_debug messages of type error since the last check (debug builds). The callback runs
  // synchronously on the thread that made the call, the one holding the context.
  std::vector<std::string> debug_errors;
};

GlContext::GlContext(GlPlatformKind platform) : impl_(std::make_unique<Impl>()) {
  impl_->platform = makePlatform(platform);
  const Current current(*this);
  GlApi& gl = impl_->api;
  // Both platforms' GetProcAddress answer even for names they do not know, so the version
  // below, not a null pointer, is what proves the entry points are real.
#define SVR_GL_LOAD(type, name)                                                            \
  gl.name = reinterpret_cast<type>(impl_->platform->proc("gl" #name));                     \
  if (!gl.name)                                                                            \
    throw Error(fmt::format("gl: {} found no gl" #name,                                    \
                            platformName(impl_->platform->kind())));
  SVR_GL_FUNCTIONS(SVR_GL_LOAD)
#undef SVR_GL_LOAD
  const auto* version = reinterpret_cast<const char*>(gl.GetString(GL_VERSION));
  const auto* renderer = reinterpret_cast<const char*>(gl.GetString(GL_RENDERER));
  int major = 0, minor = 0;
  if (!version || std::sscanf(version, "%d.%d", &major, &minor) != 2 ||
      major * 10 + minor < 45)
    throw Error(fmt::format("gl: the {} context reports OpenGL '{}'; the gl backend needs 4.5",
                            platformName(impl_->platform->kind()), version ? version : "(none)"));
  impl_->description = fmt::format("{}, {}, {}", version, renderer ? renderer : "?",
                                   impl_->platform->describe());

  GlLimits& l = impl_->limits;
  gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &l.max_texture_size);
  gl.GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &l.max_3d_texture_size);
  gl.GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &l.max_array_layers);
  gl.GetIntegerv(GL_MAX_DRAW_BUFFERS, &l.max_draw_buffers);
  gl.GetIntegerv(GL_MAX_DUAL_SOURCE_DRAW_BUFFERS, &l.max_dual_source_buffers);
  GLint64 block = 0;
  gl.GetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
  l.max_storage_block = block;
  gl.GetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &block);
  l.max_texture_buffer = block;
  gl.GetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &l.max_compute_groups_x);
  gl.GetIntegerv(GL_MAX_FRAGMENT_UNIFORM_COMPONENTS, &l.max_fragment_uniforms);
  float point_sizes[2] = {1.f, 1.f};
  gl.GetFloatv(GL_POINT_SIZE_RANGE, point_sizes);
  l.max_point_size = point_sizes[1];
  // Core OpenGL 4.5 guarantees 8 draw buffers and 1 dual-source buffer; a smaller answer means
  // the entry points above are not the ones of a working 4.5 context.
  if (l.max_draw_buffers < 8 || l.max_dual_source_buffers < 1 || l.max_texture_size < 1024)
    throw Error(fmt::format("gl: context '{}' reports {} draw buffers, {} dual-source buffers, "
                            "textures up to {}: below what OpenGL 4.5 guarantees",
                            impl_->description, l.max_draw_buffers, l.max_dual_source_buffers,
                            l.max_texture_size));
#ifndef NDEBUG
  gl.Enable(GL_DEBUG_OUTPUT);
  gl.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  gl.DebugMessageCallback(
      [](GLenum, GLenum type, GLuint, GLenum, GLsizei, const GLchar* message, const void* user) {
        if (type == GL_DEBUG_TYPE_ERROR)
          static_cast<Impl*>(const_cast<void*>(user))->debug_errors.emplace_back(message);
      },
      impl_.get());
#endif
  check("context set-up");
}

GlContext::~GlContext() = default;

const GlApi& GlContext::api() const { return impl_->api; }
const GlLimits& GlContext::limits() const { return impl_->limits; }
const std::string& GlContext::description() const { return impl_->description; }
GlPlatformKind GlContext::platform() const { return impl_->platform->kind(); }

void GlContext::check(const std::string& what) const {
  std::string errors;
  for (GLenum e = impl_->api.GetError(); e != GL_NO_ERROR; e = impl_->api.GetError())
    errors += fmt::format("{}{} (0x{:x})", errors.empty() ? "" : ", ", errorName(e), e);
  for (const std::string& m : impl_->debug_errors)
    errors += fmt::format("{}{}", errors.empty() ? "" : "; ", m);
  impl_->debug_errors.clear();
  if (!errors.empty()) throw Error(fmt::format("gl: {}: {}", what, errors));
}

GlContext::Current::Current(const GlContext& context) : platform_(*context.impl_->platform) {
  platform_.makeCurrent();
}

GlContext::Current::~Current() { platform_.release(); }

}  // namespace svr::gl
