// Portable (baseline x86-64 / any architecture) instantiation of the relight kernel, and the
// run-time choice between it and the AVX2 one.
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "spectral/relight_kernel.h"

namespace svr {
namespace relight_avx2 {
RelightFn pickKernelAvx2(int planes, SampleStorage storage, RelitEncoding encoding);
bool compiled();
}  // namespace relight_avx2

namespace relight_generic {
namespace {
inline void loadHalfChunk(const std::uint16_t* src, float* dst, int n) {
  for (int i = 0; i < n; ++i) dst[i] = halfToFloat(src[i]);
}
#include "spectral/relight_kernel_body.inc"
}  // namespace
}  // namespace relight_generic

RelightKernelChoice selectRelightKernel(int planes, SampleStorage storage,
                                        RelitEncoding encoding, KernelForce force) {
  const bool fixed = planes >= 1 && planes <= 16 && !force.dynamic_width;
  const int width = fixed ? planes : 0;  // 0 selects the dynamic path
#if defined(__x86_64__) || defined(__i386__)
  static const bool avx2 = relight_avx2::compiled() && __builtin_cpu_supports("avx2") &&
                           __builtin_cpu_supports("f16c") && __builtin_cpu_supports("fma");
  if (avx2 && !force.portable)
    return {relight_avx2::pickKernelAvx2(width, storage, encoding), "avx2", fixed};
#endif
  return {relight_generic::pickKernel(width, storage, encoding), "x86-64", fixed};
}

}  // namespace svr
