#include "renderers/gl/gl_splat_frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

#include "renderers/classification/derived_cache.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/kernels/splat_projection.h"
#include "renderers/kernels/splat_settings.h"
#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_framebuffer.h"
#include "renderers/gl/gl_objects.h"
#include "renderers/gl/gl_program.h"
#include "renderers/gl/gl_splat_shaders.h"
#include "renderers/gl/gl_state.h"
#include "renderers/gl/gl_voxel_list.h"
#include "base/error.h"

namespace svr {

namespace {

using gl::PassOutput;

void checkStorage(const gl::GlLimits& limits, std::size_t bytes, const std::string& what) {
  if (static_cast<long long>(bytes) > limits.max_storage_block)
    throw Error(fmt::format("gl: {} needs {:.1f} MiB of shader storage, beyond "
                            "GL_MAX_SHADER_STORAGE_BLOCK_SIZE ({:.1f} MiB)",
                            what, bytes / 1048576.0, limits.max_storage_block / 1048576.0));
}

double normalCdf(double t) { return 0.5 * std::erfc(-t / std::numbers::sqrt2); }

}  // namespace

// Uploads the voxel list, the tables and the shading nodes unless this classification is the
// one uploaded.
void gl::SplatUpload::ensure(const gl::GlContext& context, const ClassifiedVolume& cv) {
  if (list && uploaded_for.lock() == cv.derived) return;
  list.reset();
  voxels.reset(), tables.reset(), nodes.reset();
  const gl::GlLimits& limits = context.limits();
  const int nx = cv.dims[0] + 1, ny = cv.dims[1] + 1, nz = cv.dims[2] + 1;
  if (std::max({nx, ny, nz}) > limits.max_3d_texture_size)
    throw Error(fmt::format("gl: a {}×{}×{} volume is beyond GL_MAX_3D_TEXTURE_SIZE {} (its "
                            "shading field needs {}×{}×{} texels)",
                            cv.dims[0], cv.dims[1], cv.dims[2], limits.max_3d_texture_size, nx,
                            ny, nz));
  auto fresh = gl::GlVoxelList::of(cv);
  const std::size_t bytes = fresh->voxels.size() * sizeof(gl::GpuVoxel);
  checkStorage(limits, bytes,
               fmt::format("the voxel list ({} voxels that scatter or absorb, of {}×{}×{})",
                           fresh->voxels.size(), cv.dims[0], cv.dims[1], cv.dims[2]));
  checkStorage(limits, fresh->tables.size() * sizeof(float),
               fmt::format("the classification tables ({} entries × {} channels)", cv.entries,
                           cv.k));
  const gl::GlApi& gl = context.api();
  voxels = gl::makeBuffer(gl, bytes, fresh->voxels.data());
  tables = gl::makeBuffer(gl, fresh->tables.size() * sizeof(float), fresh->tables.data());
  GLuint id = 0;
  gl.CreateTextures(GL_TEXTURE_3D, 1, &id);
  nodes = gl::GlObject(id, gl.DeleteTextures);
  gl.TextureStorage3D(id, 1, GL_R32F, nx, ny, nz);
  gl.TextureSubImage3D(id, 0, 0, 0, 0, nx, ny, nz, GL_RED, GL_FLOAT,
                       fresh->splat_voxels->cellMeans().data());
  context.check("uploading the voxel list");
  list = std::move(fresh);
  uploaded_for = cv.derived;
}

// One frame: the projected splats in GPU buffers, then the passes and the read-back. Splat slot
// s holds the splat n − 1 − s of the front-to-back order (back to front in slot order).
class GlSplatFrame {
 public:
  GlSplatFrame(gl::GlState& state, const RenderRequest& req, const splat::SplatSettings& settings)
      : st_(state), ctx_(state.context), gl_(ctx_.api()), req_(req), cv_(req.volume),
        settings_(settings), W_(req.width), H_(req.height), k_(cv_.k), kt_(cv_.t_channels),
        scalar_(kt_ == 1), stride_(1 + kt_ + k_),
        max_targets_(std::min(ctx_.limits().max_draw_buffers, 8)) {}

