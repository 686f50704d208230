#pragma once
// Shear-warp's compositing as the renderer sees it: the slice table, one band's job, and per
// instruction set the kernel for a channel count, transmittance and classification mode
// (shearwarp_kernel.h holds the loop; shearwarp_kernel_portable.cpp and
// shearwarp_kernel_avx2.cpp compile it, as the raycaster's kernels are compiled).

#include <cmath>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/shearwarp/intermediate_warp.h"
#include "renderers/shearwarp/preclassified_axis.h"
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shear_warp_factorization.h"

namespace svr::shearwarp {

inline constexpr int kMaxChannels = 128;

// Per entry, for the slice spacing: [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}], rows
// padded to a multiple of 4 floats (raycast/sample_table.h's layout for this backend's own
// opacity correction).
// The kernel reads a row's channels four at a time from any channel on (lanes past the row's
// last channel are not used), so the rows, and the white coefficients kept beside them, end
// with kSlack floats of slack.
struct SliceTable {
  static constexpr int strideFor(int width) { return (width + 3) / 4 * 4; }
  static constexpr int kSlack = 4;
  int stride = 0;
  std::vector<float> rows;
  std::vector<float> white;  // the classification's k white coefficients, then the slack
  // alpha, transmission: the classification's entries corrected for the slice spacing.
  SliceTable(const ClassifiedVolume& cv, const std::vector<float>& alpha,
             const std::vector<float>& transmission)
      : stride(strideFor(2 + cv.k + cv.t_channels)),
        rows(blendRows(cv, alpha.data(), transmission.data(), stride)),
        white(cv.white) {
    rows.resize(rows.size() + kSlack, 0.f);
    white.resize(white.size() + kSlack, 0.f);
  }
  const float* row(int e) const { return rows.data() + static_cast<std::size_t>(e) * stride; }
};

struct CompositeJob {
  const ClassifiedVolume* volume;
  const AxisEncoding* encoding;
  const ShearWarpFactorization* view;
  const SliceTable* table;
  float threshold;
  PhongSetup phong;  // light and half vectors are unit, world
  IntermediateImage* image;
  // Pre-classified mode only (preclassified_axis.h): the classified records, the view's shading
  // table and the slice-spacing corrections x ↦ x^r of 1 − α and of t.
  const PreclassifiedAxis* pre = nullptr;
  const ShadingTable* shading = nullptr;
  const PowerTable* opacity_power = nullptr;
  const PowerTable* transmission_power = nullptr;
  // A brick of a distributed render (volume/brick_box.h): the view is the whole grid's; slices
  // and in-slice positions are placed by the brick's origin (the index of its first stored
  // voxel), and only its own samples are taken — slices [slice_begin, slice_end) of the
  // encoding and in-slice positions within [lo, hi) (whole-grid voxel coordinates, open to ±∞
  // at the grid's faces). A whole volume: origin 0, every slice, no bounds.
  int origin[3] = {0, 0, 0};
  double lo[3] = {-INFINITY, -INFINITY, -INFINITY}, hi[3] = {INFINITY, INFINITY, INFINITY};
  int slice_begin = 0, slice_end = 0;
};

// Composites intermediate scanlines [v0, v1) through every slice; `links` is the caller's
// scratch (one per thread).
using BandFn = void (*)(const CompositeJob&, int v0, int v1, std::vector<int>& links);

// What selects a kernel: channels, spectral transmittance, pre-classified records, and whether
// to take the dynamic-k path even where a fixed width is compiled (tests compare the two).
struct KernelKey {
  int k = 3;
  bool spectral_t = false, pre = false, dynamic_width = false;
};

namespace portable {
BandFn pick(const KernelKey& key);
}
namespace avx2 {
bool compiled();
BandFn pick(const KernelKey& key);
}

}  // namespace svr::shearwarp
