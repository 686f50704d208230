#include "renderers/gl/gl_splat_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <glm/vec2.hpp>
#include <map>
#include <numbers>

#include "renderers/gl/gl_context.h"
#include "renderers/gl/gl_framebuffer.h"
#include "renderers/gl/gl_objects.h"
#include "renderers/gl/gl_program.h"
#include "renderers/gl/gl_splat_shaders.h"
#include "renderers/gl/gl_voxel_list.h"
#include "renderers/splat/footprint.h"
#include "renderers/splat/splat_renderer.h"
#include "renderers/core/derived_cache.h"
#include "spectral/error.h"
#include "spectral/json_reader.h"

namespace svr {

namespace {

using gl::PassOutput;

void checkStorage(const gl::GlLimits& limits, std::size_t bytes, const std::string& what) {
  if (static_cast<long long>(bytes) > limits.max_storage_block)
    throw Error(fmt::format("gl: {} needs {:.1f} MiB of shader storage, beyond "
                            "GL_MAX_SHADER_STORAGE_BLOCK_SIZE ({:.1f} MiB)",
                            what, bytes / 1048576.0, limits.max_storage_block / 1048576.0));
}

// Stable LSD radix sort of `ids` by key[id] ascending: equal depths keep their voxel order, the
// CPU splat list's tie-break, so both backends composite in the same order.
void sortByDepth(std::vector<std::uint32_t>& ids, const std::vector<float>& key) {
  const std::size_t n = ids.size();
  std::vector<std::uint32_t> bits(n), other_ids(n), other_bits(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float k = key[ids[i]] == 0.f ? 0.f : key[ids[i]];  // −0 sorts with +0
    const std::uint32_t u = std::bit_cast<std::uint32_t>(k);
    bits[i] = (u & 0x80000000u) ? ~u : (u | 0x80000000u);  // order-preserving for floats
  }
  for (int shift = 0; shift < 32; shift += 11) {
    std::vector<std::size_t> count(2049, 0);
    for (std::size_t i = 0; i < n; ++i) ++count[((bits[i] >> shift) & 2047u) + 1];
    for (int b = 0; b < 2048; ++b) count[b + 1] += count[b];
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t to = count[(bits[i] >> shift) & 2047u]++;
      other_ids[to] = ids[i];
      other_bits[to] = bits[i];
    }
    ids.swap(other_ids);
    bits.swap(other_bits);
  }
}

double normalCdf(double t) { return 0.5 * std::erfc(-t / std::numbers::sqrt2); }

}  // namespace

struct GlSplatRenderer::State {
  gl::GlContext context;  // first: destroyed last, after every object below
  gl::GlObject vao;
  std::map<std::string, std::unique_ptr<gl::GlProgram>> programs;
  // The classification uploaded, by identity: its derived-data cache, which lives exactly as
  // long as the classification (a weak pointer, so a new classification at the same address
  // never passes for the old one).
  std::weak_ptr<DerivedCache> uploaded_for;
  std::shared_ptr<const gl::GlVoxelList> list;
  gl::GlObject voxels, tables, nodes;

  State() {
    const gl::GlContext::Current current(context);
    vao = gl::makeVertexArray(context.api());
  }
  ~State() {
    try {
      const gl::GlContext::Current current(context);
      programs.clear();
      voxels.reset(), tables.reset(), nodes.reset(), vao.reset();
    } catch (const Error&) {
      // The context could not be made current: destroying it frees its objects all the same.
    }
  }

  const gl::GlProgram& program(const std::string& key,
                               const std::function<std::vector<gl::ShaderStage>()>& stages) {
    auto& p = programs[key];
    if (!p) p = std::make_unique<gl::GlProgram>(context, key, stages());
    return *p;
  }

