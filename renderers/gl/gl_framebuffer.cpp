#include "renderers/gl/gl_framebuffer.h"

#include <fmt/format.h>

#include "base/error.h"

namespace svr::gl {
namespace {

const char* statusName(GLenum status) {
  switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
      return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS:
      return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    default: return "unknown status";
  }
}

}  // namespace

void checkFramebufferComplete(const GlContext& context, GLuint framebuffer,
                              const std::string& what) {
  const GLenum status = context.api().CheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(fmt::format("gl: framebuffer '{}' is incomplete: {} (0x{:x})", what,
                            statusName(status), status));
}

LayeredTarget::LayeredTarget(const GlContext& context, int width, int height, int layers,
                             std::string name)
    : context_(context), width_(width), height_(height), layers_(layers), name_(std::move(name)) {
  const GlLimits& limits = context.limits();
  if (width < 1 || height < 1 || width > limits.max_texture_size ||
      height > limits.max_texture_size)
    throw Error(fmt::format("gl: {}: a {}×{} image is beyond GL_MAX_TEXTURE_SIZE {}", name_,
                            width, height, limits.max_texture_size));
  // A layer is read back in one call whose byte count is a GLsizei.
  if (static_cast<long long>(width) * height * 4 * sizeof(float) > 0x7fffffffLL)
    throw Error(fmt::format("gl: {}: a {}×{} RGBA32F layer is beyond the 2 GiB GL reads at once",
                            name_, width, height));
  if (layers < 1 || layers > limits.max_array_layers)
    throw Error(fmt::format("gl: {}: {} layers of 4 channels are beyond "
                            "GL_MAX_ARRAY_TEXTURE_LAYERS {}",
                            name_, layers, limits.max_array_layers));
  const GlApi& gl = context.api();
  GLuint id = 0;
  gl.CreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  texture_ = GlObject(id, gl.DeleteTextures);
  gl.TextureStorage3D(id, 1, GL_RGBA32F, width, height, layers);
  context.check(fmt::format("allocating {} ({}×{}, {} RGBA32F layers)", name_, width, height,
                            layers));
}

void LayeredTarget::drawInto(int first, int count) {
  const GlApi& gl = context_.api();
  GlObject& fbo = framebuffers_[{first, count}];
  if (!fbo) {
    if (first < 0 || count < 1 || first + count > layers_ ||
        count > context_.limits().max_draw_buffers)
      throw Error(fmt::format("gl: {}: layers {}..{} of {} cannot be drawn at once (at most {})",
                              name_, first, first + count - 1, layers_,
                              context_.limits().max_draw_buffers));
    GLuint id = 0;
    gl.CreateFramebuffers(1, &id);
    fbo = GlObject(id, gl.DeleteFramebuffers);
    std::vector<GLenum> buffers(count);
    for (int i = 0; i < count; ++i) {
      gl.NamedFramebufferTextureLayer(id, GL_COLOR_ATTACHMENT0 + i, texture_.id(), 0, first + i);
      buffers[i] = GL_COLOR_ATTACHMENT0 + i;
    }
    gl.NamedFramebufferDrawBuffers(id, count, buffers.data());
    checkFramebufferComplete(context_, id, fmt::format("{} layers {}..{}", name_, first,
                                                       first + count - 1));
  }
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo.id());
  gl.Viewport(0, 0, width_, height_);
  bound_ = fbo.id();
  bound_count_ = count;
}

void LayeredTarget::clear(float rgb, float alpha) {
  const float v[4] = {rgb, rgb, rgb, alpha};
  for (int i = 0; i < bound_count_; ++i)
    context_.api().ClearNamedFramebufferfv(bound_, GL_COLOR, i, v);
}

void LayeredTarget::read(int layer, int x, int y, int w, int h, std::vector<float>& rgba) const {
  const std::size_t n = static_cast<std::size_t>(w) * h * 4;
  rgba.resize(n);
  context_.api().GetTextureSubImage(texture_.id(), 0, x, y, layer, w, h, 1, GL_RGBA, GL_FLOAT,
                                    static_cast<GLsizei>(n * sizeof(float)), rgba.data());
  context_.check(fmt::format("reading layer {} of {}", layer, name_));
}

}  // namespace svr::gl
