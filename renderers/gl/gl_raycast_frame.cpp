#include "renderers/gl/gl_raycast_frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderers/classification/classified_sample.h"
#include "renderers/kernels/occupancy_pyramid.h"
#include "renderers/gl/gl_raycast_shaders.h"
#include "renderers/gl/gl_state.h"
#include "base/error.h"

namespace svr::gl {
namespace {

int sLayers(int k) { return (k + 3) / 4; }
int rowTexels(int k, int kt) { return 1 + sLayers(k) + (kt + 3) / 4; }

GlObject makeTexture(const GlApi& gl, GLenum target) {
  GLuint id = 0;
  gl.CreateTextures(target, 1, &id);
  return {id, gl.DeleteTextures};
}

// Texel fetches only (integer formats must not filter).
void nearest(const GlApi& gl, const GlObject& texture) {
  gl.TextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

// The sample table (raycast/sample_table.h) in vec4s: per entry (α, α·s, 0, 0), α·ρ, t, zero
// padded; row `entries` holds the white in texels 1 … ⌈k/4⌉.
std::vector<float> tableTexels(const ClassifiedVolume& cv) {
  const int k = cv.k, kt = cv.t_channels, row = 4 * rowTexels(k, kt);
  std::vector<float> t(static_cast<std::size_t>(cv.entries + 1) * row, 0.f);
  for (int e = 0; e < cv.entries; ++e) {
    float* r = &t[static_cast<std::size_t>(e) * row];
    const float a = cv.alpha[e];
    r[0] = a;
    r[1] = a * cv.specular[e];
    for (int c = 0; c < k; ++c) r[4 + c] = a * cv.reflectance[static_cast<std::size_t>(e) * k + c];
    for (int c = 0; c < kt; ++c)
      r[4 + 4 * sLayers(k) + c] = cv.transmission[static_cast<std::size_t>(e) * kt + c];
  }
  float* white = &t[static_cast<std::size_t>(cv.entries) * row];
  for (int c = 0; c < k; ++c) white[4 + c] = cv.white[c];
  return t;
}

// Per level-0 block of the occupancy pyramid, the log2 edge of the largest empty block holding
// it, 0 when occupied: what the CPU ray finds by walking the levels, in one fetch.
std::vector<std::uint8_t> emptyShifts(const OccupancyPyramid& occ, const Dims& blocks) {
  const int shift = occ.shift(0);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(blocks[0]) * blocks[1] * blocks[2]);
  std::size_t i = 0;
  for (int z = 0; z < blocks[2]; ++z)
    for (int y = 0; y < blocks[1]; ++y)
      for (int x = 0; x < blocks[0]; ++x, ++i) {
        const int level = occ.emptyLevel(x << shift, y << shift, z << shift);
        out[i] = level < 0 ? 0 : static_cast<std::uint8_t>(occ.shift(level));
      }
  return out;
}

Dims blocksOf(const Dims& d, int shift) {
  const int size = 1 << shift;
  return {(d[0] + size - 1) / size, (d[1] + size - 1) / size, (d[2] + size - 1) / size};
}

}  // namespace

void RaycastUpload::ensure(const GlContext& context, const ClassifiedVolume& cv,
                           const GradientVolume* gradients) {
  if (field && uploaded_for.lock() == cv.derived && precomputed == (gradients != nullptr))
    return;
  field.reset(), labels.reset(), table.reset(), empty.reset();
  const GlApi& gl = context.api();
  const GlLimits& limits = context.limits();
  const Dims& d = cv.dims;
  if (std::max({d[0], d[1], d[2]}) > limits.max_3d_texture_size)
    throw Error(fmt::format("gl: a {}×{}×{} volume is beyond GL_MAX_3D_TEXTURE_SIZE {}", d[0],
                            d[1], d[2], limits.max_3d_texture_size));
  if (cv.entries + 1 > limits.max_texture_size)
    throw Error(fmt::format("gl: {} classification entries are beyond GL_MAX_TEXTURE_SIZE {}",
                            cv.entries, limits.max_texture_size));
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  field = makeTexture(gl, GL_TEXTURE_3D);
  if (gradients) {
    gl.TextureStorage3D(field.id(), 1, GL_RGBA16_SNORM, d[0], d[1], d[2]);
    gl.TextureSubImage3D(field.id(), 0, 0, 0, 0, d[0], d[1], d[2], GL_RGBA, GL_SHORT,
                         gradients->q.get());
    // SNORM16 reads q / 32767: fold that into the decoding.
    for (int j = 0; j < 4; ++j) {
      decode_scale[j] = gradients->scale[j] * 32767.f;
      decode_offset[j] = gradients->offset[j];
    }
  } else {
    gl.TextureStorage3D(field.id(), 1, GL_R32F, d[0], d[1], d[2]);
    gl.TextureSubImage3D(field.id(), 0, 0, 0, 0, d[0], d[1], d[2], GL_RED, GL_FLOAT,
                         cv.shadingField().data());
  }
  gl.TextureParameteri(field.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl.TextureParameteri(field.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    gl.TextureParameteri(field.id(), wrap, GL_CLAMP_TO_EDGE);
  if (cv.labels) {
    labels = makeTexture(gl, GL_TEXTURE_3D);
    gl.TextureStorage3D(labels.id(), 1, GL_R16UI, d[0], d[1], d[2]);
    gl.TextureSubImage3D(labels.id(), 0, 0, 0, 0, d[0], d[1], d[2], GL_RED_INTEGER,
                         GL_UNSIGNED_SHORT, cv.label.data());
    nearest(gl, labels);
  }
  const std::vector<float> rows = tableTexels(cv);
  table = makeTexture(gl, GL_TEXTURE_2D);
  const int row = rowTexels(cv.k, cv.t_channels);
  gl.TextureStorage2D(table.id(), 1, GL_RGBA32F, row, cv.entries + 1);
  gl.TextureSubImage2D(table.id(), 0, 0, 0, row, cv.entries + 1, GL_RGBA, GL_FLOAT, rows.data());
  nearest(gl, table);
  const auto occupancy = occupancyOf(cv);
  const Dims blocks = blocksOf(d, occupancy->shift(0));
  const std::vector<std::uint8_t> shifts = emptyShifts(*occupancy, blocks);
  empty = makeTexture(gl, GL_TEXTURE_3D);
  gl.TextureStorage3D(empty.id(), 1, GL_R8UI, blocks[0], blocks[1], blocks[2]);
  gl.TextureSubImage3D(empty.id(), 0, 0, 0, 0, blocks[0], blocks[1], blocks[2], GL_RED_INTEGER,
                       GL_UNSIGNED_BYTE, shifts.data());
  nearest(gl, empty);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  context.check(fmt::format("uploading a {}×{}×{} volume for ray casting", d[0], d[1], d[2]));
  precomputed = gradients != nullptr;
  uploaded_for = cv.derived;
}

namespace {

void setUniforms(const GlProgram& p, const RenderRequest& req, const RaycastUpload& up,
                 int block_shift) {
  const ClassifiedVolume& cv = req.volume;
  const RayGenerator rays(req.camera, req.width, req.height);
  const glm::dvec3 right = rays.right() * rays.halfWidth(), up_v = rays.up() * rays.halfHeight();
  const glm::dvec3 inv_spacing = 1.0 / cv.spacing;
  const glm::dvec3 centre = 0.5 * glm::dvec3(cv.dims[0] - 1, cv.dims[1] - 1, cv.dims[2] - 1);
  const auto set3 = [&](const char* name, const glm::dvec3& v) {
    p.set(name, float(v.x), float(v.y), float(v.z));
  };
  p.set("u_field", 0);
  p.set("u_labels", 1);
  p.set("u_table", 2);
  p.set("u_empty", 3);
  p.set("u_decode_scale", up.decode_scale);
  p.set("u_decode_offset", up.decode_offset);
  p.set("u_entries", cv.entries);
  p.set("u_block_shift", block_shift);
  p.set("u_skip", req.empty_space_skipping ? 1 : 0);
  set3("u_hi", glm::dvec3(cv.dims[0] - 1, cv.dims[1] - 1, cv.dims[2] - 1));
  set3("u_inv_dims", 1.0 / glm::dvec3(cv.dims[0], cv.dims[1], cv.dims[2]));
  p.set("u_bin_lo", float(cv.value_lo));
  p.set("u_bin_scale", float(cv.value_scale));
  p.set("u_bin_last", float(cv.entries - 1));
  p.set("u_last_lower", std::max(cv.entries - 2, 0));
  set3("u_half_inv_spacing", 0.5 * inv_spacing);
  set3("u_eye", req.camera.eye);
  set3("u_forward", rays.forward());
  set3("u_right", right);
  set3("u_up", up_v);
  set3("u_inv_spacing", inv_spacing);
  set3("u_centre", centre);
  p.set("u_orthographic", req.camera.orthographic() ? 1 : 0);
  p.set("u_image", float(req.width), float(req.height));
  p.set("u_step", float(cv.step_world));
  p.set("u_termination", float(req.termination));
  p.set("u_headlight", req.light_direction ? 0 : 1);
  set3("u_light", req.light_direction.value_or(glm::dvec3(0.0)));
  const PhongSetup phong(req.shading, glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 0.0, 1.0));
  p.set("u_ambient", phong.ambient);
  p.set("u_diffuse", phong.diffuse);
  p.set("u_specular", phong.specular);
  p.set("u_shininess", phong.shininess);
  p.set("u_highlight_floor", phong.highlight_floor);
}

}  // namespace

LightIndependentImage renderRaycast(GlState& st, const RenderRequest& req,
                                    const GradientVolume* gradients, ProgressCounter& progress) {
  const GlContext& ctx = st.context;
  const GlApi& gl = ctx.api();
  const ClassifiedVolume& cv = req.volume;
  const int k = cv.k, kt = cv.t_channels, W = req.width, H = req.height;
  RaycastUpload& up = st.raycast;
  up.ensure(ctx, cv, gradients);
  const int s_layers = sLayers(k), layers = s_layers + (kt + 3) / 4;
  if (!up.target || up.target->width() != W || up.target->height() != H ||
      up.target->layers() != layers)
    up.target = std::make_unique<LayeredTarget>(ctx, W, H, layers, "the ray-cast S and T image");
  const int block_shift = occupancyOf(cv)->shift(0);
  gl.BindVertexArray(st.vao.id());
  gl.Disable(GL_BLEND);
  gl.Viewport(0, 0, W, H);
  gl.BindTextureUnit(0, up.field.id());
  gl.BindTextureUnit(1, up.labels.id());  // 0 unbinds: scalar volumes sample no labels
  gl.BindTextureUnit(2, up.table.id());
  gl.BindTextureUnit(3, up.empty.id());
  const int per_pass = std::min(ctx.limits().max_draw_buffers, 8);
  const int passes = (layers + per_pass - 1) / per_pass;
  progress.stage(passes);
  for (int first = 0; first < layers; first += per_pass) {
    const RaycastShaderKey key{k, kt, cv.labels, gradients != nullptr, first,
                               std::min(per_pass, layers - first)};
    const GlProgram& p = st.program(
        fmt::format("raycast k={} kt={} labels={} precomputed={} layers={}+{}", k, kt,
                    key.labels, key.precomputed_gradients, key.first_layer, key.layers),
        [&] {
          return std::vector<ShaderStage>{{GL_VERTEX_SHADER, fullscreenVertexShader()},
                                          {GL_FRAGMENT_SHADER, raycastFragmentShader(key)}};
        });
    setUniforms(p, req, up, block_shift);
    gl.UseProgram(p.id());
    up.target->drawInto(first, key.layers);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    ctx.check("ray casting");
    progress.advance();
  }
  LightIndependentImage image(W, H, k, kt);
  std::vector<float> rgba;
  const std::size_t pixels = image.pixels();
  for (int layer = 0; layer < layers; ++layer) {
    up.target->read(layer, 0, 0, W, H, rgba);
    const int channel0 = layer < s_layers ? 4 * layer : k + 4 * (layer - s_layers);
    const int end = layer < s_layers ? k : k + kt;
    for (int j = 0; j < 4 && channel0 + j < end; ++j) {
      float* plane = image.planeFloat(channel0 + j).data();
      for (std::size_t px = 0; px < pixels; ++px) plane[px] = rgba[4 * px + j];
    }
  }
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  return image;
}

std::uint64_t raycastWorkingBytes(const RenderRequest& req) {
  const int layers = sLayers(req.volume.k) + (req.volume.t_channels + 3) / 4;
  return (std::uint64_t(layers) + 1) * req.width * req.height * 4 * sizeof(float);
}

std::uint64_t raycastDeviceBytes(const ClassifiedVolume& cv, bool precomputed_gradients) {
  const std::uint64_t voxels = std::uint64_t(cv.dims[0]) * cv.dims[1] * cv.dims[2];
  return voxels * ((precomputed_gradients ? 8 : 4) + (cv.labels ? 2 : 0)) + voxels / 64 +
         std::uint64_t(cv.entries + 1) * rowTexels(cv.k, cv.t_channels) * 16;
}

}  // namespace svr::gl
