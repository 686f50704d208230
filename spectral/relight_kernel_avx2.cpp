// AVX2 + F16C + FMA instantiation of the relight kernel (this file is compiled with
// -mavx2 -mf16c -mfma; selectRelightKernel only calls it on CPUs that have them).
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "spectral/relight_kernel.h"

#if defined(__AVX2__) && defined(__F16C__)
#include <immintrin.h>
#endif

namespace svr::relight_avx2 {

#if defined(__AVX2__) && defined(__F16C__)
namespace {
inline void loadHalfChunk(const std::uint16_t* src, float* dst, int n) {
  int i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(dst + i,
                     _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(src + i))));
  for (; i < n; ++i) dst[i] = _cvtsh_ss(src[i]);
}
#include "spectral/relight_kernel_body.inc"
}  // namespace

bool compiled() { return true; }
RelightFn pickKernelAvx2(int planes, SampleStorage storage, RelitEncoding encoding) {
  return pickKernel(planes, storage, encoding);
}
#else
bool compiled() { return false; }
RelightFn pickKernelAvx2(int, SampleStorage, RelitEncoding) { return nullptr; }
#endif

}  // namespace svr::relight_avx2
