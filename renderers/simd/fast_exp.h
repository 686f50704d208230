#pragma once
// 2^y and e^x for y, x ≤ 0 — the Phong highlight's power and a splat's per-pixel opacity and
// transmission — branch-free and inlined, one value or four (Float4) at a time, where libm's
// expf is a call per pixel. The polynomial is a least-squares fit of 2^f on [0, 1), within
// 2.3e-7 relative (float rounding is 6e-8), evaluated in Estrin's scheme to keep the dependency
// chain short. Below 2^−126 (the smallest normal float) the result is 0.

#include <algorithm>
#include <bit>
#include <cstdint>

#include "renderers/simd/float4.h"

namespace svr {

[[gnu::always_inline]] inline float fastExp2(float y) {
  const float clamped = std::max(y, -126.f);
  // 2^y = 2^n · 2^f, n = ⌊y⌋, f in [0, 1).
  const int truncated = static_cast<int>(clamped);
  const int n = truncated - (clamped < static_cast<float>(truncated));
  const float f = clamped - static_cast<float>(n);
  const float f2 = f * f, f4 = f2 * f2;
  const float p = (0.99999977f + f * 0.693156777f) + f2 * (0.240131692f + f * 0.0558765569f) +
                  f4 * (0.00894058253f + f * 0.00189437942f);
  const float r = p * std::bit_cast<float>(static_cast<std::uint32_t>(n + 127) << 23);
  return y < -126.f ? 0.f : r;
}

[[gnu::always_inline]] inline float fastExp(float x) { return fastExp2(x * 1.44269504f); }

// Four at a time, each lane taking fastExp2's operations in its order (the same floats).
[[gnu::always_inline]] inline Float4 fastExp2(Float4 y) {
  const Float4 low = splat4(-126.f);
  const Float4 clamped = y < low ? low : y;  // std::max(y, −126)
  const Int4 truncated = __builtin_convertvector(clamped, Int4);
  // ⌊y⌋: one less where truncation rounded up (the comparison's lanes are −1 or 0).
  const Int4 n = truncated + (clamped < __builtin_convertvector(truncated, Float4));
  const Float4 f = clamped - __builtin_convertvector(n, Float4);
  const Float4 f2 = f * f, f4 = f2 * f2;
  const Float4 p = (splat4(0.99999977f) + f * 0.693156777f) +
                   f2 * (splat4(0.240131692f) + f * 0.0558765569f) +
                   f4 * (splat4(0.00894058253f) + f * 0.00189437942f);
  const Float4 r = p * reinterpret_cast<Float4>((n + 127) << 23);
  return y < low ? splat4(0.f) : r;
}

[[gnu::always_inline]] inline Float4 fastExp(Float4 x) { return fastExp2(x * 1.44269504f); }

}  // namespace svr