  // Uploads the voxel list, the tables and the shading nodes unless this classification is the
  // one uploaded.
  void upload(const ClassifiedVolume& cv) {
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
};

GlSplatRenderer::GlSplatRenderer() = default;
GlSplatRenderer::~GlSplatRenderer() = default;

LightIndependentImage GlSplatRenderer::render(const RenderRequest& req,
                                              const ProgressFn& progress) const {
  const SplatSettings settings = readSplatSettings(req.options, "gl");
  const ClassifiedVolume& cv = req.volume;
  const int W = req.width, H = req.height, k = cv.k, kt = cv.t_channels;
  const bool scalar = kt == 1;
  const int stride = 1 + kt + k;

  const std::lock_guard lock(mutex_);
  if (!state_) state_ = std::make_unique<State>();
  State& st = *state_;
  const gl::GlContext::Current current(st.context);
  const gl::GlContext& ctx = st.context;
  const gl::GlApi& gl = ctx.api();
  const gl::GlLimits& limits = ctx.limits();
  const int max_targets = std::min(limits.max_draw_buffers, 8);

  // An image beyond the limits fails before anything big is allocated.
  if (W > limits.max_texture_size || H > limits.max_texture_size)
    throw Error(fmt::format("gl: a {}×{} image is beyond GL_MAX_TEXTURE_SIZE {}", W, H,
                            limits.max_texture_size));
  st.upload(cv);
  const auto list = st.list->splat_voxels->voxels();

  // Project, cull and sort on the CPU with the splat backend's Projector: the same image
  // positions, footprints and depth order as the CPU splat list.
  const splat::KernelShape kernel{settings.sigma, settings.radius, settings.lowpass};
  const splat::Projector projector(req.camera, W, H, cv.spacing, kernel);
  const bool ortho = projector.orthographic();
  const splat::Footprint any = projector.footprint(glm::dvec3(0.0));
  const std::size_t total = list.size();
  std::vector<float> depth(total);
  std::vector<glm::vec2> position(total);
  std::vector<splat::Footprint> footprint(ortho ? 0 : total);
  std::vector<std::uint8_t> keep(total);
  const Dims& d = cv.dims;
  const glm::dvec3 centre = 0.5 * glm::dvec3(d[0] - 1, d[1] - 1, d[2] - 1);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < total; ++i) {
    const std::uint32_t v = list[i].index;
    const std::uint32_t x = v % d[0], y = (v / d[0]) % d[1], z = v / (d[0] * d[1]);
    const glm::dvec3 world = (glm::dvec3(x, y, z) - centre) * cv.spacing;
    const glm::dvec3 pos = projector.project(world);
    const splat::Footprint fp = ortho ? any : projector.footprint(world);
    keep[i] = (ortho || pos.z > 0.0) && !(pos.x + fp.half_w < 0 || pos.x - fp.half_w > W ||
                                          pos.y + fp.half_h < 0 || pos.y - fp.half_h > H);
    depth[i] = static_cast<float>(pos.z);
    position[i] = {static_cast<float>(pos.x), static_cast<float>(pos.y)};
    if (!ortho) footprint[i] = fp;
  }
  std::vector<std::uint32_t> sorted;  // list indices, front to back
  for (std::size_t i = 0; i < total; ++i)
    if (keep[i]) sorted.push_back(static_cast<std::uint32_t>(i));
  sortByDepth(sorted, depth);
  const std::size_t n = sorted.size();

  LightIndependentImage image(W, H, k, kt);
  if (n == 0) {
    for (int c = 0; c < kt; ++c) std::ranges::fill(image.planeFloat(k + c), 1.f);
    if (progress) progress(1.0);
    return image;
  }