  LightIndependentImage render(ProgressCounter& progress);

 private:
  void layOut(const splat::ProjectedVoxels& projected, const splat::Footprint& any);
  void uploadSplats();
  void prepare();
  void choosePrimitive();
  const gl::GlProgram& splatProgram(PassOutput output, int targets);
  const gl::GlProgram& compositeProgram(PassOutput output, int targets);
  void drawSlots(std::size_t first, std::size_t count) const;
  void compositeS(const std::function<const gl::GlProgram&(PassOutput, int)>& use,
                  const std::function<void()>& source);
  void compositeSheets(ProgressCounter& progress);
  void readBack(LightIndependentImage& image);
  void opticalDepth(LightIndependentImage& image);

  gl::GlState& st_;
  const gl::GlContext& ctx_;
  const gl::GlApi& gl_;
  const RenderRequest& req_;
  const ClassifiedVolume& cv_;
  const splat::SplatSettings settings_;
  const int W_, H_, k_, kt_;
  const bool scalar_;
  const int stride_, max_targets_;
  bool ortho_ = true;
  double depth_sigma_ = 0.0;  // the same for every splat of a view
  std::size_t n_ = 0;
  std::vector<std::uint32_t> order_;  // slot → voxel list index
  std::vector<float> geometry_;       // slot → x, y, depth, 0
  std::vector<float> footprints_;     // slot (or one) → a, b, c, norm, half_w, half_h, 0, 0
  std::vector<float> depth_front_to_back_;
  gl::GlObject order_buffer_, geometry_buffer_, footprint_buffer_, quantities_, quantity_texture_;
  bool points_ = false;
  int margin_ = 0, s_layers_ = 0;
  std::unique_ptr<gl::LayeredTarget> s_target_;
};

LightIndependentImage GlSplatFrame::render(ProgressCounter& progress) {
  st_.splat.ensure(ctx_, cv_);
  // Project, cull and sort on the CPU exactly as the CPU splat list does (the same positions,
  // footprints and depth order).
  const splat::Projector projector(req_.camera, W_, H_, cv_.spacing, settings_.kernel);
  const splat::Footprint any = projector.footprint(glm::dvec3(0.0));
  ortho_ = projector.orthographic();
  depth_sigma_ = any.depth_sigma;
  layOut(splat::projectVoxels(*st_.splat.list->splat_voxels, cv_, projector, W_, H_), any);
  LightIndependentImage image(W_, H_, k_, kt_);
  if (n_ == 0) {
    for (int c = 0; c < kt_; ++c) std::ranges::fill(image.planeFloat(k_ + c), 1.f);
    return image;
  }
  uploadSplats();
  prepare();
  choosePrimitive();
  s_layers_ = scalar_ ? (k_ + 2) / 3 : (k_ + 3) / 4;
  s_target_ = std::make_unique<gl::LayeredTarget>(ctx_, W_ + 2 * margin_, H_ + 2 * margin_,
                                                  s_layers_, "the S image");
  gl_.BindVertexArray(st_.vao.id());
  gl_.Enable(GL_PROGRAM_POINT_SIZE);
  gl_.Enable(GL_BLEND);
  gl_.BlendEquation(GL_FUNC_ADD);
  for (int base = 0; base < s_layers_; base += max_targets_) {
    s_target_->drawInto(base, std::min(max_targets_, s_layers_ - base));
    s_target_->clear(0.f, scalar_ ? 1.f : 0.f);  // scalar: alpha holds T
  }
  if (settings_.mode == splat::SplatSettings::Mode::kDirect) {
    compositeS([&](PassOutput o, int t) -> const gl::GlProgram& { return splatProgram(o, t); },
               [&] { drawSlots(0, n_); });
    progress.set(0.9);
  } else {
    compositeSheets(progress);
  }
  ctx_.check("compositing");
  readBack(image);
  if (!scalar_) opticalDepth(image);
  gl_.Disable(GL_BLEND);
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  return image;
}

void GlSplatFrame::layOut(const splat::ProjectedVoxels& projected,
                                    const splat::Footprint& any) {
  n_ = projected.ids.size();
  order_.resize(n_);
  geometry_.assign(4 * n_, 0.f);
  footprints_.assign(ortho_ ? 8 : 8 * n_, 0.f);
  depth_front_to_back_ = projected.depth;
  const auto putFootprint = [&](std::size_t slot, const splat::Footprint& fp) {
    float* f = &footprints_[8 * slot];
    f[0] = fp.a, f[1] = fp.b, f[2] = fp.c, f[3] = fp.norm, f[4] = fp.half_w, f[5] = fp.half_h;
  };
  for (std::size_t i = 0; i < n_; ++i) {
    const std::size_t slot = n_ - 1 - i;
    order_[slot] = projected.ids[i];
    geometry_[4 * slot] = projected.position[i].x;
    geometry_[4 * slot + 1] = projected.position[i].y;
    geometry_[4 * slot + 2] = projected.depth[i];
    if (!ortho_) putFootprint(slot, projected.footprint(i));
  }
  if (ortho_) putFootprint(0, any);
}

void GlSplatFrame::uploadSplats() {
  const gl::GlLimits& limits = ctx_.limits();
  if (static_cast<long long>(n_) * stride_ > limits.max_texture_buffer)
    throw Error(fmt::format("gl: {} splats × {} quantities are beyond GL_MAX_TEXTURE_BUFFER_SIZE "
                            "({} texels)",
                            n_, stride_, limits.max_texture_buffer));
  checkStorage(limits, geometry_.size() * sizeof(float), fmt::format("{} splat positions", n_));
  checkStorage(limits, footprints_.size() * sizeof(float), fmt::format("{} footprints", n_));
  order_buffer_ = gl::makeBuffer(gl_, n_ * sizeof(std::uint32_t), order_.data());
  geometry_buffer_ = gl::makeBuffer(gl_, geometry_.size() * sizeof(float), geometry_.data());
  footprint_buffer_ =
      gl::makeBuffer(gl_, footprints_.size() * sizeof(float), footprints_.data());
  quantities_ = gl::makeBuffer(gl_, n_ * stride_ * sizeof(float), nullptr);
  GLuint id = 0;
  gl_.CreateTextures(GL_TEXTURE_BUFFER, 1, &id);
  quantity_texture_ = gl::GlObject(id, gl_.DeleteTextures);
  gl_.TextureBuffer(id, GL_R32F, quantities_.id());
  ctx_.check("uploading the sorted splats");
}

// Shades and classifies every splat once (a sheet draws each about 2·radius/sheet times).
void GlSplatFrame::prepare() {
  const gl::GlProgram& p = st_.program(fmt::format("prepare k={} kt={}", k_, kt_), [&] {
    return std::vector<gl::ShaderStage>{{GL_COMPUTE_SHADER, gl::prepareShader(k_, kt_)}};
  });
  const Dims& d = cv_.dims;
  const glm::dvec3 forward = RayGenerator(req_.camera, W_, H_).forward();
  p.set("u_count", static_cast<int>(n_));
  p.set("u_nodes", 1);
  p.set("u_dims", d[0], d[1], d[2]);
  p.set("u_inv_spacing", float(1.0 / cv_.spacing.x), float(1.0 / cv_.spacing.y),
        float(1.0 / cv_.spacing.z));
  p.set("u_entries", cv_.entries);
  p.set("u_orthographic", ortho_ ? 1 : 0);
  p.set("u_headlight", req_.light_direction ? 0 : 1);
  p.set("u_forward", float(forward.x), float(forward.y), float(forward.z));
  p.set("u_eye", float(req_.camera.eye.x), float(req_.camera.eye.y), float(req_.camera.eye.z));
  const glm::dvec3 light = req_.light_direction.value_or(glm::dvec3(0.0));
  p.set("u_light", float(light.x), float(light.y), float(light.z));
  p.set("u_ambient", float(req_.shading.ambient));
  p.set("u_diffuse", float(req_.shading.diffuse));
  // As the CPU splat list: no highlight at all when nothing is specular.
  const bool any_specular = req_.shading.specular > 0.0 &&
                            std::ranges::any_of(cv_.specular, [](float s) { return s > 0.f; });
  p.set("u_specular", any_specular ? float(req_.shading.specular) : 0.f);
  p.set("u_shininess", float(req_.shading.shininess));
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, st_.splat.voxels.id());
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, st_.splat.tables.id());
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, order_buffer_.id());
  gl_.BindImageTexture(0, quantity_texture_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, geometry_buffer_.id());
  gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, footprint_buffer_.id());
  gl_.BindTextureUnit(1, st_.splat.nodes.id());
  gl_.UseProgram(p.id());
  const std::size_t groups = (n_ + 63) / 64;
  const std::size_t gx = std::min<std::size_t>(groups, ctx_.limits().max_compute_groups_x);
  gl_.DispatchCompute(static_cast<GLuint>(gx), static_cast<GLuint>((groups + gx - 1) / gx), 1);
  gl_.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  gl_.BindTextureUnit(2, quantity_texture_.id());
  ctx_.check("shading the splats");
}

