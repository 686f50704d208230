#pragma once
// x^s for x in [0, 1] and s ≥ 0 — the Phong highlight |n·h|^shininess, taken at every shaded
// sample of every backend — as exp2(s · log2 x) with polynomial log2 and exp2, branch-free and
// inlined where libm's powf is a call and a third of the shading cost. Relative error under
// 2e-6 · s (the polynomials are least-squares fits: log2 on [1, 2) within 7e-7, exp2 on [0, 1)
// within 2.3e-7 relative), far below what an 8-bit image or a ΔE2000 of 0.01 resolves.

#include <bit>
#include <cstdint>

namespace svr {

// The polynomials are evaluated in Estrin's scheme (powers of u and f in parallel), which keeps
// the dependency chain short: Horner's twelve dependent multiply-adds cost more than libm.
[[gnu::always_inline]] inline float unitPower(float x, float s) {
  if (!(x > 0.f)) return s > 0.f ? 0.f : 1.f;
  // log2 x = e + log2 m, m in [1, 2).
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(x);
  const int e = static_cast<int>(bits >> 23) - 127;
  const float u = std::bit_cast<float>((bits & 0x7fffffu) | 0x3f800000u) - 1.f;
  const float u2 = u * u, u4 = u2 * u2;
  const float log2m = u * ((1.44265926f + u * -0.720458317f) +
                           u2 * (0.472893375f + u * -0.324294866f) +
                           u4 * ((0.192307104f + u * -0.0783569111f) + u2 * 0.0152510467f));
  const float y = s * (static_cast<float>(e) + log2m);  // ≤ 0 for x ≤ 1
  if (y < -126.f) return 0.f;
  // 2^y = 2^n · 2^f, n = ⌊y⌋, f in [0, 1).
  const int n = static_cast<int>(y) - (y < static_cast<float>(static_cast<int>(y)));
  const float f = y - static_cast<float>(n);
  const float f2 = f * f, f4 = f2 * f2;
  const float p = (0.99999977f + f * 0.693156777f) + f2 * (0.240131692f + f * 0.0558765569f) +
                  f4 * (0.00894058253f + f * 0.00189437942f);
  return p * std::bit_cast<float>(static_cast<std::uint32_t>(n + 127) << 23);
}

}  // namespace svr
