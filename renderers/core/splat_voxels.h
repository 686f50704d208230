#pragma once
// The view-independent half of splatting, built once per classification and cached on it
// (ClassifiedVolume::derived): the list of voxels that scatter or absorb — so empty space costs
// nothing on any later frame — with their classification entries, the per-unit-length
// extinction tables, and the shading field averaged over the cells of the dual grid, from which
// each frame takes a splat's shade.
//
// Post-classified splatting reconstructs the value between voxels and classifies it there, so it
// needs more than the voxels that are visible themselves: every voxel whose neighbourhood
// (3 × 3 × 3) spans a visible value. That takes in the empty voxels around a visible one — whose
// values make the reconstructed field fall off at a boundary instead of ending at the last
// visible voxel — and pairs of empty voxels a thin visible value range lies between, which the
// raycaster's interpolation finds and voxel-centre classification misses.

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "renderers/core/classification.h"

namespace svr::splat {

struct SplatVoxel {
  std::uint32_t index;  // x + y·nx + z·nx·ny
  std::uint16_t entry;  // classification entry (and entry + 1, weighted by frac)
  float frac;
};

// The coordinates of voxel indices taken in ascending order (a splat list is in index order),
// mostly without dividing: the next index in the same row is the last one's x plus the step,
// and only a voxel that starts another row is divided out. Three integer divisions a voxel
// took about 10 ns here, a tenth of a direct splat frame at 512² for the engine's 4 M voxels
// (projection and shading each decomposed every index). Any order is correct (a step back
// wraps to a large unsigned step, which divides); ascending is what makes it cheap.
class VoxelWalker {
 public:
  explicit VoxelWalker(const Dims& dims)
      : nx_(static_cast<std::uint32_t>(dims[0])), ny_(static_cast<std::uint32_t>(dims[1])) {}
  // (x, y, z) of `index`.
  std::array<int, 3> at(std::uint32_t index) {
    const std::uint32_t step = index - last_;
    if (step < row_left_) {
      x_ += step;
      row_left_ -= step;
    } else {
      const std::uint32_t row = index / nx_;
      x_ = index - row * nx_;
      y_ = row % ny_;
      z_ = row / ny_;
      row_left_ = nx_ - x_;
    }
    last_ = index;
    return {static_cast<int>(x_), static_cast<int>(y_), static_cast<int>(z_)};
  }

 private:
  std::uint32_t nx_, ny_;
  std::uint32_t last_ = 0, row_left_ = 0;  // 0: the first index divides
  std::uint32_t x_ = 0, y_ = 0, z_ = 0;
};

class SplatVoxels {
 public:
  enum class Set { kVisible, kReconstruction };
  SplatVoxels(const ClassifiedVolume& volume, Set set);
  // The classification's instance, built on first use.
  static std::shared_ptr<const SplatVoxels> of(const ClassifiedVolume& volume,
                                               Set set = Set::kVisible);

  std::span<const SplatVoxel> voxels() const { return voxels_; }
  // Per entry and per world unit: the extinction that scatters, and (× kt) that attenuates.
  const std::vector<float>& sigmaAlpha() const { return sigma_alpha_; }
  const std::vector<float>& sigmaT() const { return sigma_t_; }
  // Gradient (world units) of the shading field at the dual-grid node (i, j, k), i in
  // [0, nx]: the corner (i − ½, j − ½, k − ½) of the voxel grid, where the raycaster's
  // central difference of the trilinear field takes exactly these cell averages.
  void gradientAtNode(int i, int j, int k, float g[3]) const;
  // The cell means themselves, x fastest: the gl backend uploads them as a 3D texture.
  std::span<const float> cellMeans() const { return cell_mean_; }

 private:
  float node(int i, int j, int k) const {
    return cell_mean_[(static_cast<std::size_t>(k) * (dims_[1] + 1) + j) * (dims_[0] + 1) + i];
  }
  Dims dims_;
  float inv_spacing_[3];
  std::vector<SplatVoxel> voxels_;
  std::vector<float> sigma_alpha_, sigma_t_;
  std::vector<float> cell_mean_;  // (nx + 1)(ny + 1)(nz + 1): mean of the ≤ 8 voxels around
};

}  // namespace svr::splat
