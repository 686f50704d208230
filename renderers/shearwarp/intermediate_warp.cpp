#include "renderers/shearwarp/intermediate_warp.h"

#include <algorithm>
#include <cmath>

namespace svr::shearwarp {

IntermediateImage::IntermediateImage(int w, int h, int s, int t) { reset(w, h, s, t); }

void IntermediateImage::reset(int w, int h, int s, int t) {
  width = w, height = h, s_channels = s, t_channels = t;
  data.resize(static_cast<std::size_t>(w) * h * (s + t));
  float* d = data.data();
  for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p, d += s + t) {
    std::fill_n(d, s, 0.f);
    std::fill_n(d + s, t, 1.f);
  }
}

namespace {

// The x range of row py whose four taps all lie inside the intermediate image: there the warp
// needs no bounds checks. Coordinates are linear in px along the row.
void interiorRange(const ShearWarpFactorization& f, const IntermediateImage& im, double py,
                   int width, int& x0, int& x1) {
  x0 = 0, x1 = width;
  const auto clip = [&](const double* w, double hi) {
    // Want 0 ≤ floor(c) and floor(c) + 1 ≤ hi − 1, i.e. 0 ≤ c < hi − 1, with c = a + b·px.
    const double a = w[0] + w[2] * py, b = w[1];
    if (std::abs(b) < 1e-12) {
      if (!(a >= 0.0 && a < hi - 1)) x1 = x0;
      return;
    }
    double lo = (0.0 - a) / b - 0.5, up = (hi - 1 - a) / b - 0.5;  // px = x + 0.5
    if (b < 0) std::swap(lo, up);
    // A margin of one pixel on each side absorbs rounding; those pixels take the checked path.
    x0 = std::max(x0, static_cast<int>(std::ceil(lo)) + 1);
    x1 = std::min(x1, static_cast<int>(std::floor(up)) - 1);
  };
  clip(f.warp_u, im.width);
  clip(f.warp_v, im.height);
  if (x1 < x0) x1 = x0 = 0;
}

}  // namespace

void warpToFinal(const IntermediateImage& im, const ShearWarpFactorization& f,
                 LightIndependentImage& out) {
  const int channels = im.channels();
  const std::size_t pixels = out.pixels();
  float* planes = out.planeFloat(0).data();
  const int width = out.width(), height = out.height();
  // Empty space, for taps outside the intermediate image.
  std::vector<float> empty(channels, 0.f);
  std::fill(empty.begin() + im.s_channels, empty.end(), 1.f);
  const std::size_t row_stride = static_cast<std::size_t>(im.width) * channels;

#pragma omp parallel for schedule(static)
  for (int y = 0; y < height; ++y) {
    const double py = y + 0.5;
    int inner0, inner1;
    interiorRange(f, im, py, width, inner0, inner1);
    for (int x = 0; x < width; ++x) {
      const double px = x + 0.5;
      const double u = f.warp_u[0] + f.warp_u[1] * px + f.warp_u[2] * py;
      const double v = f.warp_v[0] + f.warp_v[1] * px + f.warp_v[2] * py;
      const double uf = std::floor(u), vf = std::floor(v);
      const float fu = static_cast<float>(u - uf), fv = static_cast<float>(v - vf);
      const float w00 = (1 - fu) * (1 - fv), w10 = fu * (1 - fv), w01 = (1 - fu) * fv,
                  w11 = fu * fv;
      const std::size_t px_index = static_cast<std::size_t>(y) * width + x;
      const float *p00, *p10, *p01, *p11;
      if (x >= inner0 && x < inner1) {
        p00 = im.pixel(static_cast<int>(uf), static_cast<int>(vf));
        p10 = p00 + channels;
        p01 = p00 + row_stride;
        p11 = p01 + channels;
      } else {
        // Far outside: avoid int overflow, it is empty anyway.
        const bool inside = uf > -2 && vf > -2 && uf < im.width + 1 && vf < im.height + 1;
        const int u0 = inside ? static_cast<int>(uf) : -2, v0 = inside ? static_cast<int>(vf) : -2;
        const auto tap = [&](int uu, int vv) {
          return uu >= 0 && vv >= 0 && uu < im.width && vv < im.height ? im.pixel(uu, vv)
                                                                        : empty.data();
        };
        p00 = tap(u0, v0), p10 = tap(u0 + 1, v0), p01 = tap(u0, v0 + 1), p11 = tap(u0 + 1, v0 + 1);
      }
      for (int c = 0; c < channels; ++c)
        planes[c * pixels + px_index] =
            w00 * p00[c] + w10 * p10[c] + w01 * p01[c] + w11 * p11[c];
    }
  }
}

}  // namespace svr::shearwarp
