#pragma once
// Run-length encoded classified voxels for shear-warp (Lacroute & Levoy 1994, §4): one encoding
// per principal axis, built once per classified volume (i.e. per transfer function, model and
// step) and reused for every view whose principal axis it is.
//
// For principal axis c the volume is cut into slices k along c; a slice has voxel rows j along
// axis_j, each row running along axis_i. Shear-warp samples bilinearly inside a slice, so a
// sample lies in one 2×2 *cell* (voxels i..i+1 × j..j+1). A cell is transparent when no value
// bilinearly interpolated from its four voxels can classify to a non-zero opacity (scalar
// volumes: the opacity table over the corners' value range; label maps: all four labels
// transparent). The encoding stores, per cell row, the runs of non-transparent cells (the
// transparent runs are the gaps between them and are never visited), and per voxel row the
// voxel records (bin coordinate or label, and the precomputed world-space gradient of the shading field)
// of the segments of voxels that non-transparent cells touch. Transparent space costs nothing.
//
// Samples between slices: an encoding may hold m slices per voxel along c (`slice_samples`),
// slice k·m + r lying at voxel position k + r/m. Its records are the two voxel slices' records
// interpolated linearly along c (value, hence bin coordinate, and gradient), so a bilinear
// sample inside it is the trilinear sample of the volume at that point: refining along the ray
// converges to the raycaster's sampling. The cells of such a slice are tested on its own
// interpolated keys, within the occupied blocks of voxel slice k (whose +1 border holds k + 1).
// Label maps cannot be interpolated, so they take m = 1 only.

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "renderers/memory/block_arena.h"
#include "renderers/classification/classification.h"

namespace svr::shearwarp {

struct VoxelRecord {
  // The voxel's bin coordinate (classified_sample.h's binCoordinate: linear in the value, so a
  // sample interpolates bins directly); label maps: its label number.
  float bin;
  float gradient[3];  // ∇ of the shading field, world units, central differences (as raycast)
};

// Non-transparent cells [begin, end) of cell row j, and where their voxels are stored: voxel i
// (begin ≤ i ≤ end) of voxel row j is record record0 + (i − begin) of the slice's records, of
// voxel row j + 1 record record1 + (i − begin). A sample takes its four corners from these two
// offsets, whatever segments the rows hold.
struct CellRun {
  std::int32_t begin, end;
  std::int32_t record0, record1;
};

// Voxels lo .. lo + count − 1 of a voxel row, stored at records offset .. offset + count − 1 of
// the slice. A row holds the voxels that the runs of the cell rows either side of it reach,
// merged into segments where they meet or overlap; the voxels between segments are not stored.
struct RowSegment {
  std::int32_t lo = 0, count = 0;
  std::int32_t offset = 0;
};

struct SliceEncoding {
  std::vector<std::int32_t> run_offsets;  // n_j: cell row j's runs are [off[j], off[j + 1])
  std::vector<CellRun> runs;
  // n_j + 1: voxel row j's segments are [segment_offsets[j], segment_offsets[j + 1]).
  std::vector<std::int32_t> segment_offsets;
  std::vector<RowSegment> segments;
  // n_j + 1: voxel row j's records are [row_first[j], row_first[j + 1]) (kept, not searched for:
  // the kernels ask for it once per scanline and slice).
  std::vector<std::int32_t> row_first;
  VoxelRecord* records = nullptr;       // record_count, in the axis encoding's arena
  std::size_t record_count = 0;
};

// The encoding for one principal axis.
class AxisEncoding {
 public:
  // slice_samples: m slices per voxel spacing along the axis (1: the voxel slices).
  AxisEncoding(const ClassifiedVolume& cv, int axis, int slice_samples = 1);

  int axis() const { return axis_; }
  int axisI() const { return axis_i_; }
  int axisJ() const { return axis_j_; }
  int slices() const { return n_k_; }     // (voxels along the axis − 1) · m + 1
  int sliceSamples() const { return m_; }
  int rowLength() const { return n_i_; }  // voxels along axis_i
  int rowCount() const { return n_j_; }   // voxel rows along axis_j

  // Non-transparent cell runs of cell row j (0 .. rowCount − 2) of slice k.
  std::span<const CellRun> runs(int k, int j) const {
    const SliceEncoding& s = slices_[k];
    return {s.runs.data() + s.run_offsets[j], s.runs.data() + s.run_offsets[j + 1]};
  }
  std::span<const RowSegment> segments(int k, int j) const {
    const SliceEncoding& s = slices_[k];
    return {s.segments.data() + s.segment_offsets[j], s.segments.data() + s.segment_offsets[j + 1]};
  }
  // Record of voxel i of row j of slice k, or nullptr where the row does not store it.
  const VoxelRecord* findVoxel(int k, int j, int i) const;
  // The first record of voxel row j (rows are stored one after the other, j rising).
  std::int32_t rowFirst(int k, int j) const { return slices_[k].row_first[j]; }
  // Slice k's records, row after row; a run's record0 / record1 index them.
  std::span<const VoxelRecord> sliceRecords(int k) const {
    return {slices_[k].records, slices_[k].record_count};
  }
  std::size_t bytes() const;
  std::size_t storedVoxels() const;

 private:
  int axis_, axis_i_, axis_j_, n_i_, n_j_, n_k_, m_;
  BlockArena records_;  // every slice's voxel records
  std::vector<SliceEncoding> slices_;
};

// The encodings of one classified volume, per axis and slice samples, each built on first use
// (thread-safe), so a render pays only for the one it needs and later views reuse it. Holds a
// reference: the classified volume must outlive it.
class RleVolume {
 public:
  static constexpr int kMaxSliceSamples = 8;
  explicit RleVolume(const ClassifiedVolume& cv);
  // The classification's instance (cached on it), so a series of views pays for each axis's
  // encoding once.
  static std::shared_ptr<const RleVolume> of(const ClassifiedVolume& cv);
  const ClassifiedVolume& classified() const { return cv_; }
  // slice_samples 1 … kMaxSliceSamples.
  const AxisEncoding& encoding(int axis, int slice_samples = 1) const;
  void buildAll() const;  // the three axes' voxel-slice encodings

 private:
  const ClassifiedVolume& cv_;
  mutable std::array<std::once_flag, 3 * kMaxSliceSamples> once_;
  mutable std::array<std::unique_ptr<AxisEncoding>, 3 * kMaxSliceSamples> axes_;
};

// Whether the cell with lower corner (x, y, z) in the plane of axes a and b (the other axis
// fixed) can hold a non-transparent sample: the criterion the encoding uses, exposed so tests
// can check the runs against it cell by cell.
bool cellOccupied(const ClassifiedVolume& cv, std::span<const int> nonzero_prefix, int x, int y,
                  int z, int a, int b);

}  // namespace svr::shearwarp