// Point sprites cost llvmpipe one primitive per splat instead of two triangles (measured: the
// engine's direct pass 2.5 s → 1.9 s, sheets 29 s → 14 s); quads where a footprint is wider
// than the largest point.
void GlSplatFrame::choosePrimitive() {
  float widest = 0.f;
  for (std::size_t f = 0; f < footprints_.size(); f += 8)
    widest = std::max({widest, footprints_[f + 4], footprints_[f + 5]});
  points_ = 2.f * widest + 1.f <= ctx_.limits().max_point_size;
  margin_ = points_ ? static_cast<int>(std::ceil(widest)) + 2 : 0;
}

const gl::GlProgram& GlSplatFrame::splatProgram(PassOutput output, int targets) {
  const gl::GlProgram& p = st_.program(
      fmt::format("splat k={} kt={} output={} targets={} points={}", k_, kt_, int(output),
                  targets, points_),
      [&] {
        return std::vector<gl::ShaderStage>{
            {GL_VERTEX_SHADER, gl::splatVertexShader(k_, kt_, output, targets, points_)},
            {GL_FRAGMENT_SHADER, gl::splatFragmentShader(k_, kt_, output, targets)}};
      });
  const double cutoff = settings_.kernel.cutoff();
  p.set("u_quantities", 2);
  p.set("u_frame", float(W_ + 2 * margin_), float(H_ + 2 * margin_));
  p.set("u_margin", float(margin_));
  p.set("u_per_splat_footprint", ortho_ ? 0 : 1);
  p.set("u_cut2", float(cutoff * cutoff));
  p.set("u_cut", float(std::min(cutoff, splat::kSheetDepthCut)));  // sheets' depth cut
  p.set("u_depth_sigma", float(depth_sigma_));
  p.set("u_phi_lo", float(normalCdf(-cutoff)));
  p.set("u_phi_span", float(normalCdf(cutoff) - normalCdf(-cutoff)));
  p.set("u_sheet", 0);
  gl_.UseProgram(p.id());
  return p;
}

