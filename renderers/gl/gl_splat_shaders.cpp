#include "renderers/gl/gl_splat_shaders.h"

#include <fmt/format.h>

namespace svr::gl {
namespace {

std::string header(int k, int kt, PassOutput output, int targets) {
  return fmt::format(
      "#version 450 core\n"
      "#define K {}\n#define KT {}\n#define STRIDE (1 + KT + K)\n#define NOUT {}\n"
      "#define OUTPUT {}\n",
      k, kt, targets, static_cast<int>(output));
}

// The output stage shared by the splat and composite fragment shaders: quantity(q) gives
// quantity q of what this fragment composites (one splat's kernel length, or one sheet).
constexpr const char* kEmit = R"(
// (1 − e^{−x}) / x without the cancellation of 1 − exp(−x) at small x (the CPU's −expm1(−x)/x).
float alphaPerTau(float x) { return x < 1e-3 ? 1.0 - x * (0.5 - x / 6.0) : (1.0 - exp(-x)) / x; }

uniform int u_first;  // first S channel (kDual, kScalar) or first quantity (kAccumulate)
uniform int u_end;    // kAccumulate: one past the last quantity
#if OUTPUT == 1
layout(location = 0, index = 0) out vec4 o_colour;
layout(location = 0, index = 1) out vec4 o_transmission;
void emit() {
  float per_tau = alphaPerTau(quantity(0));
  for (int j = 0; j < 4; ++j) {
    int ch = u_first + j;
    o_colour[j] = ch < K ? per_tau * quantity(1 + KT + ch) : 0.0;
    o_transmission[j] = ch < K ? exp(-quantity(1 + (KT > 1 ? ch : 0))) : 1.0;
  }
}
#else
layout(location = 0) out vec4 o[NOUT];
#if OUTPUT == 2
void emit() {
  float per_tau = alphaPerTau(quantity(0));
  float tau_t = quantity(1);
  float absorbed = tau_t * alphaPerTau(tau_t);
  for (int i = 0; i < NOUT; ++i) {
    vec4 v = vec4(0.0, 0.0, 0.0, absorbed);
    for (int j = 0; j < 3; ++j) {
      int ch = u_first + 3 * i + j;
      if (ch < K) v[j] = per_tau * quantity(1 + KT + ch);
    }
    o[i] = v;
  }
}
#else
void emit() {
  for (int i = 0; i < NOUT; ++i) {
    vec4 v = vec4(0.0);
    for (int j = 0; j < 4; ++j) {
      int q = u_first + 4 * i + j;
      if (q < u_end) v[j] = quantity(q);
    }
    o[i] = v;
  }
}
#endif
#endif
)";

}  // namespace

std::string prepareShader(int k, int kt) {
  return header(k, kt, PassOutput::kAccumulate, 1) + R"(
layout(local_size_x = 64) in;
struct Voxel { vec4 world_frac; ivec4 cell_entry; };
layout(std430, binding = 0) readonly buffer Voxels { Voxel voxels[]; };
layout(std430, binding = 1) readonly buffer Tables { float tables[]; };
layout(std430, binding = 2) readonly buffer Order { uint order[]; };
// Per splat STRIDE floats, in a buffer texture: GL_MAX_TEXTURE_BUFFER_SIZE (2^27 texels on
// llvmpipe) holds 4× what one shader storage block may (128 MiB), enough for the engine at
// spectral:31.
layout(r32f, binding = 0) uniform writeonly imageBuffer u_quantities;
uniform sampler3D u_nodes;  // shading-field cell means on the dual grid (gl_voxel_list.h)
uniform ivec3 u_dims;       // voxels per axis: nodes run 0 .. u_dims
uniform vec3 u_inv_spacing;
uniform int u_count, u_entries;
uniform int u_orthographic, u_headlight;
uniform vec3 u_forward, u_eye, u_light;
uniform float u_ambient, u_diffuse, u_specular, u_shininess;

// SplatVoxels::gradientAtNode: central differences of the node field, clamped at the border.
vec3 gradientAtNode(ivec3 p) {
  vec3 g;
  for (int a = 0; a < 3; ++a) {
    ivec3 lo = p, hi = p;
    lo[a] = max(p[a] - 1, 0);
    hi[a] = min(p[a] + 1, u_dims[a]);
    g[a] = (texelFetch(u_nodes, hi, 0).r - texelFetch(u_nodes, lo, 0).r) * 0.5 * u_inv_spacing[a];
  }
  return g;
}

void main() {
  uint slot = gl_GlobalInvocationID.x +
              gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (slot >= uint(u_count)) return;
  Voxel v = voxels[order[slot]];
  int E = u_entries;
  int e0 = v.cell_entry.w, e1 = min(e0 + 1, E - 1);
  float f = v.world_frac.w, g = 1.0 - f;
  // The CPU splat's shade: two-sided Phong (renderers/classification/classified_sample.h) at the 8 corners
  // of the voxel's cell, averaged; full light and no highlight where the gradient vanishes.
  vec3 view = u_orthographic != 0 ? -u_forward : normalize(u_eye - v.world_frac.xyz);
  vec3 light = u_headlight != 0 ? view : u_light;
  vec3 halfway = normalize(light + view);
  float shade = 0.0, highlight = 0.0;
  for (int c = 0; c < 8; ++c) {
    vec3 grad = gradientAtNode(v.cell_entry.xyz + ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    float len = length(grad);
    if (!(len > 1e-6)) {
      shade += u_ambient + u_diffuse;
    } else {
      shade += u_ambient + u_diffuse * abs(dot(grad, light) / len);
      highlight += u_specular * pow(abs(dot(grad, halfway) / len), u_shininess);
    }
  }
  shade *= 0.125;
  highlight *= 0.125;
  // Entries blended as classified_sample.h's blendEntries, opacity-weighted; E = σ_α × colour
  // needs no division by σ_α.
  int sigma_t = E, rho = E + E * KT, spec = rho + E * K, white = spec + E;
  float a0 = g * tables[e0], a1 = f * tables[e1];
  float highlight_w = highlight * (a0 * tables[spec + e0] + a1 * tables[spec + e1]);
  int base = int(slot) * STRIDE;
  imageStore(u_quantities, base, vec4(a0 + a1));
  // A model's projected transmission can exceed 1 (a negative extinction); the CPU splat
  // attenuates only by positive ones, so T never rises above 1.
  for (int c = 0; c < KT; ++c)
    imageStore(u_quantities, base + 1 + c,
               vec4(max(g * tables[sigma_t + e0 * KT + c] + f * tables[sigma_t + e1 * KT + c],
                        0.0)));
  for (int c = 0; c < K; ++c)
    imageStore(u_quantities, base + 1 + KT + c,
               vec4(shade * (a0 * tables[rho + e0 * K + c] + a1 * tables[rho + e1 * K + c]) +
                    tables[white + c] * highlight_w));
}
)";
}

