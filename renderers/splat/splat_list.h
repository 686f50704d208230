#pragma once
// The splats of one frame: every voxel of one of the classification's splat lists
// (splat_voxels.h: the visible voxels, for pre-classification; or every voxel the reconstruction
// needs, for post-classification), shaded with the same Phong model as every backend, projected
// to the image and sorted front to back.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/render/renderer.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/kernels/splat_projection.h"
#include "renderers/kernels/splat_voxels.h"

namespace svr::splat {

// The most colour channels (and spectral transmittance channels) a splat render takes: the
// backend's max_channels.
inline constexpr int kMaxSplatChannels = 128;

struct Splat {
  float x, y;           // image position, pixels
  float depth;          // along the view axis, world units
  std::uint16_t entry;  // classification entry (and entry + 1, weighted by frac)
  float frac;
  float shade;      // ambient + diffuse |n·l|
  float highlight;  // specular |n·h|^shininess (the entries' specular weight applies later)
};

// Per-unit-length coefficients of one splat, from the per-step classification tables.
struct SplatCoefficients {
  float sigma_alpha;         // extinction that scatters (x-ray materials included)
  std::span<float> sigma_t;  // kt: extinction that attenuates
  std::span<float> colour;   // k: ρ·shade + white·highlight
};

// The arrays a frame's list takes, kept by the renderer for its next frame (reuse_pool.h): the
// voxels' projections and depth order, their splats in list order, and the splats in depth
// order with their footprints (the list's own).
struct SplatListMemory {
  VoxelProjection projection;
  std::vector<Splat> in_list_order, splats;
  std::vector<Footprint> footprints;
};

class SplatList {
 public:
  // Valid while `memory` is.
  SplatList(const ClassifiedVolume& volume, const RenderRequest& request,
            const Projector& projector, SplatVoxels::Set set, SplatListMemory& memory);
  std::span<const Splat> splats() const { return splats_; }
  const Footprint& footprint(std::size_t i) const {
    return footprints_.size() == 1 ? footprints_[0] : footprints_[i];
  }
  // Whether every splat has the one footprint of an orthographic camera.
  bool orthographic() const { return orthographic_; }
  float maxDepthSigma() const { return max_depth_sigma_; }
  int channels() const { return k_; }
  int transmittanceChannels() const { return kt_; }
  // Fills out.sigma_t and out.colour (caller-owned storage of kt and k floats): the splat
  // classified at its voxel.
  void coefficients(const Splat& splat, SplatCoefficients& out) const {
    classify(splat.entry, std::min(splat.entry + 1, cv_.entries - 1), splat.frac, splat.shade,
             splat.highlight, out);
  }
  // The same for a reconstructed value `bin` (the classification's bin coordinate, as
  // entry + frac) with the shade and highlight reconstructed beside it.
  void classifyBin(float bin, float shade, float highlight, SplatCoefficients& out) const {
    int e0, e1;
    float frac;
    entriesOfBin(cv_, bin, e0, e1, frac);
    classify(e0, e1, frac, shade, highlight, out);
  }

