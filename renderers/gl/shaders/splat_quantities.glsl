
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
