#pragma once
// The intermediate image of shear-warp (every channel: k of S, then 1 or k of T, interleaved
// per pixel so compositing touches one cache line per pixel) and the 2D affine warp that
// resamples it, bilinearly, into the final light-independent image.

#include <vector>

#include "renderers/shearwarp/shear_warp_factorization.h"
#include "spectral/light_independent_image.h"

namespace svr::shearwarp {

struct IntermediateImage {
  IntermediateImage(int width, int height, int s_channels, int t_channels);
  // Empty again at this size, reusing the storage (no fresh pages to fault in and zero).
  void reset(int width, int height, int s_channels, int t_channels);
  int width, height, s_channels, t_channels;
  int channels() const { return s_channels + t_channels; }
  float* pixel(int u, int v) {
    return data.data() + (static_cast<std::size_t>(v) * width + u) * channels();
  }
  const float* pixel(int u, int v) const {
    return data.data() + (static_cast<std::size_t>(v) * width + u) * channels();
  }
  // Floats past the last pixel, so that the warp may read any pixel's channels four at a time.
  static constexpr int kSlack = 3;
  std::vector<float> data;  // starts empty: S = 0, T = 1 (then kSlack floats of slack)
};

// Every final pixel takes the bilinear interpolation of the intermediate pixels around its
// warped centre; pixels outside the intermediate image are empty space (S = 0, T = 1), as the
// raycaster leaves rays that miss the volume.
void warpToFinal(const IntermediateImage& intermediate, const ShearWarpFactorization& f,
                 LightIndependentImage& out);

}  // namespace svr::shearwarp