 private:
  // Entries e0 and e1 blended (weight frac on e1) as classified_sample.h's blendEntries blends
  // them, opacity-weighted, from their rows of the blend table: two rows' lerp and one division,
  // where blendEntries' loops over its tables took about 350 instructions a call, a million or
  // more calls a frame (once per splat and band, or per post-classified sheet pixel).
  void classify(int e0, int e1, float frac, float shade, float highlight,
                SplatCoefficients& out) const {
    const float* r0 = &rows_[static_cast<std::size_t>(e0) * row_stride_];
    const float* r1 = &rows_[static_cast<std::size_t>(e1) * row_stride_];
    alignas(16) float b[kMaxRowStride];
    const Float4 w0 = splat4(1.f - frac), w1 = splat4(frac);
    for (int j = 0; j < row_stride_; j += 4) store4(b + j, w0 * load4(r0 + j) + w1 * load4(r1 + j));
    out.sigma_alpha = b[0];
    // Σ w σ_α ρ / Σ w σ_α, the opacity-weighted reflectance; 0 where nothing scatters.
    const float inv = b[0] > 0.f ? 1.f / b[0] : 0.f;
    const float scale = shade * inv, white = highlight * b[1] * inv;
    for (int c = 0; c < k_; ++c) out.colour[c] = b[2 + c] * scale + cv_.white[c] * white;
    for (int c = 0; c < kt_; ++c) out.sigma_t[c] = b[2 + k_ + c];
  }
  // Rows of the blend table: [σ_α, σ_α·specular, σ_α·ρ_0 … σ_α·ρ_{k−1}, σ_t,0 … σ_t,kt−1] per
  // entry, padded to whole vectors.
  static constexpr int kMaxRowStride = (2 + 2 * kMaxSplatChannels + 3) / 4 * 4;
  const ClassifiedVolume& cv_;
  std::shared_ptr<const SplatVoxels> voxels_;
  int k_, kt_;
  std::vector<Splat>& splats_;
  std::vector<float> rows_;  // the blend table, row_stride_ floats an entry
  int row_stride_ = 0;
  std::vector<Footprint>& footprints_;  // one (orthographic) or one per splat
  float max_depth_sigma_ = 0.f;
  bool orthographic_ = false;
};

}  // namespace svr::splat

namespace svr::splat {

// Image rows cut into fixed bands of `rows` (independent of the thread count, so the result is
// too); each band lists the splats whose footprint reaches it, front to back.
struct Bands {
  int rows = 8, count = 0;
  std::vector<std::size_t> offsets;   // count + 1
  std::vector<std::uint32_t> splats;  // band b: splats[offsets[b] .. offsets[b + 1])
  std::vector<std::int32_t> first, last;  // working arrays: each splat's first and last band
  std::span<const std::uint32_t> of(int b) const {
    return {splats.data() + offsets[b], offsets[b + 1] - offsets[b]};
  }
};
class SplatCoverage;
// Fills `bands` (its arrays reused from an earlier frame where it has them).
void bandsOf(const SplatCoverage& coverage, int rows, Bands& bands);

// All a splat frame allocates, for the renderer's ReusePool.
struct SplatFrameMemory {
  SplatListMemory list;
  Bands bands;
};

// ⌊x⌋ and ⌈x⌉ as ints, for x within int range: std::floor and std::ceil are libm calls on the
// baseline x86-64 target (no SSE4.1 rounding), four per splat row.
inline int floorToInt(float x) {
  const int t = static_cast<int>(x);  // towards zero
  return t - (x < static_cast<float>(t));
}
inline int ceilToInt(float x) {
  const int t = static_cast<int>(x);
  return t + (x > static_cast<float>(t));
}

// The pixel range [lo, hi] whose centres lie within [centre − half, centre + half], clamped to
// [0, size − 1] (empty when lo > hi).
inline void pixelRange(float centre, float half, int size, int& lo, int& hi) {
  lo = std::max(ceilToInt(centre - half - 0.5f), 0);
  hi = std::min(floorToInt(centre + half - 0.5f), size - 1);
}

// Within [xa, xb], the pixels of one row whose centres can lie inside the footprint's ellipse
// q = a dx² + 2 b dx dy + c dy² < cut2, dy the row's offset from the splat centre: the chord of
// the ellipse, widened by 0.01 pixel so that float rounding never drops a pixel the per-pixel
// test would keep (that test still decides). Empty (lo > hi) where the row misses the ellipse.
inline void ellipseRow(const Footprint& fp, float sx, float dy, float cut2, int xa, int xb,
                       int& lo, int& hi) {
  const float disc = (fp.b * fp.b - fp.a * fp.c) * dy * dy + fp.a * cut2;
  if (!(disc > 0.f)) {
    lo = xa;
    hi = xa - 1;
    return;
  }
  const float centre = sx - fp.b * dy / fp.a - 0.5f;  // in pixel indices
  const float half = std::sqrt(disc) / fp.a + 0.01f;
  lo = std::max(xa, ceilToInt(centre - half));
  hi = std::min(xb, floorToInt(centre + half));
}

}  // namespace svr::splat
