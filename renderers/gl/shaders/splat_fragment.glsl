
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
