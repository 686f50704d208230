#pragma once
// How a file's voxel axes become svr's (x, y, z) when the file states an orientation (NIfTI's
// sform/qform, DICOM's image orientation and slice positions). svr grids have no direction
// matrix (volume.h: axis-aligned, centred), so such files are turned to the closest canonical
// frame, RAS+ (x towards the patient's right… NIfTI's "x increases to the right" is +R, y to
// anterior, z to superior), by permuting and flipping axes only: no voxel is resampled. An
// oblique grid keeps its nearest axes, and the description says how far off it was.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "renderers/volume/brick_box.h"
#include "renderers/volume/volume_io.h"

namespace svr {

struct AxisMap {
  // Output axis a is the file's axis file_axis[a], run backwards when flip[a].
  std::array<int, 3> file_axis{0, 1, 2};
  std::array<bool, 3> flip{false, false, false};

  bool identity() const;
  Dims outputDims(const Dims& file_dims) const;
  glm::dvec3 outputSpacing(const glm::dvec3& file_spacing) const;
  // The file's voxels that make up `out_box` of the output grid (a box too).
  VoxelBox fileBox(const VoxelBox& out_box, const Dims& file_dims) const;
  // The file's indices, ascending per file axis, of an output lattice.
  LatticeIndices fileLattice(const LatticeIndices& out, const Dims& file_dims) const;
  // Voxels of a file-order box of `file_size` (x fastest, `width` bytes each) in output order.
  std::vector<std::byte> reorder(const std::vector<std::byte>& file_order, const Dims& file_size,
                                 std::size_t width) const;
};

// The axis map that turns a grid whose file axes i, j, k point along the columns of
// `directions` (world RAS+, any length) into RAS+, and the largest angle in degrees between a file
// axis and the world axis it became (0 for a grid that is not oblique). Throws svr::Error naming
// `source` for a singular matrix or two file axes nearest the same world axis.
struct OrientedAxes {
  AxisMap map;
  double oblique_degrees = 0.0;
  std::string file_axes;  // "LPS", "RAS", …: where the file's i, j, k point
};
OrientedAxes axesToRas(const std::array<glm::dvec3, 3>& directions, const std::string& source);

}  // namespace svr