namespace {

// Which quantities a splat pass needs, as v_q[0 .. NQ): the vertex shader loads them once per
// splat corner, so fragments only scale them by the kernel length (no per-fragment loads).
// sourceOf(i) is the quantity index behind v_q[i], or −1 for a channel past K (read as 0).
constexpr const char* kSplatQuantities = R"(
uniform int u_first;  // first S channel (kDual, kScalar) or first quantity (kAccumulate)
uniform int u_end;    // kAccumulate: one past the last quantity
#if OUTPUT == 0
#define NQ (4 * NOUT)
int sourceOf(int i) { return u_first + i < u_end ? u_first + i : -1; }
#elif OUTPUT == 1
#define NQ 9  // τ_α, 4 × E, 4 × τ_t
int sourceOf(int i) {
  if (i == 0) return 0;
  int ch = u_first + (i - 1) % 4;
  if (ch >= K) return -1;
  return i < 5 ? 1 + KT + ch : 1 + (KT > 1 ? ch : 0);
}
#else
#define NQ (2 + 3 * NOUT)  // τ_α, τ_t, 3 × NOUT × E
int sourceOf(int i) {
  if (i < 2) return i;
  int ch = u_first + i - 2;
  return ch < K ? 1 + KT + ch : -1;
}
#endif
)";

}  // namespace

std::string splatVertexShader(int k, int kt, PassOutput output, int targets, bool points) {
  return header(k, kt, output, targets) + (points ? "#define POINTS 1\n" : "#define POINTS 0\n") +
         kSplatQuantities + R"(
// Per splat, in back-to-front order: (x, y, depth, 0) in image pixels (row 0 at the top, drawn
// to window row 0) and world depth; footprints as (a, b, c, norm), (half_w, half_h, 0, 0) —
// one per splat in perspective, one for all in orthographic views.
uniform samplerBuffer u_quantities;  // written by the prepare shader
layout(std430, binding = 4) readonly buffer Geometry { vec4 geometry[]; };
layout(std430, binding = 5) readonly buffer Footprints { vec4 footprints[]; };
// The targets are the image plus a margin of u_margin pixels all round (a point sprite whose
// centre leaves the viewport is dropped whole, so splats just outside the image need it).
uniform vec2 u_frame;
uniform float u_margin;
uniform int u_per_splat_footprint;
// Sheet mode: the splat's share of its kernel between depths u_z0 and u_z1 (the truncated
// normal CDF, as the CPU's table, its tails beyond ±u_cut — kSheetDepthCut — given to the
// sheets next to them); otherwise the whole kernel.
uniform int u_sheet;
uniform float u_z0, u_z1, u_depth_sigma, u_cut, u_phi_lo, u_phi_span;
flat out float v_weight;
flat out vec2 v_centre;
flat out vec3 v_abc;
flat out float v_q[NQ];

// Φ(t) through erfc (Abramowitz & Stegun 7.1.26, |error| < 1.5e-7).
float phi(float t) {
  float x = abs(t) * 0.70710678;
  float s = 1.0 / (1.0 + 0.3275911 * x);
  float poly = s * (0.254829592 + s * (-0.284496736 + s * (1.421413741 + s * (-1.453152027 +
               s * 1.061405429))));
  float upper = 0.5 * poly * exp(-x * x);  // 1 − Φ(|t|)
  return t >= 0.0 ? 1.0 - upper : upper;
}
float cdf(float t) {
  if (t <= -u_cut) return 0.0;
  if (t >= u_cut) return 1.0;
  return clamp((phi(t) - u_phi_lo) / u_phi_span, 0.0, 1.0);
}

const vec2 kCorner[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1),
                               vec2(-1, 1));
