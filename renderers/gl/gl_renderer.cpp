#include "renderers/gl/gl_renderer.h"

#include <fmt/format.h>

#include "renderers/kernels/gradient_volume.h"
#include "renderers/kernels/splat_settings.h"
#include "renderers/gl/gl_relighter.h"
#include "renderers/gl/gl_state.h"
#include "renderers/render/backend_entry.h"
#include "base/error.h"

namespace svr {
namespace {

// The splat options of the splat backend, its `mode` (sheet or direct) as `splat_mode` here.
std::vector<OptionSpec> glOptionSpecs() {
  std::vector<OptionSpec> specs{
      OptionSpec::choice("mode", {"raycast", "splat"},
                         "raycast: a ray per pixel in a fragment shader (the raycast backend's "
                         "algorithm); splat: the splat backend's algorithm"),
      OptionSpec::choice("platform", {"auto", "osmesa", "egl"},
                         "where the OpenGL context comes from; auto: EGL on a GPU when one is "
                         "present, OSMesa otherwise"),
      OptionSpec::choice("gradients", {"auto", "precomputed", "on-the-fly"},
                         "raycast: normals from gradients precomputed at the voxels (a 3D "
                         "texture of 8 bytes a voxel) or central differences per sample; auto: "
                         "precomputed when they fit the memory budget")};
  for (OptionSpec spec : splat::splatOptionSpecs()) {
    if (spec.key == "mode") spec.key = "splat_mode";
    spec.help = "splat: " + spec.help;
    specs.push_back(std::move(spec));
  }
  return specs;
}

// The precomputed gradients unless on-the-fly is asked for or, with auto, they do not fit.
std::shared_ptr<const GradientVolume> gradientsFor(const RenderRequest& req,
                                                   const std::string& mode) {
  if (mode == "on-the-fly") return nullptr;
  return gradientsWithinBudget(req, mode == "precomputed", "gl");
}

}  // namespace

GlRenderer::GlRenderer() = default;
GlRenderer::~GlRenderer() = default;

const BackendInfo& GlRenderer::info() const {
  static const BackendInfo info{
      "gl",
      "OpenGL 4.5 core offscreen (OSMesa or EGL): the raycaster's algorithm in a fragment "
      "shader, or the splat backend's",
      {.perspective = true, .spectral_transmittance = true, .max_channels = 128,
       .needs_gl = true},
      glOptionSpecs()};
  return info;
}

std::uint64_t GlRenderer::workingBytes(const RenderRequest& req,
                                       const BackendOptions& options) const {
  if (options.choice("mode") == "splat") return gl::splatWorkingBytes(req);
  return gl::raycastWorkingBytes(req) +
         gl::raycastDeviceBytes(req.volume, options.choice("gradients") != "on-the-fly");
}

LightIndependentImage GlRenderer::renderImpl(const RenderRequest& req,
                                             const BackendOptions& options,
                                             ProgressCounter& progress) const {
  const std::lock_guard lock(mutex_);
  const gl::GlPlatformKind platform = gl::platformOf(options.choice("platform"));
  if (state_ && state_->context.platform() != platform) state_.reset();
  if (!state_) state_ = std::make_unique<gl::GlState>(platform);
  const gl::GlContext::Current current(state_->context);
  const gl::GlLimits& limits = state_->context.limits();
  // An image beyond the limits fails before anything big is allocated.
  if (req.width > limits.max_texture_size || req.height > limits.max_texture_size)
    throw Error(fmt::format("gl: a {}×{} image is beyond GL_MAX_TEXTURE_SIZE {}", req.width,
                            req.height, limits.max_texture_size));
  if (options.choice("mode") == "splat") {
    splat::SplatSettings settings = splat::splatSettings(options, "splat_mode");
    return gl::renderSplats(*state_, req, settings, progress);
  }
  const auto gradients = gradientsFor(req, options.choice("gradients"));
  return gl::renderRaycast(*state_, req, gradients.get(), progress);
}

namespace backends {
BackendEntry gl() {
  return {GlRenderer().info(), [] { return std::make_unique<GlRenderer>(); },
          [] { return std::make_unique<GlRelighter>(); }, {}};
}
}  // namespace backends

}  // namespace svr
