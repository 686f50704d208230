#include "renderers/gl/gl_relighter.h"

#include <fmt/format.h>

#include <vector>

#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_framebuffer.h"
#include "renderers/gl/gl_objects.h"
#include "base/error.h"
#include "renderers/gl/gl_program.h"
#include "renderers/gl/gl_shader_sources.h"

namespace svr {

struct GlRelighter::Impl {
  gl::GlContext context;  // first: destroyed last
  gl::GlObject vao, planes, target, framebuffer, first_bad;
  std::unique_ptr<gl::GlProgram> program;
  int width = 0, height = 0, plane_count = 0;

  ~Impl() {
    try {
      const gl::GlContext::Current current(context);
      program.reset();
      vao.reset(), planes.reset(), target.reset(), framebuffer.reset(), first_bad.reset();
    } catch (const Error&) {
      // Not current: destroying the context frees its objects all the same.
    }
  }
};

GlRelighter::GlRelighter() : impl_(std::make_unique<Impl>()) {
  const gl::GlContext::Current current(impl_->context);
  impl_->vao = gl::makeVertexArray(impl_->context.api());
  const std::uint32_t none = 0xffffffffu;
  impl_->first_bad = gl::makeBuffer(impl_->context.api(), sizeof(none), &none,
                                    GL_DYNAMIC_STORAGE_BIT);
}

GlRelighter::~GlRelighter() = default;

void GlRelighter::setImage(const LightIndependentImage& image) {
  Impl& m = *impl_;
  const gl::GlContext::Current current(m.context);
  const gl::GlContext& ctx = m.context;
  const gl::GlApi& gl = ctx.api();
  const gl::GlLimits& limits = ctx.limits();
  const int w = image.width(), h = image.height(), planes = image.planes();
  const int layers = (planes + 3) / 4;
  if (w > limits.max_texture_size || h > limits.max_texture_size)
    throw Error(fmt::format("gl relight: a {}×{} image is beyond GL_MAX_TEXTURE_SIZE {}", w, h,
                            limits.max_texture_size));
  if (layers > limits.max_array_layers || 3 * planes > limits.max_fragment_uniforms - 64)
    throw Error(fmt::format("gl relight: {} planes are beyond the context's limits ({} layers, "
                            "{} fragment uniforms)",
                            planes, limits.max_array_layers, limits.max_fragment_uniforms));
  const bool half = image.storage() == SampleStorage::kHalf;
  m.planes.reset();
  GLuint id = 0;
  gl.CreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
  m.planes = gl::GlObject(id, gl.DeleteTextures);
  gl.TextureStorage3D(id, 1, half ? GL_RGBA16F : GL_RGBA32F, w, h, layers);
  // Interleave 4 planes per layer (a missing fourth plane reads 0 and has no matrix column).
  const std::size_t pixels = image.pixels();
  for (int layer = 0; layer < layers; ++layer) {
    if (half) {
      std::vector<std::uint16_t> texels(4 * pixels, 0);
      for (int j = 0; j < 4 && 4 * layer + j < planes; ++j) {
        const auto plane = image.planeHalf(4 * layer + j);
        for (std::size_t p = 0; p < pixels; ++p) texels[4 * p + j] = plane[p];
      }
      gl.TextureSubImage3D(id, 0, 0, 0, layer, w, h, 1, GL_RGBA, GL_HALF_FLOAT, texels.data());
    } else {
      std::vector<float> texels(4 * pixels, 0.f);
      for (int j = 0; j < 4 && 4 * layer + j < planes; ++j) {
        const auto plane = image.planeFloat(4 * layer + j);
        for (std::size_t p = 0; p < pixels; ++p) texels[4 * p + j] = plane[p];
      }
      gl.TextureSubImage3D(id, 0, 0, 0, layer, w, h, 1, GL_RGBA, GL_FLOAT, texels.data());
    }
  }
  if (w != m.width || h != m.height || !m.target) {
    m.framebuffer.reset();
    m.target.reset();
    gl.CreateTextures(GL_TEXTURE_2D, 1, &id);
    m.target = gl::GlObject(id, gl.DeleteTextures);
    gl.TextureStorage2D(id, 1, GL_RGBA8, w, h);
    gl.CreateFramebuffers(1, &id);
    m.framebuffer = gl::GlObject(id, gl.DeleteFramebuffers);
    gl.NamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, m.target.id(), 0);
    gl::checkFramebufferComplete(ctx, id, "the relit image");
  }
  if (planes != m.plane_count || !m.program)
    m.program = std::make_unique<gl::GlProgram>(
        ctx, fmt::format("relight {} planes", planes),
        std::vector<gl::ShaderStage>{
            {GL_VERTEX_SHADER, gl::glsl("relight_vertex.glsl")},
            // Planes packed 4 per layer; window row y is image row y, so the pixels read back
            // in order.
            {GL_FRAGMENT_SHADER, fmt::format("#version 450 core\n#define P {}\n", planes) +
                                     gl::glsl("relight_fragment.glsl")}});
  m.width = w, m.height = h, m.plane_count = planes;
  ctx.check("uploading the light-independent image");
}

void GlRelighter::relightSrgb8(const Eigen::MatrixXd& folded, std::span<std::uint8_t> rgb) const {
  const Impl& m = *impl_;
  if (!m.program) throw Error("gl relight: no image; call setImage first");
  if (folded.rows() != 3 || folded.cols() != m.plane_count)
    throw Error(fmt::format("gl relight: the matrix is {}×{}, the image has {} planes",
                            folded.rows(), folded.cols(), m.plane_count));
  const std::size_t pixels = static_cast<std::size_t>(m.width) * m.height;
  if (rgb.size() != 3 * pixels)
    throw Error(fmt::format("gl relight: output holds {} bytes, need {}", rgb.size(), 3 * pixels));
  const gl::GlContext::Current current(m.context);
  const gl::GlApi& gl = m.context.api();
  std::vector<float> matrix(3 * m.plane_count);
  for (int r = 0; r < 3; ++r)
    for (int p = 0; p < m.plane_count; ++p)
      matrix[r * m.plane_count + p] = static_cast<float>(folded(r, p));
  m.program->set("u_matrix", matrix);
  m.program->set("u_planes", 0);
  m.program->set("u_width", m.width);
  const std::uint32_t none = 0xffffffffu;
  gl.NamedBufferSubData(m.first_bad.id(), 0, sizeof(none), &none);
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.first_bad.id());
  gl.BindTextureUnit(0, m.planes.id());
  gl.BindFramebuffer(GL_FRAMEBUFFER, m.framebuffer.id());
  gl.Viewport(0, 0, m.width, m.height);
  gl.BindVertexArray(m.vao.id());
  gl.UseProgram(m.program->id());
  gl.DrawArrays(GL_TRIANGLES, 0, 3);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.ReadPixels(0, 0, m.width, m.height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  std::uint32_t bad = none;
  gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  gl.GetNamedBufferSubData(m.first_bad.id(), 0, sizeof(bad), &bad);
  m.context.check("relighting");
  if (bad != none)
    throw Error(fmt::format("gl relight: non-finite result at pixel ({}, {})", bad % m.width,
                            bad / m.width));
}

}  // namespace svr