  // Per-render buffers, in back-to-front slot order: slot s holds sorted[n − 1 − s].
  std::vector<std::uint32_t> order(n);
  std::vector<float> geometry(4 * n);
  std::vector<float> footprints(ortho ? 8 : 8 * n, 0.f);
  std::vector<float> depth_front_to_back(n);
  const auto putFootprint = [&](std::size_t slot, const splat::Footprint& fp) {
    float* f = &footprints[8 * slot];
    f[0] = fp.a, f[1] = fp.b, f[2] = fp.c, f[3] = fp.norm, f[4] = fp.half_w, f[5] = fp.half_h;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = sorted[i];
    const std::size_t slot = n - 1 - i;
    order[slot] = id;
    geometry[4 * slot] = position[id].x;
    geometry[4 * slot + 1] = position[id].y;
    geometry[4 * slot + 2] = depth[id];
    depth_front_to_back[i] = depth[id];
    if (!ortho) putFootprint(slot, footprint[id]);
  }
  if (ortho) putFootprint(0, any);
  if (static_cast<long long>(n) * stride > limits.max_texture_buffer)
    throw Error(fmt::format("gl: {} splats × {} quantities are beyond GL_MAX_TEXTURE_BUFFER_SIZE "
                            "({} texels)",
                            n, stride, limits.max_texture_buffer));
  checkStorage(limits, geometry.size() * sizeof(float), fmt::format("{} splat positions", n));
  checkStorage(limits, footprints.size() * sizeof(float), fmt::format("{} footprints", n));
  const gl::GlObject order_buffer = gl::makeBuffer(gl, n * sizeof(std::uint32_t), order.data());
  const gl::GlObject geometry_buffer =
      gl::makeBuffer(gl, geometry.size() * sizeof(float), geometry.data());
  const gl::GlObject footprint_buffer =
      gl::makeBuffer(gl, footprints.size() * sizeof(float), footprints.data());
  const gl::GlObject quantities = gl::makeBuffer(gl, n * stride * sizeof(float), nullptr);
  GLuint id = 0;
  gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &id);
  const gl::GlObject quantity_texture(id, gl.DeleteTextures);
  gl.TextureBuffer(id, GL_R32F, quantities.id());
  ctx.check("uploading the sorted splats");

  // Shade and classify every splat once (a sheet draws each about 2·radius/sheet times).
  const gl::GlProgram& prepare = st.program(fmt::format("prepare k={} kt={}", k, kt), [&] {
    return std::vector<gl::ShaderStage>{{GL_COMPUTE_SHADER, gl::prepareShader(k, kt)}};
  });
  const glm::dvec3 forward = RayGenerator(req.camera, W, H).forward();
  prepare.set("u_count", static_cast<int>(n));
  prepare.set("u_nodes", 1);
  prepare.set("u_dims", d[0], d[1], d[2]);
  prepare.set("u_inv_spacing", float(1.0 / cv.spacing.x), float(1.0 / cv.spacing.y),
              float(1.0 / cv.spacing.z));
  prepare.set("u_entries", cv.entries);
  prepare.set("u_orthographic", ortho ? 1 : 0);
  prepare.set("u_headlight", req.light_direction ? 0 : 1);
  prepare.set("u_forward", float(forward.x), float(forward.y), float(forward.z));
  prepare.set("u_eye", float(req.camera.eye.x), float(req.camera.eye.y), float(req.camera.eye.z));
  const glm::dvec3 light = req.light_direction.value_or(glm::dvec3(0.0));
  prepare.set("u_light", float(light.x), float(light.y), float(light.z));
  prepare.set("u_ambient", float(req.shading.ambient));
  prepare.set("u_diffuse", float(req.shading.diffuse));
  // As the CPU splat list: no highlight at all when nothing is specular.
  const bool any_specular = req.shading.specular > 0.0 &&
                            std::ranges::any_of(cv.specular, [](float s) { return s > 0.f; });
  prepare.set("u_specular", any_specular ? float(req.shading.specular) : 0.f);
  prepare.set("u_shininess", float(req.shading.shininess));
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, st.voxels.id());
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, st.tables.id());
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, order_buffer.id());
  gl.BindImageTexture(0, quantity_texture.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, geometry_buffer.id());
  gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, footprint_buffer.id());
  gl.BindTextureUnit(1, st.nodes.id());
  gl.UseProgram(prepare.id());
  const std::size_t groups = (n + 63) / 64;
  const std::size_t gx = std::min<std::size_t>(groups, limits.max_compute_groups_x);
  gl.DispatchCompute(static_cast<GLuint>(gx), static_cast<GLuint>((groups + gx - 1) / gx), 1);
  gl.MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  gl.BindTextureUnit(2, quantity_texture.id());
  ctx.check("shading the splats");

  // The passes.
  const double cutoff = kernel.cutoff();
  const double depth_sigma = any.depth_sigma;  // the same for every splat of a view
  // Point sprites cost llvmpipe one primitive per splat instead of two triangles (measured: the
  // engine's direct pass 2.5 s → 1.9 s, sheets 29 s → 14 s); quads where a footprint is wider
  // than the largest point.
  float widest = 0.f;
  for (std::size_t f = 0; f < footprints.size(); f += 8)
    widest = std::max({widest, footprints[f + 4], footprints[f + 5]});
  const bool points = 2.f * widest + 1.f <= limits.max_point_size;
  const int margin = points ? static_cast<int>(std::ceil(widest)) + 2 : 0;
  const int s_layers = scalar ? (k + 2) / 3 : (k + 3) / 4;
  gl::LayeredTarget s_target(ctx, W + 2 * margin, H + 2 * margin, s_layers, "the S image");
  const auto splatProgram = [&](PassOutput output, int targets) -> const gl::GlProgram& {
    const gl::GlProgram& p = st.program(
        fmt::format("splat k={} kt={} output={} targets={} points={}", k, kt, int(output),
                    targets, points),
        [&] {
          return std::vector<gl::ShaderStage>{
              {GL_VERTEX_SHADER, gl::splatVertexShader(k, kt, output, targets, points)},
              {GL_FRAGMENT_SHADER, gl::splatFragmentShader(k, kt, output, targets)}};
        });
    p.set("u_quantities", 2);
    p.set("u_frame", float(W + 2 * margin), float(H + 2 * margin));
    p.set("u_margin", float(margin));
    p.set("u_per_splat_footprint", ortho ? 0 : 1);
    p.set("u_cut2", float(cutoff * cutoff));
    p.set("u_cut", float(cutoff));
    p.set("u_depth_sigma", float(depth_sigma));
    p.set("u_phi_lo", float(normalCdf(-cutoff)));
    p.set("u_phi_span", float(normalCdf(cutoff) - normalCdf(-cutoff)));
    p.set("u_sheet", 0);
    gl.UseProgram(p.id());
    return p;
  };
  const auto compositeProgram = [&](PassOutput output, int targets) -> const gl::GlProgram& {
    const gl::GlProgram& p = st.program(
        fmt::format("composite k={} kt={} output={} targets={}", k, kt, int(output), targets),
        [&] {
          return std::vector<gl::ShaderStage>{
              {GL_VERTEX_SHADER, gl::fullscreenVertexShader()},
              {GL_FRAGMENT_SHADER, gl::compositeFragmentShader(k, kt, output, targets)}};
        });
    p.set("u_sheet_buffer", 0);
    gl.UseProgram(p.id());
    return p;
  };
  const auto drawSlots = [&](std::size_t first, std::size_t count) {
    if (points)
      gl.DrawArrays(GL_POINTS, static_cast<GLint>(first), static_cast<GLsizei>(count));
    else
      gl.DrawArrays(GL_TRIANGLES, static_cast<GLint>(6 * first), static_cast<GLsizei>(6 * count));
  };
  // S: chromatic, one dual-source pass per 4 channels; scalar, up to 8 targets of 3 channels
  // (+ T in alpha) per pass. `source` draws what is composited: splats or a sheet buffer.
  const auto compositeS = [&](const std::function<const gl::GlProgram&(PassOutput, int)>& use,
                              const std::function<void()>& source) {
    if (scalar) {
      gl.BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA);
      for (int base = 0; base < s_layers; base += max_targets) {
        const int count = std::min(max_targets, s_layers - base);
        s_target.drawInto(base, count);
        use(PassOutput::kScalar, count).set("u_first", 3 * base);
        source();
      }
    } else {
      gl.BlendFunc(GL_ONE, GL_SRC1_COLOR);
      for (int g = 0; g < s_layers; ++g) {
        s_target.drawInto(g, 1);
        use(PassOutput::kDual, 1).set("u_first", 4 * g);
        source();
      }
    }
  };

  gl.BindVertexArray(st.vao.id());
  gl.Enable(GL_PROGRAM_POINT_SIZE);
  gl.Enable(GL_BLEND);
  gl.BlendEquation(GL_FUNC_ADD);
  for (int base = 0; base < s_layers; base += max_targets) {
    s_target.drawInto(base, std::min(max_targets, s_layers - base));
    s_target.clear(0.f, scalar ? 1.f : 0.f);  // scalar: alpha holds T
  }

  if (settings.mode == SplatSettings::Mode::kDirect) {
    compositeS(splatProgram, [&] { drawSlots(0, n); });
    if (progress) progress(0.9);
  } else {
    const double min_spacing = std::min({cv.spacing.x, cv.spacing.y, cv.spacing.z});
    const double thickness = settings.sheet_voxels * min_spacing;
    const double reach = cutoff * depth_sigma;
    // The CPU's sheet lattice: the first sheet starts where the front splat's kernel does.
    const double first = depth_front_to_back.front() - reach;
    const long sheets =
        static_cast<long>(std::floor((depth_front_to_back.back() + reach - first) / thickness)) +
        1;
    const auto boundary = [&](long j) { return first + j * thickness; };
    const int acc_layers = (stride + 3) / 4;
    gl::LayeredTarget sheet(ctx, W + 2 * margin, H + 2 * margin, acc_layers, "the sheet buffer");
    gl.BindTextureUnit(0, sheet.texture());
    gl.Enable(GL_SCISSOR_TEST);
    for (long j = sheets - 1; j >= 0; --j) {
      const double z0 = boundary(j), z1 = boundary(j + 1);
      // Splats whose kernel reaches into [z0, z1]: a run of the depth order.
      const std::size_t ia = std::upper_bound(depth_front_to_back.begin(),
                                              depth_front_to_back.end(), z0 - reach) -
                             depth_front_to_back.begin();
      const std::size_t ib = std::lower_bound(depth_front_to_back.begin(),
                                              depth_front_to_back.end(), z1 + reach) -
                             depth_front_to_back.begin();
      if (ia >= ib) continue;
      // The sheet's pixels: clearing and compositing touch nothing else.
      float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
      for (std::size_t i = ia; i < ib; ++i) {
        const std::size_t slot = n - 1 - i;
        const float* g = &geometry[4 * slot];
        const float* f = &footprints[ortho ? 0 : 8 * slot];
        x0 = std::min(x0, g[0] - f[4]), x1 = std::max(x1, g[0] + f[4]);
        y0 = std::min(y0, g[1] - f[5]), y1 = std::max(y1, g[1] + f[5]);
      }
      const int px0 = std::max(0, static_cast<int>(std::floor(x0)));
      const int px1 = std::min(W, static_cast<int>(std::ceil(x1)));
      const int py0 = std::max(0, static_cast<int>(std::floor(y0)));
      const int py1 = std::min(H, static_cast<int>(std::ceil(y1)));
      if (px0 >= px1 || py0 >= py1) continue;
      gl.Scissor(margin + px0, margin + py0, px1 - px0, py1 - py0);

      gl.BlendFunc(GL_ONE, GL_ONE);
      for (int base = 0; base < acc_layers; base += max_targets) {
        const int count = std::min(max_targets, acc_layers - base);
        sheet.drawInto(base, count);
        sheet.clear(0.f, 0.f);
        const gl::GlProgram& p = splatProgram(PassOutput::kAccumulate, count);
        p.set("u_first", 4 * base);
        p.set("u_end", stride);
        p.set("u_sheet", 1);
        p.set("u_z0", float(z0));
        p.set("u_z1", float(z1));
        drawSlots(n - ib, ib - ia);
      }
      compositeS(compositeProgram, [&] { gl.DrawArrays(GL_TRIANGLES, 0, 3); });
      if (progress) progress(0.9 * (sheets - j) / sheets);
    }
    gl.Disable(GL_SCISSOR_TEST);
  }
  ctx.check("compositing");

  // Read back. Window row y is image row y (the vertex shader maps image y to window y), so
  // the layers come back in image order.
  std::vector<float> rgba;
  const std::size_t pixels = image.pixels();
  const int per_layer = scalar ? 3 : 4;
  for (int layer = 0; layer < s_layers; ++layer) {
    s_target.read(layer, margin, margin, W, H, rgba);
    for (int j = 0; j < per_layer && per_layer * layer + j < k; ++j) {
      float* plane = image.planeFloat(per_layer * layer + j).data();
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = rgba[4 * p + j];
    }
    if (scalar && layer == 0) {
      float* plane = image.planeFloat(k).data();
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = rgba[4 * p + 3];
    }
  }
  if (!scalar) {
    // T = exp(−Σ τ_t): the optical depth of every splat along the ray, additively.
    const int t_layers = (kt + 3) / 4;
    gl::LayeredTarget optical_depth(ctx, W + 2 * margin, H + 2 * margin, t_layers,
                                    "the optical depth image");
    gl.BlendFunc(GL_ONE, GL_ONE);
    for (int base = 0; base < t_layers; base += max_targets) {
      const int count = std::min(max_targets, t_layers - base);
      optical_depth.drawInto(base, count);
      optical_depth.clear(0.f, 0.f);
      const gl::GlProgram& p = splatProgram(PassOutput::kAccumulate, count);
      p.set("u_first", 1 + 4 * base);
      p.set("u_end", 1 + kt);
      drawSlots(0, n);
    }
    ctx.check("the optical depth pass");
    for (int layer = 0; layer < t_layers; ++layer) {
      optical_depth.read(layer, margin, margin, W, H, rgba);
      for (int j = 0; j < 4 && 4 * layer + j < kt; ++j) {
        float* plane = image.planeFloat(k + 4 * layer + j).data();
        for (std::size_t p = 0; p < pixels; ++p) plane[p] = std::exp(-rgba[4 * p + j]);
      }
    }
  }
  gl.Disable(GL_BLEND);
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  if (progress) progress(1.0);

  // Numeric failure is reported, never written out.
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    for (std::size_t i = 0; i < plane.size(); ++i)
      if (!std::isfinite(plane[i]))
        throw Error(fmt::format("gl: non-finite value {} in channel {} at pixel ({}, {})",
                                plane[i], p, i % W, i / W));
  }
  return image;
}

}  // namespace svr
