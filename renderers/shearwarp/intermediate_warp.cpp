#include "renderers/shearwarp/intermediate_warp.h"

#include <algorithm>
#include <cmath>

#include "renderers/simd/channel_widths.h"
#include "renderers/simd/float4.h"

namespace svr::shearwarp {

IntermediateImage::IntermediateImage(int w, int h, int s, int t) {
  resize(w, h, s, t);
  clearRows(0, h);
}

void IntermediateImage::resize(int w, int h, int s, int t) {
  const bool same = w == width && h == height && s == s_channels && t == t_channels;
  width = w, height = h, s_channels = s, t_channels = t, stride = strideFor(s, t);
  data.resize(static_cast<std::size_t>(w) * h * stride + kSlack);
  // Pixels in another layout: every column of every row for clearRows to empty.
  if (!same) touchAll();
}

void IntermediateImage::touchAll() {
  touched_begin.assign(height, 0);
  touched_end.assign(height, width);
}

bool IntermediateImage::touchedWithin(int u0, int u1, int v0, int v1) const {
  u0 = std::max(u0, 0), v0 = std::max(v0, 0);
  u1 = std::min(u1, width - 1), v1 = std::min(v1, height - 1);
  for (int v = v0; v <= v1; ++v)
    if (touched_begin[v] <= u1 && touched_end[v] > u0) return true;
  return false;
}

void IntermediateImage::clearRows(int v0, int v1) {
  // One empty pixel (S = 0, T = 1, padding 0), copied four floats at a time: filling each
  // pixel's channels in turn took a memset call for every three floats. Only the touched
  // columns: the rest of each row is empty still.
  std::vector<float> empty(stride, 0.f);
  std::fill_n(empty.begin() + s_channels, t_channels, 1.f);
  for (int v = v0; v < v1; ++v) {
    float* d = pixel(touched_begin[v], v);
    for (int u = touched_begin[v]; u < touched_end[v]; ++u, d += stride)
      for (int c = 0; c < stride; c += 4) store4(d + c, load4(empty.data() + c));
    touched_begin[v] = width, touched_end[v] = 0;
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

// Whether any tap of the output pixels [x0, x1) of the rows whose warped coordinates start at
// (u_first, v_first) and (u_last, v_last) (a tile's first and last rows) lies in a pixel that
// compositing touched. The taps of a pixel at (u, v) are floor(u) and floor(u) + 1 along u
// (and so along v), and the coordinates are affine in x and y, so the tile's four corners
// bound them.
bool tileTouched(const IntermediateImage& im, const ShearWarpFactorization& f, double u_first,
                 double v_first, double u_last, double v_last, int x0, int x1) {
  const double a = f.warp_u[1] * (x0 + 0.5), b = f.warp_u[1] * (x1 - 0.5);
  const double c = f.warp_v[1] * (x0 + 0.5), d = f.warp_v[1] * (x1 - 0.5);
  const double u_lo = std::min({u_first + a, u_first + b, u_last + a, u_last + b});
  const double u_hi = std::max({u_first + a, u_first + b, u_last + a, u_last + b});
  const double v_lo = std::min({v_first + c, v_first + d, v_last + c, v_last + d});
  const double v_hi = std::max({v_first + c, v_first + d, v_last + c, v_last + d});
  // One pixel of margin on each side absorbs rounding in the stepped coordinates.
  const auto lo = [](double q) { return static_cast<int>(std::floor(q)) - 1; };
  const auto hi = [](double q) { return static_cast<int>(std::floor(q)) + 2; };
  if (!(u_hi >= -2.0 && v_hi >= -2.0 && u_lo < im.width + 1 && v_lo < im.height + 1))
    return false;  // wholly outside: every tap is empty space
  return im.touchedWithin(lo(std::max(u_lo, -2.0)), hi(std::min(u_hi, im.width + 1.0)),
                          lo(std::max(v_lo, -2.0)), hi(std::min(v_hi, im.height + 1.0)));
}

// warpToFinal for an image of N channels (S and T), fixed at compile time for the channel
// counts the kernels are compiled for (channel_widths.h), so that the per-pixel loop over
// channels and planes unrolls; N = 0: any count. The same arithmetic either way.
template <int N>
bool warpTiles(const IntermediateImage& im, const ShearWarpFactorization& f,
               LightIndependentImage& out) {
  const int channels = N > 0 ? N : im.channels();
  const std::size_t pixels = out.pixels();
  float* planes = out.planeFloat(0).data();
  const int width = out.width(), height = out.height();
  // Empty space, for taps outside the intermediate image (padded as the image is, so that it
  // too may be read four channels at a time).
  std::vector<float> empty(im.stride + IntermediateImage::kSlack, 0.f);
  std::fill(empty.begin() + im.s_channels, empty.begin() + channels, 1.f);
  const std::size_t row_stride = static_cast<std::size_t>(im.width) * im.stride;
  // Output pixel `at` from four taps: their channels blended four at a time; the lanes past
  // the last channel read the pixel's padding and are not stored. Lanes whose exponent bits
  // are all set (NaN, ±Inf) are marked in `bad`.
  const auto blend = [&](std::size_t at, const float* p00, const float* p10, const float* p01,
                         const float* p11, float fu, float fv, Int4& bad) {
    const Float4 fu4 = splat4(fu), fv4 = splat4(fv);
    for (int c = 0; c < channels; c += 4) {
      // Bilinear as three lerps: along u in both rows, then along v.
      const Float4 a0 = load4(p00 + c), a1 = load4(p10 + c);
      const Float4 b0 = load4(p01 + c), b1 = load4(p11 + c);
      const Float4 top = a0 + fu4 * (a1 - a0), bottom = b0 + fu4 * (b1 - b0);
      const Float4 sum = top + fv4 * (bottom - top);
      bad |= (reinterpret_cast<Int4>(sum) & 0x7f800000) == 0x7f800000;
      for (int lane = 0; lane < std::min(4, channels - c); ++lane)
        planes[(c + lane) * pixels + at] = sum[lane];
    }
  };

  // Tiles of kTileRows × kTileColumns output pixels: under rotation a row of output pixels
  // walks across the intermediate image's rows, touching a new cache line at most steps, and
  // the next output row reuses those lines only a whole row later; within a tile they are
  // reused while they are still in the first-level cache.
  constexpr int kTileRows = 8, kTileColumns = 32;
  const int row_blocks = (height + kTileRows - 1) / kTileRows;
  unsigned any_bad = 0;
#pragma omp parallel for schedule(static) reduction(| : any_bad)
  for (int block = 0; block < row_blocks; ++block) {
    const int y0 = block * kTileRows, y1 = std::min(y0 + kTileRows, height);
    Int4 bad{0, 0, 0, 0};
    int inner0[kTileRows], inner1[kTileRows];
    double u_row[kTileRows], v_row[kTileRows];
    for (int y = y0; y < y1; ++y) {
      const double py = y + 0.5;
      interiorRange(f, im, py, width, inner0[y - y0], inner1[y - y0]);
      // Along a row the warped coordinates are linear in px.
      u_row[y - y0] = f.warp_u[0] + f.warp_u[2] * py;
      v_row[y - y0] = f.warp_v[0] + f.warp_v[2] * py;
    }
    for (int x0 = 0; x0 < width; x0 += kTileColumns) {
      const int x1 = std::min(x0 + kTileColumns, width);
      if (!tileTouched(im, f, u_row[0], v_row[0], u_row[y1 - 1 - y0], v_row[y1 - 1 - y0], x0,
                       x1)) {
        // Every tap is empty space, and so is every pixel the tile would blend from them.
        for (int c = 0; c < channels; ++c)
          for (int y = y0; y < y1; ++y)
            std::fill(planes + c * pixels + static_cast<std::size_t>(y) * width + x0,
                      planes + c * pixels + static_cast<std::size_t>(y) * width + x1, empty[c]);
        continue;
      }
      for (int y = y0; y < y1; ++y) {
        const int r = y - y0;
        const std::size_t row_index = static_cast<std::size_t>(y) * width;
        const int begin = std::clamp(inner0[r], x0, x1);
        const int end = std::clamp(inner1[r], begin, x1);
        // The border pixels, with every tap checked.
        const auto border = [&](int x) {
          const double px = x + 0.5;
          const double u = u_row[r] + f.warp_u[1] * px, v = v_row[r] + f.warp_v[1] * px;
          if (!(u >= -1.0 && v >= -1.0 && u < im.width && v < im.height)) {  // no tap inside
            for (int c = 0; c < channels; ++c) planes[c * pixels + row_index + x] = empty[c];
            return;
          }
          const double uf = std::floor(u), vf = std::floor(v);
          const int u0 = static_cast<int>(uf), v0 = static_cast<int>(vf);
          const auto tap = [&](int uu, int vv) {
            return uu >= 0 && vv >= 0 && uu < im.width && vv < im.height ? im.pixel(uu, vv)
                                                                          : empty.data();
          };
          blend(row_index + x, tap(u0, v0), tap(u0 + 1, v0), tap(u0, v0 + 1),
                tap(u0 + 1, v0 + 1), static_cast<float>(u - uf), static_cast<float>(v - vf),
                bad);
        };
        for (int x = x0; x < begin; ++x) border(x);
        for (int x = end; x < x1; ++x) border(x);
        // Inside: all four taps in the image and both coordinates ≥ 0, so truncation is the
        // floor (std::floor is a libm call on the baseline x86-64 target). Stepped along the
        // segment from its first pixel (two additions a pixel instead of a conversion, two
        // multiplications and two additions; over at most kTileColumns steps the sums stay
        // within 1e-13 voxel of the products).
        double u = u_row[r] + f.warp_u[1] * (begin + 0.5);
        double v = v_row[r] + f.warp_v[1] * (begin + 0.5);
        for (int x = begin; x < end; ++x, u += f.warp_u[1], v += f.warp_v[1]) {
          const int iu = static_cast<int>(u), iv = static_cast<int>(v);
          const float* p00 = im.pixel(iu, iv);
          const float* p01 = p00 + row_stride;
          blend(row_index + x, p00, p00 + im.stride, p01, p01 + im.stride,
                static_cast<float>(u - iu), static_cast<float>(v - iv), bad);
        }
      }
    }
    any_bad |= laneMask(bad);
  }
  return any_bad == 0;
}

}  // namespace

bool warpToFinal(const IntermediateImage& im, const ShearWarpFactorization& f,
                 LightIndependentImage& out) {
  const bool spectral_t = im.t_channels > 1;
  return pickWidth(im.s_channels, false, [&]<int K>() {
    constexpr int kScalar = K > 0 ? K + 1 : 0, kSpectral = 2 * K;
    return spectral_t ? warpTiles<kSpectral>(im, f, out) : warpTiles<kScalar>(im, f, out);
  });
}

}  // namespace svr::shearwarp