const gl::GlProgram& GlSplatFrame::compositeProgram(PassOutput output, int targets) {
  const gl::GlProgram& p = st_.program(
      fmt::format("composite k={} kt={} output={} targets={}", k_, kt_, int(output), targets),
      [&] {
        return std::vector<gl::ShaderStage>{
            {GL_VERTEX_SHADER, gl::fullscreenVertexShader()},
            {GL_FRAGMENT_SHADER, gl::compositeFragmentShader(k_, kt_, output, targets)}};
      });
  p.set("u_sheet_buffer", 0);
  gl_.UseProgram(p.id());
  return p;
}

void GlSplatFrame::drawSlots(std::size_t first, std::size_t count) const {
  if (points_)
    gl_.DrawArrays(GL_POINTS, static_cast<GLint>(first), static_cast<GLsizei>(count));
  else
    gl_.DrawArrays(GL_TRIANGLES, static_cast<GLint>(6 * first), static_cast<GLsizei>(6 * count));
}

// S: chromatic, one dual-source pass per 4 channels; scalar, up to 8 targets of 3 channels
// (+ T in alpha) per pass. `source` draws what is composited: splats or a sheet buffer.
void GlSplatFrame::compositeS(
    const std::function<const gl::GlProgram&(PassOutput, int)>& use,
    const std::function<void()>& source) {
  if (scalar_) {
    gl_.BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA);
    for (int base = 0; base < s_layers_; base += max_targets_) {
      const int count = std::min(max_targets_, s_layers_ - base);
      s_target_->drawInto(base, count);
      use(PassOutput::kScalar, count).set("u_first", 3 * base);
      source();
    }
  } else {
    gl_.BlendFunc(GL_ONE, GL_SRC1_COLOR);
    for (int g = 0; g < s_layers_; ++g) {
      s_target_->drawInto(g, 1);
      use(PassOutput::kDual, 1).set("u_first", 4 * g);
      source();
    }
  }
}

