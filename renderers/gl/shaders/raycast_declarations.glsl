
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

