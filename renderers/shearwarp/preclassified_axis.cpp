#include "renderers/shearwarp/preclassified_axis.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <utility>

#include "renderers/classification/classified_sample.h"
#include "renderers/simd/float4.h"
#include "renderers/volume/volume.h"

namespace svr::shearwarp {

// The last of the kNormalSide steps along each coordinate of the folded square.
constexpr float kTopStep = kNormalSide - 1;

// Octahedral mapping (Meyer et al. 2010): the unit sphere folded onto [−1, 1]², kNormalSide
// steps a side, each coordinate rounded to the nearest step.
std::uint16_t encodeNormal(const float g[3]) {
  if (!(g[0] * g[0] + g[1] * g[1] + g[2] * g[2] > 1e-12f)) return kFlatNormal;
  const float inv_len1 = 1.f / (std::abs(g[0]) + std::abs(g[1]) + std::abs(g[2]));
  float x = g[0] * inv_len1, y = g[1] * inv_len1;
  if (g[2] < 0.f) {
    const float fx = (1.f - std::abs(y)) * (x >= 0.f ? 1.f : -1.f);
    const float fy = (1.f - std::abs(x)) * (y >= 0.f ? 1.f : -1.f);
    x = fx, y = fy;
  }
  // c lies in [−1, 1], so the step plus a half is non-negative and truncation rounds it (half
  // up; libm's lround was a third of the encoding's time). A NaN falls to step 0.
  const auto q = [](float c) {
    const float step = (c * 0.5f + 0.5f) * kTopStep + 0.5f;
    return step > 0.f ? std::min(static_cast<int>(step), kNormalSide - 1) : 0;
  };
  return static_cast<std::uint16_t>(q(y) * kNormalSide + q(x));
}

void decodeNormal(std::uint16_t index, float n[3]) {
  float x = static_cast<float>(index % kNormalSide) / kTopStep * 2.f - 1.f;
  float y = static_cast<float>(index / kNormalSide) / kTopStep * 2.f - 1.f;
  const float z = 1.f - std::abs(x) - std::abs(y);
  if (z < 0.f) {
    const float fx = (1.f - std::abs(y)) * (x >= 0.f ? 1.f : -1.f);
    const float fy = (1.f - std::abs(x)) * (y >= 0.f ? 1.f : -1.f);
    x = fx, y = fy;
  }
  const float len = std::sqrt(x * x + y * y + z * z);
  n[0] = x / len, n[1] = y / len, n[2] = z / len;
}

// Four normals at a time, each lane taking encodeNormal's operations in its order (so the two
// agree bit for bit), with selects for its branches.
void encodeNormals(std::span<const VoxelRecord> voxels, std::uint16_t* normals) {
  const Float4 one = splat4(1.f), half = splat4(0.5f), zero = splat4(0.f);
  const auto sign = [&](Float4 c) { return c >= zero ? one : -one; };
  const auto q = [&](Float4 c) {
    Float4 step = (c * half + half) * splat4(kTopStep) + half;
    step = step > zero ? step : zero;  // a NaN too
    step = step < splat4(kTopStep) ? step : splat4(kTopStep);
    return __builtin_convertvector(step, Int4);
  };
  std::size_t n = 0;
  for (; n + 4 <= voxels.size(); n += 4) {
    Float4 bins = load4(&voxels[n].bin), gx = load4(&voxels[n + 1].bin);
    Float4 gy = load4(&voxels[n + 2].bin), gz = load4(&voxels[n + 3].bin);
    transpose4(bins, gx, gy, gz);
    const Int4 flat = !(gx * gx + gy * gy + gz * gz > splat4(1e-12f));
    const Float4 inv_len1 = one / (abs4(gx) + abs4(gy) + abs4(gz));
    Float4 x = gx * inv_len1, y = gy * inv_len1;
    const Int4 below = gz < zero;
    const Float4 fx = (one - abs4(y)) * sign(x), fy = (one - abs4(x)) * sign(y);
    x = below ? fx : x, y = below ? fy : y;
    const Int4 index = flat ? Int4{kFlatNormal, kFlatNormal, kFlatNormal, kFlatNormal}
                            : q(y) * kNormalSide + q(x);
    for (int m = 0; m < 4; ++m) normals[n + m] = static_cast<std::uint16_t>(index[m]);
  }
  for (; n < voxels.size(); ++n) normals[n] = encodeNormal(voxels[n].gradient);
}

namespace {

// Every table entry's classified record, [α, α·specular, α·ρ_0 …, t_0 …] padded with zeros to
// the stride: a voxel's record is its bin's two entries blended (classification is linear in
// the entries' weights), two vector lerps a voxel for rgb instead of 2 × (2 + k + kt) products.
std::vector<float> entryRecords(const ClassifiedVolume& cv, int stride) {
  return blendRows(cv, cv.alpha.data(), cv.transmission.data(), stride);
}

// Each voxel's record: its bin's two entries' rows of `table` blended (entriesOfBin, four
// voxels' at a time). V: vectors a record (stride / 4), fixed at compile time for the common
// strides so the blend unrolls; 0 for any.
template <int V>
void classifyRecords(const ClassifiedVolume& cv, const float* table, int stride,
                     std::span<const VoxelRecord> voxels, float* records) {
  const int vectors = V > 0 ? V : stride / 4;
  const auto blend = [&](std::size_t n, int e0, int e1, float w) {
    const float* a = table + static_cast<std::size_t>(e0) * stride;
    const float* b = table + static_cast<std::size_t>(e1) * stride;
    float* r = records + n * stride;
    for (int q = 0; q < vectors; ++q) {
      const Float4 lo = load4(a + 4 * q);
      store4(r + 4 * q, lo + (load4(b + 4 * q) - lo) * splat4(w));
    }
  };
  std::size_t n = 0;
  for (; n + 4 <= voxels.size(); n += 4) {
    const Float4 bins{voxels[n].bin, voxels[n + 1].bin, voxels[n + 2].bin, voxels[n + 3].bin};
    Int4 e0, e1;
    Float4 w = splat4(0.f);
    if (cv.labels)
      e0 = e1 = __builtin_convertvector(bins, Int4);  // the label's own entry
    else
      entriesOfBins(cv, bins, e0, e1, w);
    for (int m = 0; m < 4; ++m) blend(n + m, e0[m], e1[m], w[m]);
  }
  for (; n < voxels.size(); ++n) {
    int e0 = 0, e1 = 0;
    float w = 0.f;
    if (cv.labels)
      e0 = e1 = static_cast<int>(voxels[n].bin);
    else
      entriesOfBin(cv, voxels[n].bin, e0, e1, w);
    blend(n, e0, e1, w);
  }
}

// One slice: each voxel's quantised normal and its classified record.
void classifySlice(const ClassifiedVolume& cv, const float* table, int stride,
                   std::span<const VoxelRecord> voxels, float* records, std::uint16_t* normals) {
  encodeNormals(voxels, normals);
  switch (stride / 4) {
    case 2:  // 2 + k + kt ≤ 8: rgb, factor:3 and factor:4 with one t
      return classifyRecords<2>(cv, table, stride, voxels, records);
    case 3:
      return classifyRecords<3>(cv, table, stride, voxels, records);
    case 4:
      return classifyRecords<4>(cv, table, stride, voxels, records);
    default:
      return classifyRecords<0>(cv, table, stride, voxels, records);
  }
}

}  // namespace

PreclassifiedAxis::PreclassifiedAxis(const ClassifiedVolume& cv,
                                     std::shared_ptr<const RleVolume> encoded, int axis)
    : encoded_(std::move(encoded)),
      encoding_(&encoded_->encoding(axis)),
      stride_((2 + cv.k + cv.t_channels + 3) / 4 * 4) {
  const AxisEncoding& encoding = *encoding_;
  const int n_k = encoding.slices();
  const std::vector<float> table = entryRecords(cv, stride_);
  records_.resize(n_k);
  normals_.resize(n_k);
  // Classifying a voxel costs some 10 times what the loops kParallelVoxels was chosen for do
  // per voxel: in parallel from a tenth of it (the engine stores about 3 M).
  const bool parallel =
      encoding.storedVoxels() >= static_cast<std::size_t>(kParallelVoxels) / 10;
#pragma omp parallel if (parallel)
  {
    BlockArena arena;  // this thread's slices, adopted below
#pragma omp for schedule(dynamic)
    for (int s = 0; s < n_k; ++s) {
      const std::span<const VoxelRecord> voxels = encoding.sliceRecords(s);
      float* records = arena.allocate<float>(voxels.size() * stride_);
      std::uint16_t* normals = arena.allocate<std::uint16_t>(voxels.size());
      classifySlice(cv, table.data(), stride_, voxels, records, normals);
      records_[s] = records;
      normals_[s] = normals;
    }
#pragma omp critical(svr_shearwarp_preclassified)
    arena_.adopt(std::move(arena));
  }
}

std::shared_ptr<const PreclassifiedAxis> PreclassifiedAxis::of(const ClassifiedVolume& cv,
                                                               int axis) {
  static const char* const kKeys[3] = {"shearwarp.pre.x", "shearwarp.pre.y", "shearwarp.pre.z"};
  // The encoding first: the cache is not re-entrant (a get inside a get's builder deadlocks).
  auto encoded = RleVolume::of(cv);
  encoded->encoding(axis);
  return cv.derived->get<PreclassifiedAxis>(kKeys[axis], [&] {
    return std::make_shared<const PreclassifiedAxis>(cv, encoded, axis);
  });
}

std::size_t PreclassifiedAxis::bytes() const {
  const std::size_t voxels = encoding_->storedVoxels();
  return voxels * (stride_ * sizeof(float) + sizeof(std::uint16_t));
}

ShadingTable::ShadingTable(const PhongSetup& phong) : terms(2 * (kFlatNormal + 1)) {
  for (int i = 0; i <= kFlatNormal; ++i) {
    float n[3] = {0.f, 0.f, 0.f};
    if (i != kFlatNormal) decodeNormal(static_cast<std::uint16_t>(i), n);
    const PhongTerms t = svr::phong(phong, n);
    terms[2 * i] = t.shade;
    terms[2 * i + 1] = t.highlight;
  }
}

PowerTable::PowerTable(float lo, float hi, double r)
    : lo_(lo), inv_step_(hi > lo ? kSteps / (hi - lo) : 0.f), values_(kSteps + 1) {
  for (int i = 0; i <= kSteps; ++i) {
    const double x = lo + (hi - lo) * static_cast<double>(i) / kSteps;
    values_[i] = signedPow(x, r);
  }
}

}  // namespace svr::shearwarp
