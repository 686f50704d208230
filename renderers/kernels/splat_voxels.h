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

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "renderers/classification/classification.h"

namespace svr::splat {

struct SplatVoxel {
  std::uint32_t index;  // x + y·nx + z·nx·ny
  std::uint16_t entry;  // classification entry (and entry + 1, weighted by frac)
  float frac;
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
