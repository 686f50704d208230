#include "renderers/shearwarp/rle_volume.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <type_traits>

#include "renderers/classification/classified_sample.h"
#include "renderers/simd/float4.h"
#include "renderers/volume/volume.h"
#include "base/error.h"

namespace svr::shearwarp {
namespace {

std::size_t indexOf(const Dims& d, int x, int y, int z) {
  return (static_cast<std::size_t>(z) * d[1] + y) * d[0] + x;
}

// Where one principal axis's slices lie in the volume: voxel i of row j of slice k is at
// k · stride_k + j · stride_j + i · stride_i.
struct SliceLayout {
  int n_i, n_j, n_k;
  std::size_t stride_i, stride_j, stride_k;
};

// One slice of an array of the volume (float values or field, or 16-bit labels) as contiguous
// rows: row j starts at data + j · row_stride.
template <class T>
struct SliceRows {
  const T* data;
  std::size_t row_stride;
  const T* row(int j) const { return data + static_cast<std::size_t>(j) * row_stride; }
};

// Slices k0 − 1 .. k1 − 1 + after of an array (clamped to the volume), for the group of slices
// k0 .. k1 − 1 that one thread encodes (the neighbours give the gradient along the axis; slices
// between voxel slices, the next slice's too: after = 2). The rows of y and z
// slices run along x, contiguous in memory, and are read in place. The rows of x slices run
// along y, a volume row apart: read in place, every voxel would be a cache line of its own, read
// once per slice that holds it; gathered for the group at once, each line is read once.
//
// The gathered planes come from a block arena (memory/block_arena.h) kept per thread for the
// whole encoding: a 64-slice group of a 256³ volume is 17 MiB, allocated and faulted in once,
// not again for every group.
template <class T>
struct GatherBuffer {
  BlockArena arena;
  T* data = nullptr;
  std::size_t size = 0;
  T* get(std::size_t n) {
    if (n > size) data = arena.allocate<T>(n), size = n;
    return data;
  }
};

template <class T>
class SliceGroup {
 public:
  SliceGroup(const SliceLayout& layout, const T* array, int k0, int k1, GatherBuffer<T>& buffer,
             int after = 1)
      : layout_(layout), array_(array), first_(std::max(k0 - 1, 0)),
        last_(std::min(k1 - 1 + after, layout.n_k - 1)) {
    if (layout.stride_i == 1) return;
    const int count = last_ - first_ + 1;
    // Planes a cache line more than a slice apart: slices of power-of-two size would otherwise
    // map every plane's row to the same cache sets.
    plane_ = static_cast<std::size_t>(layout.n_i) * layout.n_j + 16;
    // Room for a whole group and both neighbours, which the first group (no slice before it)
    // does not use: the buffer is then sized once, not grown (and faulted in) again by the next.
    T* const planes = buffer.get((k1 - k0 + 1 + after) * plane_);
    // A transpose, in tiles of kTile voxels of a row by every slice of the group: each voxel's
    // slices are contiguous in the volume and its row neighbours a volume row apart, so a tile
    // reads kTile short contiguous runs and writes kTile-voxel runs of each slice.
    constexpr int kTile = 8;
    for (int j = 0; j < layout.n_j; ++j) {
      const T* from = array + j * layout.stride_j + first_ * layout.stride_k;
      T* to = planes + static_cast<std::size_t>(j) * layout.n_i;
      for (int i0 = 0; i0 < layout.n_i; i0 += kTile) {
        const int width = std::min(kTile, layout.n_i - i0);
        // The next tile's lines, which the hardware does not see coming.
        for (int i = i0 + kTile; i < std::min(i0 + 2 * kTile, layout.n_i); ++i)
          for (int n = 0; n < count; n += 16)
            __builtin_prefetch(from + i * layout.stride_i + n * layout.stride_k);
        for (int n = 0; n < count; ++n)
          for (int i = i0; i < i0 + width; ++i)
            to[n * plane_ + i] = from[i * layout.stride_i + n * layout.stride_k];
      }
    }
    gathered_ = planes;
  }
  SliceRows<T> slice(int k) const {
    k = std::clamp(k, 0, layout_.n_k - 1);
    if (!gathered_) return {array_ + k * layout_.stride_k, layout_.stride_j};
    return {gathered_ + (k - first_) * plane_, static_cast<std::size_t>(layout_.n_i)};
  }

