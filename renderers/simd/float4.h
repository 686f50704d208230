#pragma once
// Four floats as one vector (GCC's vector extension: SSE on the baseline target, AVX's encoding
// inside the AVX2 kernels), for work done four lanes at a time with each lane's arithmetic the
// same as the scalar code's: shear-warp's records (blended and encoded), table rows and warp
// taps, and phong4 (classified_sample.h). Loads and stores go through memcpy, one unaligned move each.

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace svr {

typedef float Float4 __attribute__((vector_size(16)));
typedef std::int32_t Int4 __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store4(float* p, Float4 v) { std::memcpy(p, &v, sizeof v); }

[[gnu::always_inline]] inline Float4 splat4(float x) { return Float4{x, x, x, x}; }

// |x| per lane (the sign bit cleared, as std::abs).
[[gnu::always_inline]] inline Float4 abs4(Float4 x) {
  return reinterpret_cast<Float4>(reinterpret_cast<Int4>(x) & 0x7fffffff);
}

// The correctly rounded square root per lane, as std::sqrt.
[[gnu::always_inline]] inline Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
  return reinterpret_cast<Float4>(_mm_sqrt_ps(reinterpret_cast<__m128>(x)));
#else
  return Float4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}

// Bit m set where lane m of a comparison's result is true (−1).
[[gnu::always_inline]] inline unsigned laneMask(Int4 m) {
#if defined(__SSE__)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
  return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
#endif
}

// Rows to columns: afterwards a holds the first lanes of a, b, c, d, b their second lanes, and
// so on.
[[gnu::always_inline]] inline void transpose4(Float4& a, Float4& b, Float4& c, Float4& d) {
  const Float4 ab_low = __builtin_shufflevector(a, b, 0, 4, 1, 5);
  const Float4 ab_high = __builtin_shufflevector(a, b, 2, 6, 3, 7);
  const Float4 cd_low = __builtin_shufflevector(c, d, 0, 4, 1, 5);
  const Float4 cd_high = __builtin_shufflevector(c, d, 2, 6, 3, 7);
  a = __builtin_shufflevector(ab_low, cd_low, 0, 1, 4, 5);
  b = __builtin_shufflevector(ab_low, cd_low, 2, 3, 6, 7);
  c = __builtin_shufflevector(ab_high, cd_high, 0, 1, 4, 5);
  d = __builtin_shufflevector(ab_high, cd_high, 2, 3, 6, 7);
}

}  // namespace svr
