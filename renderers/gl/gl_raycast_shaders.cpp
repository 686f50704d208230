#include "renderers/gl/gl_raycast_shaders.h"

#include <fmt/format.h>

namespace svr::gl {

namespace {

// The uniforms, the per-ray state and the helpers: sampling, classification, blocks, shading.
constexpr const char* kRaycastDeclarations = R"(
#define SL ((K + 3) / 4)   // vec4s of S (and of a table row's α·ρ)
#define TL ((KT + 3) / 4)  // vec4s of T (and of a row's transmission)
#define ROW (1 + SL + TL)  // texels of a table row: (α, α·s, 0, 0), α·ρ, t (zero-padded)
layout(location = 0) out vec4 o_layers[NOUT];

// The volume, texel centres at voxel coordinates: PRECOMPUTED, (f, ∇f) as RGBA16_SNORM decoded
// by u_decode (kernels/gradient_volume.h); otherwise the shading field as R32F.
uniform sampler3D u_field;
uniform vec4 u_decode_scale, u_decode_offset;
#if LABELS
uniform usampler3D u_labels;
#endif
// Table rows by entry (raycast/sample_table.h's, in vec4s); row u_entries holds the white's
// coefficients in texels 1 … SL.
uniform sampler2D u_table;
uniform int u_entries;
// Per 4³ block (ClassifiedVolume::kBlock): the log2 edge of the largest empty block around it
// (kernels/occupancy_pyramid.h), 0 when it is occupied.
uniform usampler3D u_empty;
uniform int u_block_shift, u_skip;

uniform vec3 u_hi;         // dims − 1
uniform vec3 u_inv_dims;
uniform float u_bin_lo, u_bin_scale, u_bin_last;
uniform int u_last_lower;  // entries − 2 (0 for a single entry)
uniform vec3 u_half_inv_spacing;

// The camera (scene/camera.h's RayGenerator): right and up scaled by the half extents.
uniform vec3 u_eye, u_forward, u_right, u_up, u_inv_spacing, u_centre;
uniform int u_orthographic;
uniform vec2 u_image;
uniform float u_step, u_termination;

uniform int u_headlight;
uniform vec3 u_light;
uniform float u_ambient, u_diffuse, u_specular, u_shininess, u_highlight_floor;

vec4 S[SL];
vec4 T[TL];
vec4 acc[ROW];

// The first lattice sample past the exit of the block of 2^shift voxels holding p (raycast_
// kernel.h's firstSamplePast).
int firstSamplePast(int shift, vec3 p, vec3 d, int i, float t, float first) {
  float size = float(1 << shift);
  float exit_t = 3.0e38;
  for (int a = 0; a < 3; ++a) {
    if (abs(d[a]) > 1e-30) {
      float lo = float(int(max(p[a], 0.0)) >> shift) * size;
      float bound = d[a] > 0.0 ? lo + size : lo;
      exit_t = min(exit_t, (bound - p[a]) / d[a]);
    }
  }
  float target = t + max(exit_t, 0.0);
  return max(int(ceil((target - first) / u_step)), i + 1);
}

vec4 field(vec3 p) { return texture(u_field, (p + 0.5) * u_inv_dims); }

// The sample's blended table row into acc: the two bins around a scalar value, or the eight
// corners' labels weighted trilinearly.
void blendRow(vec3 p, float v) {
#if LABELS
  ivec3 base = min(ivec3(p), max(ivec3(u_hi) - 1, 0));
  vec3 f = p - vec3(base);
  for (int r = 0; r < ROW; ++r) acc[r] = vec4(0.0);
  for (int n = 0; n < 8; ++n) {
    ivec3 corner = ivec3(n & 1, (n >> 1) & 1, n >> 2);
    vec3 w3 = mix(1.0 - f, f, vec3(corner));
    float w = w3.x * w3.y * w3.z;
    int e = int(texelFetch(u_labels, min(base + corner, ivec3(u_hi)), 0).r);
    for (int r = 0; r < ROW; ++r) acc[r] += w * texelFetch(u_table, ivec2(r, e), 0);
  }
#else
  float bin = clamp((v - u_bin_lo) * u_bin_scale, 0.0, u_bin_last);
  int e0 = min(int(bin), u_last_lower);
  int e1 = min(e0 + 1, u_entries - 1);
  float f = bin - float(e0);
  for (int r = 0; r < ROW; ++r) {
    vec4 r0 = texelFetch(u_table, ivec2(r, e0), 0);
    acc[r] = r0 + f * (texelFetch(u_table, ivec2(r, e1), 0) - r0);
  }
#endif
}

)";

// One ray per fragment: march the lattice, composite S and T, write the asked layers.
constexpr const char* kRaycastMain = R"(void main() {
  for (int i = 0; i < SL; ++i) S[i] = vec4(0.0);
  for (int i = 0; i < TL; ++i) T[i] = vec4(lessThan(ivec4(4 * i) + ivec4(0, 1, 2, 3), ivec4(KT)));
  vec4 white[SL];
  for (int i = 0; i < SL; ++i) white[i] = texelFetch(u_table, ivec2(1 + i, u_entries), 0);