 private:
  SliceLayout layout_;
  const T* array_;
  int first_, last_;
  const T* gathered_ = nullptr;
  std::size_t plane_ = 0;
};

// Which cells can hold a non-transparent sample, from each voxel's key: its bin coordinate
// (scalar volumes), or 1 for a visible label and 0 for a hidden one. A cell's samples blend the
// bins floor(min) .. ceil(max) of its corners' keys (clamped to the table); where the visible
// entries are one contiguous range [first, last] — most transfer functions — that range meets
// them exactly when max > first − 1 and min < last + 1, two comparisons a cell that vectorise.
// Otherwise the cells that pass are checked against the prefix of visible entries.
struct Visibility {
  bool any = false;
  float above = -INFINITY, below = INFINITY;  // visible: max > above and min < below
  bool contiguous = true;
  const ClassifiedVolume* classified;
  std::vector<int> prefix;  // nonzeroOpacityPrefix, for the non-contiguous case
  std::vector<float> label_key;  // label maps: each label's key (1 visible, 0 hidden)

  explicit Visibility(const ClassifiedVolume& cv) : classified(&cv) {
    if (cv.labels) {
      for (float a : cv.alpha) label_key.push_back(a > 0.f ? 1.f : 0.f);
      any = std::any_of(cv.alpha.begin(), cv.alpha.end(), [](float a) { return a > 0.f; });
      above = 0.f;
      return;
    }
    prefix = nonzeroOpacityPrefix(cv);
    const int last = cv.entries - 1;
    int first_visible = -1, last_visible = -1;
    for (int e = 0; e < cv.entries; ++e)
      if (cv.alpha[e] > 0.f) {
        if (first_visible < 0) first_visible = e;
        last_visible = e;
      }
    any = first_visible >= 0;
    if (!any) return;
    if (first_visible > 0) above = static_cast<float>(first_visible - 1);
    if (last_visible < last) below = static_cast<float>(last_visible + 1);
    contiguous =
        prefix[last_visible + 1] - prefix[first_visible] == last_visible - first_visible + 1;
  }

  // occupied[i] for the cells from ≤ i < to between key rows a and b.
  void cells(const float* a, const float* b, int from, int to, std::uint8_t* occupied) const {
    for (int i = from; i < to; ++i) {
      const float lo = std::min(std::min(a[i], a[i + 1]), std::min(b[i], b[i + 1]));
      const float hi = std::max(std::max(a[i], a[i + 1]), std::max(b[i], b[i + 1]));
      occupied[i] = (hi > above) & (lo < below);
    }
    if (contiguous) return;
    for (int i = from; i < to; ++i) {
      if (!occupied[i]) continue;
      const float lo = std::min(std::min(a[i], a[i + 1]), std::min(b[i], b[i + 1]));
      const float hi = std::max(std::max(a[i], a[i + 1]), std::max(b[i], b[i + 1]));
      occupied[i] = binRangeVisible(*classified, prefix, lo, hi);
    }
  }
};

// The runs of occupied cells from ≤ i < cells of one cell row (bytes 0 or 1), eight cells at a
// time through stretches that are all transparent or all occupied.
void appendRuns(const std::uint8_t* occupied, int from, int cells, std::vector<CellRun>& runs) {
  constexpr std::uint64_t kNone = 0, kAll = 0x0101010101010101ull;
  const auto eight = [&](int i) {
    std::uint64_t word;
    std::memcpy(&word, occupied + i, sizeof word);
    return word;
  };
  for (int i = from; i < cells;) {
    if (i + 8 <= cells && eight(i) == kNone) {
      i += 8;
      continue;
    }
    if (!occupied[i]) {
      ++i;
      continue;
    }
    const int begin = i;
    while (i + 8 <= cells && eight(i) == kAll) i += 8;
    while (i < cells && occupied[i]) ++i;
    runs.push_back({begin, i, 0, 0});  // records placed by storeSegments
  }
}

// The cells of a slice that can hold anything, by the classification's occupied blocks
// (ClassifiedVolume::kBlock³ voxels with their +1 border, so that every cell of a slice lies in
// one): per block row, kBlock cell rows, the stretches of occupied blocks as cell ranges. Only
// these are tested cell by cell; most of a CT is air.
struct ActiveCells {
  struct Range {
    int begin, end;  // cells [begin, end)
  };
  std::vector<std::int32_t> offsets;  // block row b's ranges are [offsets[b], offsets[b + 1])
  std::vector<Range> ranges;

