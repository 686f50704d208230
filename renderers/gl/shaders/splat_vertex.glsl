
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