  // Window row y is image row y, so the layers read back in image order (row 0 at the top).
  float u = 2.0 * gl_FragCoord.x / u_image.x - 1.0;
  float v = 1.0 - 2.0 * gl_FragCoord.y / u_image.y;
  vec3 origin = u_eye, dir = u_forward;
  if (u_orthographic != 0) origin += u * u_right + v * u_up;
  else dir = normalize(u_forward + u * u_right + v * u_up);
  vec3 o = origin * u_inv_spacing + u_centre;
  vec3 d = dir * u_inv_spacing;
  float t0 = 0.0, t1 = 3.0e38;
  bool hit = true;
  for (int a = 0; a < 3; ++a) {
    if (abs(d[a]) < 1e-30) {
      hit = hit && o[a] >= 0.0 && o[a] <= u_hi[a];
    } else {
      float ta = -o[a] / d[a], tb = (u_hi[a] - o[a]) / d[a];
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    }
  }
  if (hit && t1 > t0) {
    vec3 view = -dir;
    vec3 light = u_headlight != 0 ? view : u_light;
    vec3 halfway = normalize(light + view);
    float first = t0 + 0.5 * u_step;
    int samples = int(ceil((t1 - first) / u_step));
    int occupied_until = 0;
    for (int i = 0; i < samples;) {
      float t = first + float(i) * u_step;
      vec3 p = o + t * d;
      // Empty space: jump past the largest empty block; in an occupied one, look again only
      // once the ray has left it.
      if (u_skip != 0 && i >= occupied_until) {
        ivec3 c = ivec3(clamp(p, vec3(0.0), u_hi));
        uint empty_shift = texelFetch(u_empty, c >> u_block_shift, 0).r;
        if (empty_shift != 0u) {
          i = firstSamplePast(int(empty_shift), p, d, i, t, first);
          continue;
        }
        occupied_until = firstSamplePast(u_block_shift, p, d, i, t, first);
      }
      vec3 pc = clamp(p, vec3(0.0), u_hi);
#if PRECOMPUTED
      vec4 vg = field(pc) * u_decode_scale + u_decode_offset;
      float value = vg.x;
      vec3 g = vg.yzw;
#else
      float value = field(pc).r;
#endif
      blendRow(pc, value);
      if (acc[0].x > 0.0) {
#if !PRECOMPUTED
        vec3 g;
        for (int a = 0; a < 3; ++a) {
          vec3 step_a = vec3(0.0);
          step_a[a] = 1.0;
          g[a] = (field(clamp(p + step_a, vec3(0.0), u_hi)).r -
                  field(clamp(p - step_a, vec3(0.0), u_hi)).r) * u_half_inv_spacing[a];
        }
#endif
        // Two-sided Phong (classification/classified_sample.h): full light and no highlight where the
        // gradient vanishes.
        float shade = u_ambient + u_diffuse, highlight = 0.0;
        float len = length(g);
        if (len > 1e-6) {
          shade = u_ambient + u_diffuse * abs(dot(g, light) / len);
          float cos_h = min(abs(dot(g, halfway) / len), 1.0);
          if (cos_h > u_highlight_floor) highlight = u_specular * pow(cos_h, u_shininess);
        }
        float hs = highlight * acc[0].y;
        for (int c = 0; c < SL; ++c)
          S[c] += (KT > 1 ? T[c] : vec4(T[0].x)) * (acc[1 + c] * shade + white[c] * hs);
      }
      float tmax = 0.0;
      for (int c = 0; c < TL; ++c) {
        T[c] *= acc[1 + SL + c];
        tmax = max(tmax, max(max(T[c].x, T[c].y), max(T[c].z, T[c].w)));
      }
      if (tmax < u_termination) break;
      ++i;
    }
  }
  for (int j = 0; j < NOUT; ++j) o_layers[j] = FIRST + j < SL ? S[FIRST + j] : T[FIRST + j - SL];
}
)";

}  // namespace

std::string raycastFragmentShader(const RaycastShaderKey& key) {
  return fmt::format(
             "#version 450 core\n#define K {}\n#define KT {}\n#define LABELS {}\n"
             "#define PRECOMPUTED {}\n#define FIRST {}\n#define NOUT {}\n",
             key.k, key.kt, key.labels ? 1 : 0, key.precomputed_gradients ? 1 : 0,
             key.first_layer, key.layers) +
         kRaycastDeclarations + kRaycastMain;
}

}  // namespace svr::gl