void main() {
#if POINTS
  int slot = gl_VertexID;
#else
  int slot = gl_VertexID / 6;
#endif
  vec4 g = geometry[slot];
  int f = u_per_splat_footprint != 0 ? slot : 0;
  vec4 shape = footprints[2 * f], extent = footprints[2 * f + 1];
  float share = 1.0;
  if (u_sheet != 0)
    share = cdf((u_z1 - g.z) / u_depth_sigma) - cdf((u_z0 - g.z) / u_depth_sigma);
#if POINTS
  // A square sprite whose pixel centres cover the footprint's bounding box (with half a pixel
  // to spare on each side).
  vec2 p = g.xy;
  gl_PointSize = 2.0 * max(extent.x, extent.y) + 1.0;
#else
  vec2 p = g.xy + kCorner[gl_VertexID % 6] * extent.xy;
#endif
  // No share of this sheet: a degenerate quad outside the clip volume draws nothing.
  gl_Position = share > 0.0 ? vec4((p + u_margin) / u_frame * 2.0 - 1.0, 0.0, 1.0)
                            : vec4(2.0, 2.0, 2.0, 1.0);
  v_weight = shape.w * share;
  v_centre = g.xy;
  v_abc = shape.xyz;
  for (int i = 0; i < NQ; ++i) {
    int q = sourceOf(i);
    v_q[i] = q >= 0 ? texelFetch(u_quantities, slot * STRIDE + q).r : 0.0;
  }
}
)";
}

std::string splatFragmentShader(int k, int kt, PassOutput output, int targets) {
  return header(k, kt, output, targets) + kSplatQuantities + R"(
// (1 − e^{−x}) / x without the cancellation of 1 − exp(−x) at small x (the CPU's −expm1(−x)/x).
float alphaPerTau(float x) { return x < 1e-3 ? 1.0 - x * (0.5 - x / 6.0) : (1.0 - exp(-x)) / x; }
uniform float u_cut2, u_margin;
flat in float v_weight;
flat in vec2 v_centre;
flat in vec3 v_abc;
flat in float v_q[NQ];
#if OUTPUT == 1
layout(location = 0, index = 0) out vec4 o_colour;
layout(location = 0, index = 1) out vec4 o_transmission;
#else
layout(location = 0) out vec4 o[NOUT];
#endif

void main() {
  vec2 d = gl_FragCoord.xy - u_margin - v_centre;
  float q = v_abc.x * d.x * d.x + 2.0 * v_abc.y * d.x * d.y + v_abc.z * d.y * d.y;
  if (q >= u_cut2) discard;
  float len = v_weight * exp(-0.5 * q);  // world length of the kernel on this ray (in this sheet)
#if OUTPUT == 0
  for (int i = 0; i < NOUT; ++i)
    o[i] = vec4(v_q[4 * i], v_q[4 * i + 1], v_q[4 * i + 2], v_q[4 * i + 3]) * len;
#elif OUTPUT == 1
  float per_tau = alphaPerTau(v_q[0] * len);
  o_colour = per_tau * len * vec4(v_q[1], v_q[2], v_q[3], v_q[4]);
  o_transmission = exp(-len * vec4(v_q[5], v_q[6], v_q[7], v_q[8]));
#else
  float per_tau = alphaPerTau(v_q[0] * len);
  float tau_t = v_q[1] * len;
  float absorbed = tau_t * alphaPerTau(tau_t);
  for (int i = 0; i < NOUT; ++i)
    o[i] = vec4(per_tau * len * vec3(v_q[2 + 3 * i], v_q[3 + 3 * i], v_q[4 + 3 * i]), absorbed);
#endif
}
)";
}

std::string compositeFragmentShader(int k, int kt, PassOutput output, int targets) {
  return header(k, kt, output, targets) + R"(
uniform sampler2DArray u_sheet_buffer;  // quantity q in layer q / 4, component q % 4
float quantity(int q) {
  return texelFetch(u_sheet_buffer, ivec3(ivec2(gl_FragCoord.xy), q / 4), 0)[q % 4];
}
)" + kEmit + R"(
void main() { emit(); }
)";
}

}  // namespace svr::gl