void GlSplatFrame::compositeSheets(ProgressCounter& progress) {
  const double min_spacing = std::min({cv_.spacing.x, cv_.spacing.y, cv_.spacing.z});
  const double thickness = settings_.sheet_voxels * min_spacing;
  const double full_reach = settings_.kernel.cutoff() * depth_sigma_;
  const double reach = std::min(settings_.kernel.cutoff(), splat::kSheetDepthCut) * depth_sigma_;
  const auto& depth = depth_front_to_back_;
  // The CPU's sheet lattice: the first sheet starts where the front splat's kernel does.
  const double first = depth.front() - full_reach;
  const long sheets = static_cast<long>(std::floor((depth.back() + reach - first) / thickness)) + 1;
  const int acc_layers = (stride_ + 3) / 4;
  gl::LayeredTarget sheet(ctx_, W_ + 2 * margin_, H_ + 2 * margin_, acc_layers, "the sheet buffer");
  gl_.BindTextureUnit(0, sheet.texture());
  gl_.Enable(GL_SCISSOR_TEST);
  for (long j = sheets - 1; j >= 0; --j) {
    const double z0 = first + j * thickness, z1 = first + (j + 1) * thickness;
    // Splats whose kernel reaches into [z0, z1]: a run of the depth order.
    const std::size_t ia =
        std::upper_bound(depth.begin(), depth.end(), z0 - reach) - depth.begin();
    const std::size_t ib =
        std::lower_bound(depth.begin(), depth.end(), z1 + reach) - depth.begin();
    if (ia >= ib) continue;
    // The sheet's pixels: clearing and compositing touch nothing else.
    float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
    for (std::size_t i = ia; i < ib; ++i) {
      const std::size_t slot = n_ - 1 - i;
      const float* g = &geometry_[4 * slot];
      const float* f = &footprints_[ortho_ ? 0 : 8 * slot];
      x0 = std::min(x0, g[0] - f[4]), x1 = std::max(x1, g[0] + f[4]);
      y0 = std::min(y0, g[1] - f[5]), y1 = std::max(y1, g[1] + f[5]);
    }
    const int px0 = std::max(0, static_cast<int>(std::floor(x0)));
    const int px1 = std::min(W_, static_cast<int>(std::ceil(x1)));
    const int py0 = std::max(0, static_cast<int>(std::floor(y0)));
    const int py1 = std::min(H_, static_cast<int>(std::ceil(y1)));
    if (px0 >= px1 || py0 >= py1) continue;
    gl_.Scissor(margin_ + px0, margin_ + py0, px1 - px0, py1 - py0);
    gl_.BlendFunc(GL_ONE, GL_ONE);
    for (int base = 0; base < acc_layers; base += max_targets_) {
      const int count = std::min(max_targets_, acc_layers - base);
      sheet.drawInto(base, count);
      sheet.clear(0.f, 0.f);
      const gl::GlProgram& p = splatProgram(PassOutput::kAccumulate, count);
      p.set("u_first", 4 * base);
      p.set("u_end", stride_);
      p.set("u_sheet", 1);
      p.set("u_z0", float(z0));
      p.set("u_z1", float(z1));
      drawSlots(n_ - ib, ib - ia);
    }
    compositeS([&](PassOutput o, int t) -> const gl::GlProgram& { return compositeProgram(o, t); },
               [&] { gl_.DrawArrays(GL_TRIANGLES, 0, 3); });
    progress.set(0.9 * (sheets - j) / sheets);
  }
  gl_.Disable(GL_SCISSOR_TEST);
}

