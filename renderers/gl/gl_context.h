#pragma once
// An offscreen OpenGL 4.5 core context, owned RAII-style: the platform's context (OSMesa or EGL,
// gl_platform.h; design.md §5) and the GL function table loaded through it. Both platforms bind a
// context to the calling thread, so a context is used by one thread at a time through a Current
// guard, and everything a render draws goes to framebuffer objects (gl_framebuffer.h), never to
// a default framebuffer.
//
// Errors: a context that cannot be created, or one below 4.5, is an svr::Error; check() turns a
// pending glGetError (and, in debug builds, the KHR_debug messages of type error) into one,
// naming the step that failed.

#include <memory>
#include <string>

#include "renderers/gl/gl_api.h"
#include "renderers/gl/gl_platform.h"

namespace svr::gl {

struct GlLimits {
  int max_texture_size = 0;        // GL_MAX_TEXTURE_SIZE: widest 2D target
  int max_3d_texture_size = 0;     // GL_MAX_3D_TEXTURE_SIZE
  int max_array_layers = 0;        // GL_MAX_ARRAY_TEXTURE_LAYERS
  int max_draw_buffers = 0;        // GL_MAX_DRAW_BUFFERS
  int max_dual_source_buffers = 0; // GL_MAX_DUAL_SOURCE_DRAW_BUFFERS
  long long max_storage_block = 0; // GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes
  long long max_texture_buffer = 0; // GL_MAX_TEXTURE_BUFFER_SIZE, texels
  int max_compute_groups_x = 0;    // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]
  int max_fragment_uniforms = 0;   // GL_MAX_FRAGMENT_UNIFORM_COMPONENTS
  float max_point_size = 1.f;      // GL_POINT_SIZE_RANGE[1], pixels
};

class GlContext {
 public:
  // Creates the context on `platform` and checks that it is OpenGL 4.5 core or newer. Throws
  // svr::Error.
  explicit GlContext(GlPlatformKind platform = defaultPlatform());
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  const GlApi& api() const;
  const GlLimits& limits() const;
  // "4.5 (Core Profile) Mesa 22.3.6, llvmpipe (…), OSMesa"
  const std::string& description() const;
  GlPlatformKind platform() const;

  // Throws svr::Error "gl: <what>: <error>" when GL recorded an error since the last check.
  void check(const std::string& what) const;

  // Makes the context current on this thread while it lives. Throws svr::Error when the
  // platform refuses (for example, when the context is current on another thread).
  class Current {
   public:
    explicit Current(const GlContext& context);
    ~Current();
    Current(const Current&) = delete;
    Current& operator=(const Current&) = delete;

   private:
    GlPlatform& platform_;
  };

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace svr::gl