  std::span<const Range> of(int block_row) const {
    return {ranges.data() + offsets[block_row], ranges.data() + offsets[block_row + 1]};
  }
};

// What one thread keeps between the slices it encodes.
struct EncoderScratch {
  ActiveCells active;
  std::vector<float> keys;          // the slice's keys, row after row
  std::vector<std::uint8_t> occupied;  // one cell row
  GatherBuffer<float> values, field;   // SliceGroup's gathered slices
  GatherBuffer<std::uint16_t> label_planes;
  std::vector<VoxelRecord> next_records;  // a segment's records in the next voxel slice
  BlockArena records;                  // the records of the slices this thread encodes
};

// Everything a slice's encoding reads.
struct SliceSource {
  const ClassifiedVolume& cv;
  const SliceLayout& layout;
  int axis, axis_i, axis_j;
  const Visibility& visibility;
};

// The voxel records of one segment of row j of slice k, voxels lo .. lo + count − 1: the bin
// coordinate (or label number, from `bins`: the row's keys, or its 16-bit labels) and the central
// differences of the shading field, clamped at the border as the raycaster's, in world units.
template <class Bin>
void fillRowRecords(const SliceSource& src, const SliceGroup<float>& field, const Bin* bins,
                    int k, int j, const RowSegment& span, VoxelRecord* out) {
  const SliceLayout& l = src.layout;
  const double* sp = &src.cv.spacing.x;
  const float h_i = static_cast<float>(0.5 / sp[src.axis_i]);
  const float h_j = static_cast<float>(0.5 / sp[src.axis_j]);
  const float h_k = static_cast<float>(0.5 / sp[src.axis]);
  const SliceRows here = field.slice(k);
  const float* f = here.row(j);
  const float* f_jm = here.row(std::max(j - 1, 0));
  const float* f_jp = here.row(std::min(j + 1, l.n_j - 1));
  const float* f_km = field.slice(k - 1).row(j);
  const float* f_kp = field.slice(k + 1).row(j);
  const auto one = [&](int n) {
    const int i = span.lo + n;
    VoxelRecord& rec = out[n];
    rec.bin = bins[i];
    rec.gradient[src.axis_i] = (f[std::min(i + 1, l.n_i - 1)] - f[std::max(i - 1, 0)]) * h_i;
    rec.gradient[src.axis_j] = (f_jp[i] - f_jm[i]) * h_j;
    rec.gradient[src.axis] = (f_kp[i] - f_km[i]) * h_k;
  };
  // Four voxels at a time where both row neighbours exist, with each lane's arithmetic the
  // scalar one's: the components as vectors (record lane 0 the bin, 1 + a the gradient along
  // world axis a), transposed into four records.
  int n = 0;
  if (span.lo == 0) one(n++);
  for (; n + 4 <= span.count && span.lo + n + 4 < l.n_i; n += 4) {
    const int i = span.lo + n;
    Float4 lane[4];
    if constexpr (std::is_same_v<Bin, float>)
      lane[0] = load4(bins + i);
    else
      lane[0] = Float4{float(bins[i]), float(bins[i + 1]), float(bins[i + 2]), float(bins[i + 3])};
    lane[1 + src.axis_i] = (load4(f + i + 1) - load4(f + i - 1)) * splat4(h_i);
    lane[1 + src.axis_j] = (load4(f_jp + i) - load4(f_jm + i)) * splat4(h_j);
    lane[1 + src.axis] = (load4(f_kp + i) - load4(f_km + i)) * splat4(h_k);
    transpose4(lane[0], lane[1], lane[2], lane[3]);
    for (int m = 0; m < 4; ++m) std::memcpy(&out[n + m], &lane[m], sizeof(VoxelRecord));
  }
  for (; n < span.count; ++n) one(n);
}

void findActiveCells(const SliceSource& src, int k, ActiveCells& active) {
  const ClassifiedVolume& cv = src.cv;
  constexpr int B = ClassifiedVolume::kBlock;
  const int cells_i = src.layout.n_i - 1, block_rows = (src.layout.n_j - 1 + B - 1) / B;
  active.offsets.assign(1, 0);
  active.ranges.clear();
  for (int bj = 0; bj < block_rows; ++bj) {
    if (cv.block_occupied.empty()) {
      active.ranges.push_back({0, cells_i});
    } else {
      int b[3];
      b[src.axis] = k / B;
      b[src.axis_j] = bj;
      for (int bi = 0; bi * B < cells_i; ++bi) {
        b[src.axis_i] = bi;
        if (!cv.blockOccupied(b[0], b[1], b[2])) continue;
        const int begin = bi * B, end = std::min(begin + B, cells_i);
        const bool in_this_row =
            active.offsets.back() < static_cast<std::int32_t>(active.ranges.size());
        if (in_this_row && active.ranges.back().end == begin)
          active.ranges.back().end = end;
        else
          active.ranges.push_back({begin, end});
      }
    }
    active.offsets.push_back(static_cast<std::int32_t>(active.ranges.size()));
  }
}

// Each voxel row's segments (the voxels that the runs of the cell rows either side of it reach,
// merged where they meet or overlap), their places in the slice's records, row after row, and
// each run's record0 / record1. Returns the number of records.
std::int32_t storeSegments(SliceEncoding& s, int n_j) {
  const auto runsOf = [&](int cj) {
    return std::span<const CellRun>(s.runs.data() + s.run_offsets[cj],
                                    s.runs.data() + s.run_offsets[cj + 1]);
  };
  s.segments.clear();
  std::int32_t stored = 0;
  for (int j = 0; j < n_j; ++j) {
    s.segment_offsets[j] = static_cast<std::int32_t>(s.segments.size());
    s.row_first[j] = stored;
    const std::span<const CellRun> above = j > 0 ? runsOf(j - 1) : std::span<const CellRun>{};
    const std::span<const CellRun> below = j + 1 < n_j ? runsOf(j) : std::span<const CellRun>{};
    auto a = above.begin(), b = below.begin();
    while (a != above.end() || b != below.end()) {  // both sorted: merged by begin
      const bool from_above = b == below.end() || (a != above.end() && a->begin <= b->begin);
      const CellRun& run = from_above ? *a++ : *b++;
      const bool open = static_cast<std::int32_t>(s.segments.size()) > s.segment_offsets[j];
      RowSegment* last = open ? &s.segments.back() : nullptr;
      if (last && run.begin <= last->lo + last->count)  // meets or overlaps: voxels begin .. end
        last->count = std::max(last->count, run.end + 1 - last->lo);
      else
        s.segments.push_back({run.begin, run.end + 1 - run.begin, 0});
    }
    for (int g = s.segment_offsets[j]; g < static_cast<int>(s.segments.size()); ++g) {
      s.segments[g].offset = stored;
      stored += s.segments[g].count;
    }
  }
  s.segment_offsets[n_j] = static_cast<std::int32_t>(s.segments.size());
  s.row_first[n_j] = stored;
  // A run of cell row j lies within one segment of voxel row j and one of row j + 1.
  for (int cj = 0; cj + 1 < n_j; ++cj) {
    const RowSegment* in[2] = {s.segments.data() + s.segment_offsets[cj],
                               s.segments.data() + s.segment_offsets[cj + 1]};
    for (CellRun& run : std::span<CellRun>(s.runs.data() + s.run_offsets[cj],
                                           s.runs.data() + s.run_offsets[cj + 1])) {
      for (const RowSegment*& g : in)
        while (g->lo + g->count <= run.begin) ++g;
      run.record0 = in[0]->offset + (run.begin - in[0]->lo);
      run.record1 = in[1]->offset + (run.begin - in[1]->lo);
    }
  }
  return stored;
}

// The runs and records of the slice at voxel position k + t along the axis (0 ≤ t < 1; t > 0
// for scalar volumes only: values and gradients interpolated linearly from voxel slices k and
// k + 1). T: what the slices of `values` hold, the float values of a scalar volume or a label
// map's 16-bit labels (read as such: a quarter of the memory traffic of the labels' float copy
// that classification keeps for the other backends).
template <class T>
void encodeSlice(const SliceSource& src, const SliceGroup<T>& values,
                 const SliceGroup<float>& field, int k, float t, EncoderScratch& scratch,
                 SliceEncoding& s) {
  const ClassifiedVolume& cv = src.cv;
  constexpr int B = ClassifiedVolume::kBlock;
  const int n_i = src.layout.n_i, n_j = src.layout.n_j;
  s.run_offsets.assign(n_j, 0);
  s.segment_offsets.assign(n_j + 1, 0);
  s.row_first.assign(n_j + 1, 0);
  if (!src.visibility.any) return;
  ActiveCells& active = scratch.active;
  findActiveCells(src, k, active);
  if (active.ranges.empty()) return;
  // Keys, every voxel's bin coordinate or its label's visibility, where the active cells of
  // the cell rows either side of the voxel row reach: from the first active cell to the last
  // one's right voxel, so that every record the runs below store has its key.
  scratch.keys.resize(static_cast<std::size_t>(n_i) * n_j);
  const SliceRows<T> rows = values.slice(k);
  const SliceRows<T> next_rows = values.slice(k + 1);
  for (int j = 0; j < n_j; ++j) {
    int lo = n_i, hi = -1;
    for (int cj = std::max(j - 1, 0); cj <= std::min(j, n_j - 2); ++cj) {
      const auto ranges = active.of(cj / B);
      if (ranges.empty()) continue;
      lo = std::min(lo, ranges.front().begin);
      hi = std::max(hi, ranges.back().end);  // the last cell's right voxel
    }
    const T* v = rows.row(j);
    // The next row's lines, fetched while this one is keyed: in place, the rows of a slice are a
    // volume row or slice apart, each on a page of its own, where the hardware prefetcher
    // starts cold (the load of the labels was most of the keys' time).
    if (j + 1 < n_j)
      for (int i = lo; i <= hi; i += 64 / static_cast<int>(sizeof(T)))
        __builtin_prefetch(rows.row(j + 1) + i);
    float* key = scratch.keys.data() + static_cast<std::size_t>(j) * n_i;
    if constexpr (std::is_same_v<T, std::uint16_t>) {
      const float* visible = src.visibility.label_key.data();
      for (int i = lo; i <= hi; ++i) key[i] = visible[v[i]];
    } else if (t == 0.f) {
      for (int i = lo; i <= hi; ++i) key[i] = binCoordinate(cv, v[i]);
    } else {
      const T* w = next_rows.row(j);
      for (int i = lo; i <= hi; ++i) key[i] = binCoordinate(cv, v[i] + t * (w[i] - v[i]));
    }
  }
  scratch.occupied.resize(n_i);
  for (int j = 0; j + 1 < n_j; ++j) {
    s.run_offsets[j] = static_cast<std::int32_t>(s.runs.size());
    const float* a = scratch.keys.data() + static_cast<std::size_t>(j) * n_i;
    for (const ActiveCells::Range& r : active.of(j / B)) {
      src.visibility.cells(a, a + n_i, r.begin, r.end, scratch.occupied.data());
      appendRuns(scratch.occupied.data(), r.begin, r.end, s.runs);
    }
  }
  s.run_offsets[n_j - 1] = static_cast<std::int32_t>(s.runs.size());
  const std::int32_t stored = storeSegments(s, n_j);
  s.records = scratch.records.allocate<VoxelRecord>(stored);
  s.record_count = stored;
  for (int j = 0; j < n_j; ++j) {
    // A label map's records hold its labels, read as such; a scalar volume's its keys.
    const auto* bins = [&] {
      if constexpr (std::is_same_v<T, std::uint16_t>)
        return rows.row(j);
      else
        return static_cast<const float*>(scratch.keys.data() + static_cast<std::size_t>(j) * n_i);
    }();
    for (int g = s.segment_offsets[j]; g < s.segment_offsets[j + 1]; ++g) {
      const RowSegment& segment = s.segments[g];
      VoxelRecord* out = s.records + segment.offset;
      fillRowRecords(src, field, bins, k, j, segment, out);
      if (t == 0.f) continue;
      // Between voxel slices: the gradient interpolated as the value was (the bin is the key's).
      scratch.next_records.resize(segment.count);
      fillRowRecords(src, field, bins, k + 1, j, segment, scratch.next_records.data());
      for (int n = 0; n < segment.count; ++n)
        for (int a = 0; a < 3; ++a)
          out[n].gradient[a] += t * (scratch.next_records[n].gradient[a] - out[n].gradient[a]);
    }
  }
}

// The one range check of an encoding's slice samples (RleVolume indexes its cache by them).
void requireSliceSamples(int m) {
  if (m < 1 || m > RleVolume::kMaxSliceSamples)
    throw Error(fmt::format("shearwarp: {} slice samples per voxel; 1 to {} are supported", m,
                            RleVolume::kMaxSliceSamples));
}

}  // namespace

bool cellOccupied(const ClassifiedVolume& cv, std::span<const int> nonzero_prefix, int x, int y,
                  int z, int a, int b) {
  float bmin = INFINITY, bmax = -INFINITY;
  for (int n = 0; n < 4; ++n) {
    int p[3] = {x, y, z};
    p[a] += n & 1;
    p[b] += (n >> 1) & 1;
    const std::size_t i = indexOf(cv.dims, p[0], p[1], p[2]);
    if (cv.labels) {
      if (cv.alpha[cv.label[i]] > 0.f) return true;
    } else {
      bmin = std::min(bmin, binCoordinate(cv, cv.values[i]));
      bmax = std::max(bmax, binCoordinate(cv, cv.values[i]));
    }
  }
  if (cv.labels) return false;
  // Every bilinear sample's bin coordinate lies in [bmin, bmax].
  return binRangeVisible(cv, nonzero_prefix, bmin, bmax);
}

AxisEncoding::AxisEncoding(const ClassifiedVolume& cv, int axis, int slice_samples)
    : axis_(axis), axis_i_((axis + 1) % 3), axis_j_((axis + 2) % 3), m_(slice_samples) {
  // Keep x fastest inside a row where possible: for z slices rows run along x, for y slices
  // along x too (rows are then contiguous in memory); x slices run along y.
  if (axis == 1) std::swap(axis_i_, axis_j_);
  n_i_ = cv.dims[axis_i_];
  n_j_ = cv.dims[axis_j_];
  const int voxel_slices = cv.dims[axis_];
  requireSliceSamples(m_);
  if (m_ > 1 && cv.labels)
    throw Error(fmt::format("shearwarp: a label map has no values between its voxel slices, so it "
                            "takes one sample per slice (slice_samples 1, not {})",
                            m_));
  n_k_ = (voxel_slices - 1) * m_ + 1;
  if (n_i_ < 2 || n_j_ < 2)
    throw Error(fmt::format("shearwarp: a {}×{}×{} volume is too thin to shear (at least 2 "
                            "voxels along each axis)",
                            cv.dims[0], cv.dims[1], cv.dims[2]));
  // A slice's records are indexed by int32 (CellRun, RowSegment).
  if (static_cast<std::int64_t>(n_i_) * n_j_ > std::numeric_limits<std::int32_t>::max())
    throw Error(fmt::format("shearwarp: a {}×{} slice of a {}×{}×{} volume is too large to "
                            "encode (at most 2³¹ − 1 voxels a slice)",
                            n_i_, n_j_, cv.dims[0], cv.dims[1], cv.dims[2]));
  const std::size_t stride[3] = {1, static_cast<std::size_t>(cv.dims[0]),
                                 static_cast<std::size_t>(cv.dims[0]) * cv.dims[1]};
  const SliceLayout layout{n_i_, n_j_, voxel_slices, stride[axis_i_], stride[axis_j_],
                           stride[axis_]};
  const Visibility visibility(cv);
  const SliceSource source{cv, layout, axis_, axis_i_, axis_j_, visibility};
  // Gathered slices go in groups of 64: a few cache lines of floats along the axis for each
  // voxel of a slice, read once for the group.
  const int group = layout.stride_i == 1 ? 1 : 64;
  const int groups = (voxel_slices + group - 1) / group;
  slices_.resize(n_k_);
  const bool parallel =
      static_cast<std::int64_t>(n_i_) * n_j_ * n_k_ >= kParallelVoxels;
  // Voxel slice k's own slice and, short of the last, the m − 1 between it and k + 1.
  const auto encodeVoxelSlice = [&](const auto& values, const SliceGroup<float>& field, int k,
                                    EncoderScratch& scratch) {
    const int between = k + 1 < voxel_slices ? m_ : 1;
    for (int r = 0; r < between; ++r)
      encodeSlice(source, values, field, k, static_cast<float>(r) / static_cast<float>(m_),
                  scratch, slices_[static_cast<std::size_t>(k) * m_ + r]);
  };
#pragma omp parallel if (parallel)
  {
    EncoderScratch scratch;
#pragma omp for schedule(dynamic)
    for (int g = 0; g < groups; ++g) {
      const int k0 = g * group, k1 = std::min(k0 + group, voxel_slices);
      if (cv.labels) {
        const SliceGroup<std::uint16_t> labels(layout, cv.label.data(), k0, k1,
                                               scratch.label_planes);
        const SliceGroup<float> field(layout, cv.shading_field.data(), k0, k1, scratch.field);
        for (int k = k0; k < k1; ++k) encodeVoxelSlice(labels, field, k, scratch);
      } else {
        const SliceGroup<float> values(layout, cv.values.data(), k0, k1, scratch.values,
                                       m_ > 1 ? 2 : 1);
        for (int k = k0; k < k1; ++k) encodeVoxelSlice(values, values, k, scratch);
      }
    }
#pragma omp critical(svr_shearwarp_records)
    records_.adopt(std::move(scratch.records));
  }
}

std::size_t AxisEncoding::bytes() const {
  std::size_t n = 0;
  for (const SliceEncoding& s : slices_)
    n += (s.run_offsets.size() + s.segment_offsets.size() + s.row_first.size()) *
             sizeof(std::int32_t) +
         s.runs.size() * sizeof(CellRun) + s.segments.size() * sizeof(RowSegment) +
         s.record_count * sizeof(VoxelRecord);
  return n;
}

const VoxelRecord* AxisEncoding::findVoxel(int k, int j, int i) const {
  for (const RowSegment& g : segments(k, j))
    if (i >= g.lo && i < g.lo + g.count) return slices_[k].records + g.offset + (i - g.lo);
  return nullptr;
}

std::size_t AxisEncoding::storedVoxels() const {
  std::size_t n = 0;
  for (const SliceEncoding& s : slices_) n += s.record_count;
  return n;
}

RleVolume::RleVolume(const ClassifiedVolume& cv) : cv_(cv) {}

std::shared_ptr<const RleVolume> RleVolume::of(const ClassifiedVolume& cv) {
  return cv.derived->get<RleVolume>("shearwarp.rle",
                                    [&] { return std::make_shared<const RleVolume>(cv); });
}

const AxisEncoding& RleVolume::encoding(int axis, int slice_samples) const {
  requireSliceSamples(slice_samples);
  const int n = axis * kMaxSliceSamples + slice_samples - 1;
  std::call_once(once_[n],
                 [&] { axes_[n] = std::make_unique<AxisEncoding>(cv_, axis, slice_samples); });
  return *axes_[n];
}

void RleVolume::buildAll() const {
  for (int a = 0; a < 3; ++a) encoding(a);
}

}  // namespace svr::shearwarp