// Window row y is image row y (the vertex shader maps image y to window y), so the layers come
// back in image order.
void GlSplatFrame::readBack(LightIndependentImage& image) {
  std::vector<float> rgba;
  const std::size_t pixels = image.pixels();
  const int per_layer = scalar_ ? 3 : 4;
  for (int layer = 0; layer < s_layers_; ++layer) {
    s_target_->read(layer, margin_, margin_, W_, H_, rgba);
    for (int j = 0; j < per_layer && per_layer * layer + j < k_; ++j) {
      float* plane = image.planeFloat(per_layer * layer + j).data();
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = rgba[4 * p + j];
    }
    if (scalar_ && layer == 0) {
      float* plane = image.planeFloat(k_).data();
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = rgba[4 * p + 3];
    }
  }
}

// T = exp(−Σ τ_t): the optical depth of every splat along the ray, additively.
void GlSplatFrame::opticalDepth(LightIndependentImage& image) {
  const int t_layers = (kt_ + 3) / 4;
  gl::LayeredTarget optical_depth(ctx_, W_ + 2 * margin_, H_ + 2 * margin_, t_layers,
                                  "the optical depth image");
  gl_.BlendFunc(GL_ONE, GL_ONE);
  for (int base = 0; base < t_layers; base += max_targets_) {
    const int count = std::min(max_targets_, t_layers - base);
    optical_depth.drawInto(base, count);
    optical_depth.clear(0.f, 0.f);
    const gl::GlProgram& p = splatProgram(PassOutput::kAccumulate, count);
    p.set("u_first", 1 + 4 * base);
    p.set("u_end", 1 + kt_);
    drawSlots(0, n_);
  }
  ctx_.check("the optical depth pass");
  std::vector<float> rgba;
  const std::size_t pixels = image.pixels();
  for (int layer = 0; layer < t_layers; ++layer) {
    optical_depth.read(layer, margin_, margin_, W_, H_, rgba);
    for (int j = 0; j < 4 && 4 * layer + j < kt_; ++j) {
      float* plane = image.planeFloat(k_ + 4 * layer + j).data();
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = std::exp(-rgba[4 * p + j]);
    }
  }
}

std::uint64_t gl::splatWorkingBytes(const RenderRequest& req) {
  const int k = req.volume.k, kt = req.volume.t_channels;
  const std::uint64_t layers = (k + 3) / 4 + (1 + kt + k + 3) / 4 + (kt + 3) / 4 + 1;
  return layers * std::uint64_t(req.width) * std::uint64_t(req.height) * 4 * sizeof(float);
}

LightIndependentImage gl::renderSplats(gl::GlState& state, const RenderRequest& request,
                                   const splat::SplatSettings& settings,
                                   ProgressCounter& progress) {
  GlSplatFrame frame(state, request, settings);
  return frame.render(progress);
}

}  // namespace svr
