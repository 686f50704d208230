
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
