#pragma once
// Table-driven linear → 8-bit sRGB encoding, the portable path of the relight kernel (and the
// tail of the vector one). The table has kSrgbLutSize entries over linear [0, 1].

#include <algorithm>
#include <cstdint>

#include "spectral/relight_kernel.h"

namespace svr {

inline void encodeSrgbWithTable(const float* r, const float* g, const float* b, int n,
                                std::uint8_t* out, const std::uint8_t* lut) {
  const float scale = static_cast<float>(kSrgbLutSize - 1);
  for (int i = 0; i < n; ++i) {
    const float rgb[3] = {r[i], g[i], b[i]};
    for (int c = 0; c < 3; ++c) {
      const float v = std::min(std::max(rgb[c], 0.f), 1.f);
      out[3 * i + c] = lut[static_cast<int>(v * scale + 0.5f)];
    }
  }
}

}  // namespace svr
