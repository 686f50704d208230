// Portable (baseline x86-64 / any architecture) instantiation of the relight kernel.
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "spectral/relight_kernel.h"
#include "spectral/srgb_table.h"

namespace svr {
namespace relight_portable {
namespace {
inline void loadHalfChunk(const std::uint16_t* src, float* dst, int n) {
  for (int i = 0; i < n; ++i) dst[i] = halfToFloat(src[i]);
}
inline void encodeSrgbChunk(const float* r, const float* g, const float* b, int n,
                            std::uint8_t* out, const std::uint8_t* lut) {
  encodeSrgbWithTable(r, g, b, n, out, lut);
}
#include "spectral/relight_kernel_body.inc"
}  // namespace

RelightFn pick(int width, SampleStorage storage, RelitEncoding encoding) {
  return pickKernel(width, storage, encoding);
}
}  // namespace relight_portable

}  // namespace svr

