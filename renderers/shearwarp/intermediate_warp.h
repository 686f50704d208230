#pragma once
// The intermediate image of shear-warp (every channel: k of S, then 1 or k of T, interleaved
// per pixel so compositing touches one cache line per pixel, and the pixel padded to a
// multiple of four floats, so that compositing takes S four channels at a time up to its last
// channel) and the 2D affine warp that resamples it, bilinearly, into the final
// light-independent image.

#include <algorithm>
#include <vector>

#include "renderers/memory/huge_pages.h"
#include "renderers/shearwarp/shear_warp_factorization.h"
#include "spectral/light_independent_image.h"

namespace svr::shearwarp {

struct IntermediateImage {
  IntermediateImage() = default;
  // An empty image (S = 0, T = 1).
  IntermediateImage(int width, int height, int s_channels, int t_channels);
  // This size, reusing the storage (no fresh pages to fault in and zero); the pixels are
  // unspecified until clearRows. A render clears each band's rows just before compositing
  // them, on the thread that composites them, instead of the whole image on one thread first.
  void resize(int width, int height, int s_channels, int t_channels);
  // Rows [v0, v1) empty again, rewriting only their touched columns (every column after a
  // resize to another layout): an image reused at one size clears only what the last frame
  // wrote.
  void clearRows(int v0, int v1);
  // Compositing wrote to pixels [u0, u1) of row v (or left them as they were): outside each
  // row's touched columns the row is still empty, and the warp fills what it reads only from
  // there without reading it.
  void touch(int v, int u0, int u1) {
    touched_begin[v] = std::min(touched_begin[v], u0);
    touched_end[v] = std::max(touched_end[v], u1);
  }
  // Every pixel possibly non-empty (pixels written other than by compositing).
  void touchAll();
  // Whether any pixel in columns [u0, u1] of rows [v0, v1] was touched (bounds inclusive,
  // clipped to the image).
  bool touchedWithin(int u0, int u1, int v0, int v1) const;
  int width = 0, height = 0, s_channels = 0, t_channels = 0;
  int stride = 0;  // floats a pixel: its channels and zeros up to a multiple of four
  int channels() const { return s_channels + t_channels; }
  static int strideFor(int s_channels, int t_channels) {
    return (s_channels + t_channels + 3) / 4 * 4;
  }
  float* pixel(int u, int v) {
    return data.data() + (static_cast<std::size_t>(v) * width + u) * stride;
  }
  const float* pixel(int u, int v) const {
    return data.data() + (static_cast<std::size_t>(v) * width + u) * stride;
  }
  // Floats past the last pixel, so that a pixel's T may be read four channels at a time.
  static constexpr int kSlack = 3;
  // Starts empty: S = 0, T = 1, padding 0 (then kSlack floats of slack). On huge pages: the
  // warp crosses its rows at most steps under rotation.
  std::vector<float, HugePageAllocator<float>> data;
  std::vector<int> touched_begin, touched_end;  // per row; begin ≥ end: untouched
};

// Every final pixel takes the bilinear interpolation of the intermediate pixels around its
// warped centre; pixels outside the intermediate image are empty space (S = 0, T = 1), as the
// raycaster leaves rays that miss the volume. Writes every sample of `out`; returns whether
// all of them are finite (checked as they are written, while in registers).
bool warpToFinal(const IntermediateImage& intermediate, const ShearWarpFactorization& f,
                 LightIndependentImage& out);

}  // namespace svr::shearwarp
