
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
