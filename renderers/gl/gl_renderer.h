#pragma once
// The OpenGL backend (design.md §5): OpenGL 4.5 core offscreen, on OSMesa or EGL (gl.platform;
// gl_platform.h), in one of two modes sharing context, programs, framebuffers and relighter:
//   raycast  the CPU raycaster's algorithm as a fragment shader (gl_raycast_frame.h; issue 18),
//            the default: the fast way to make an offscreen render;
//   splat    the CPU splat backend's algorithm, direct or in sheets (gl_splat_frame.h; issue 6).
//
// One context per renderer instance, created at the first render (again when gl.platform
// changes) and used by one render at a time (a mutex): renders on several instances run in
// parallel, each on its own context.
//
// Options: `svr render --help-options gl`.

#include <memory>
#include <mutex>

#include "renderers/render/renderer.h"

namespace svr {
namespace gl {
struct GlState;
}

class GlRenderer final : public Renderer {
 public:
  GlRenderer();
  ~GlRenderer() override;
  const BackendInfo& info() const override;

 protected:
  // The mode's render targets and read-back buffer (and, ray casting, the volume's textures,
  // which llvmpipe keeps in host memory).
  std::uint64_t workingBytes(const RenderRequest& request,
                             const BackendOptions& options) const override;
  // Throws svr::Error when no context can be made, a shader fails, or the image or volume
  // exceeds the context's limits (named in the message).
  LightIndependentImage renderImpl(const RenderRequest& request, const BackendOptions& options,
                                   ProgressCounter& progress) const override;

 private:
  mutable std::mutex mutex_;
  mutable std::unique_ptr<gl::GlState> state_;
};

}  // namespace svr
