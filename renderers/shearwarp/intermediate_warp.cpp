#include "renderers/shearwarp/intermediate_warp.h"

#include <algorithm>
#include <cmath>

namespace svr::shearwarp {

IntermediateImage::IntermediateImage(int w, int h, int s, int t)
    : width(w), height(h), s_channels(s), t_channels(t) {
  data.assign(static_cast<std::size_t>(w) * h * (s + t), 0.f);
  for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p)
    std::fill_n(data.data() + p * (s + t) + s, t, 1.f);
}

void warpToFinal(const IntermediateImage& im, const ShearWarpFactorization& f,
                 LightIndependentImage& out) {
  const int channels = im.channels();
  const std::size_t pixels = out.pixels();
  float* planes = out.planeFloat(0).data();
  const int width = out.width(), height = out.height();
  // Empty space, for taps outside the intermediate image.
  std::vector<float> empty(channels, 0.f);
  std::fill(empty.begin() + im.s_channels, empty.end(), 1.f);

#pragma omp parallel for schedule(static)
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double u = f.warp_u[0] + f.warp_u[1] * px + f.warp_u[2] * py;
      const double v = f.warp_v[0] + f.warp_v[1] * px + f.warp_v[2] * py;
      const double uf = std::floor(u), vf = std::floor(v);
      const float fu = static_cast<float>(u - uf), fv = static_cast<float>(v - vf);
      // Far outside: avoid int overflow, it is empty anyway.
      const bool inside = uf > -2 && vf > -2 && uf < im.width + 1 && vf < im.height + 1;
      const int u0 = inside ? static_cast<int>(uf) : -2, v0 = inside ? static_cast<int>(vf) : -2;
      const auto tap = [&](int uu, int vv) {
        return uu >= 0 && vv >= 0 && uu < im.width && vv < im.height ? im.pixel(uu, vv)
                                                                      : empty.data();
      };
      const float* p00 = tap(u0, v0);
      const float* p10 = tap(u0 + 1, v0);
      const float* p01 = tap(u0, v0 + 1);
      const float* p11 = tap(u0 + 1, v0 + 1);
      const float w00 = (1 - fu) * (1 - fv), w10 = fu * (1 - fv), w01 = (1 - fu) * fv,
                  w11 = fu * fv;
      const std::size_t px_index = static_cast<std::size_t>(y) * width + x;
      for (int c = 0; c < channels; ++c)
        planes[c * pixels + px_index] =
            w00 * p00[c] + w10 * p10[c] + w01 * p01[c] + w11 * p11[c];
    }
  }
}

}  // namespace svr::shearwarp
