#pragma once
// The compositing inner loop of shear-warp: one intermediate scanline through every slice,
// front to back, templated on the channel count K (0 = dynamic) and on spectral (k-channel) or
// scalar transmittance. Per sample it does what raycast_kernel.h does (classify the
// interpolated value, or interpolate the classified labels; Phong with the interpolated
// gradient; S += T ⊙ α(ρ·shade + white·spec·highlight); T ⊙= t), with the entries corrected
// for the slice spacing and laid out as the raycaster's sample table (SliceTable: α, α·s, α·ρ,
// t per entry, so the opacity-weighted blend needs no division). Included only by
// shearwarp_renderer.cpp.
//
// Skipping: only the runs of non-transparent cells are visited (rle_volume.h), and pixels that
// became opaque are jumped over through links in the scanline (Lacroute & Levoy §4.2): links[u]
// = u while pixel u is live, else a pointer towards the next live pixel, path-compressed.

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderers/core/classification.h"
#include "renderers/core/classified_sample.h"
#include "renderers/shearwarp/intermediate_warp.h"
#include "renderers/shearwarp/preclassified_axis.h"
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shear_warp_factorization.h"

namespace svr::shearwarp {

inline constexpr int kMaxChannels = 128;

// Per entry, for the slice spacing: [α, α·specular, α·ρ_0 … α·ρ_{k−1}, t_0 … t_{kt−1}], rows
// padded to a multiple of 4 floats (raycast/sample_table.h's layout for this backend's own
// opacity correction).
struct SliceTable {
  static constexpr int strideFor(int width) { return (width + 3) / 4 * 4; }
  int stride = 0;
  std::vector<float> rows;
  // alpha, transmission: the classification's entries corrected for the slice spacing.
  SliceTable(const ClassifiedVolume& cv, const std::vector<float>& alpha,
             const std::vector<float>& transmission)
      : stride(strideFor(2 + cv.k + cv.t_channels)) {
    const int k = cv.k, kt = cv.t_channels;
    rows.assign(static_cast<std::size_t>(cv.entries) * stride, 0.f);
    for (int e = 0; e < cv.entries; ++e) {
      float* row = &rows[static_cast<std::size_t>(e) * stride];
      row[0] = alpha[e];
      row[1] = alpha[e] * cv.specular[e];
      for (int c = 0; c < k; ++c)
        row[2 + c] = alpha[e] * cv.reflectance[static_cast<std::size_t>(e) * k + c];
      for (int c = 0; c < kt; ++c)
        row[2 + k + c] = transmission[static_cast<std::size_t>(e) * kt + c];
    }
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
  // A brick of a distributed render (core/brick_box.h): the view is the whole grid's; slices
  // and in-slice positions are placed by the brick's origin (the index of its first stored
  // voxel), and only its own samples are taken — slices [slice_begin, slice_end) of the
  // encoding and in-slice positions within [lo, hi) (whole-grid voxel coordinates, open to ±∞
  // at the grid's faces). A whole volume: origin 0, every slice, no bounds.
  int origin[3] = {0, 0, 0};
  double lo[3] = {-INFINITY, -INFINITY, -INFINITY}, hi[3] = {INFINITY, INFINITY, INFINITY};
  int slice_begin = 0, slice_end = 0;
};

inline int nextLive(int* links, int u) {
  int root = u;
  while (links[root] != root) root = links[root];
  while (links[u] != root) {
    const int next = links[u];
    links[u] = root;
    u = next;
  }
  return root;
}

// First intermediate pixel u ≥ 0 whose coordinate q(u) = u / scale + base reaches `target`
// (strictly passes it when `strict`), computed with the same arithmetic the loop uses, so a
// pixel is never lost or counted twice at a run boundary.
inline int firstPixel(double target, double base, double inv_scale, int scale, bool strict) {
  int u = static_cast<int>(std::ceil((target - base) * scale));
  const auto reached = [&](int w) {
    const double q = w * inv_scale + base;
    return strict ? q > target : q >= target;
  };
  while (reached(u - 1)) --u;
  while (!reached(u)) ++u;
  return u;
}

// The sample's blended table row: the two bins around a scalar value, or the four corners'
// labels weighted bilinearly.
template <int kStride>
[[gnu::always_inline]] inline void blendRow(const ClassifiedVolume& cv, const SliceTable& table,
                                            const VoxelRecord* const c[4], const float w[4],
                                            int width_, float* acc) {
  const int width = kStride > 0 ? kStride : width_;
  if (cv.labels) {
    for (int j = 0; j < width; ++j) acc[j] = 0.f;
    for (int n = 0; n < 4; ++n) {
      const float* r = table.row(static_cast<int>(c[n]->value));
      for (int j = 0; j < width; ++j) acc[j] += w[n] * r[j];
    }
    return;
  }
  const float value = w[0] * c[0]->value + w[1] * c[1]->value + w[2] * c[2]->value +
                      w[3] * c[3]->value;
  int e0, e1;
  float frac;
  binOf(cv, value, e0, e1, frac);
  const float* r0 = table.row(e0);
  const float* r1 = table.row(e1);
  for (int j = 0; j < width; ++j) acc[j] = r0[j] + frac * (r1[j] - r0[j]);
}

// Every live intermediate pixel u of scanline v that slice `slice`'s cell runs cover: perRow(j0,
// fj) is called once with the cell row and its fraction along j, and returns the per-sample
// function sample(u, i0, fi) (i0: the cell along i, fi: the fraction), which composites pixel
// u and says whether it became opaque (links then skips it from now on).
template <class PerRow>
[[gnu::always_inline]] inline void forEachSample(const CompositeJob& job, int v, int slice,
                                                 int* links, const PerRow& perRow) {
  const AxisEncoding& enc = *job.encoding;
  const ShearWarpFactorization& f = *job.view;
  const int width = job.image->width;
  const int n_i = enc.rowLength(), n_j = enc.rowCount();
  const double inv_scale = 1.0 / f.scale;
  // Positions are computed in the whole grid, as a whole render computes them, then moved to
  // the brick's stored voxels (exact: integer offsets of doubles a few thousand voxels wide).
  const int whole_slice = slice + job.origin[f.axis];
  const double qj_whole = v * inv_scale + f.offset_j + f.shear_j * whole_slice;
  if (!(qj_whole >= job.lo[f.axis_j] && qj_whole < job.hi[f.axis_j])) return;
  const double qj = qj_whole - job.origin[f.axis_j];
  if (!(qj >= 0.0 && qj <= n_j - 1)) return;
  const int j0 = std::min(static_cast<int>(qj), n_j - 2);
  const auto sample = perRow(j0, static_cast<float>(qj - j0));
  const double base_i = f.offset_i + f.shear_i * whole_slice;
  const int oi = job.origin[f.axis_i];
  // The brick's own pixels along the scanline.
  const int own_begin = std::isfinite(job.lo[f.axis_i])
                            ? firstPixel(job.lo[f.axis_i], base_i, inv_scale, f.scale, false)
                            : 0;
  const int own_end = std::isfinite(job.hi[f.axis_i])
                          ? firstPixel(job.hi[f.axis_i], base_i, inv_scale, f.scale, false)
                          : width;
  for (const CellRun& run : enc.runs(slice, j0)) {
    const int u_begin = std::max(
        {firstPixel(run.begin + oi, base_i, inv_scale, f.scale, false), 0, own_begin});
    // The last cell of a row also holds the samples exactly on the row's last voxel.
    const int u_end = std::min(
        {firstPixel(run.end + oi, base_i, inv_scale, f.scale, run.end == n_i - 1), width,
         own_end});
    for (int u = nextLive(links, u_begin); u < u_end; u = nextLive(links, u + 1)) {
      const double qi = (u * inv_scale + base_i) - oi;
      const int i0 = std::clamp(static_cast<int>(qi), run.begin, run.end - 1);
      const float fi = std::clamp(static_cast<float>(qi - i0), 0.f, 1.f);
      if (sample(u, i0, fi)) links[u] = u + 1;
    }
  }
}

// One slice's samples on intermediate scanline v, post-classified.
template <int K, bool kSpectralT>
[[gnu::always_inline]] inline void compositeSlice(const CompositeJob& job, int v, int slice,
                                                  int* links) {
  const ClassifiedVolume& cv = *job.volume;
  const AxisEncoding& enc = *job.encoding;
  const SliceTable& table = *job.table;
  const int k = K > 0 ? K : cv.k;
  const int kt = kSpectralT ? k : 1;
  constexpr int kStride = K > 0 ? SliceTable::strideFor(2 + K + (kSpectralT ? K : 1)) : 0;
  constexpr int kWidthCap = SliceTable::strideFor(2 + kMaxChannels + kMaxChannels);
  const float* white = cv.white.data();
  float* row = job.image->pixel(0, v);
  const int stride = job.image->channels();
  forEachSample(job, v, slice, links, [&](int j0, float fj) {
    // Voxel i of rows j0 and j0 + 1, for the i the cell runs touch.
    const VoxelRecord* rec0 = enc.rowRecords(slice, j0);
    const VoxelRecord* rec1 = enc.rowRecords(slice, j0 + 1);
    return [&, rec0, rec1, fj](int u, int i0, float fi) {
      const VoxelRecord* const c[4] = {rec0 + i0, rec0 + i0 + 1, rec1 + i0, rec1 + i0 + 1};
      const float w[4] = {(1 - fi) * (1 - fj), fi * (1 - fj), (1 - fi) * fj, fi * fj};
      alignas(16) float acc[K > 0 ? kStride : kWidthCap];
      blendRow<kStride>(cv, table, c, w, table.stride, acc);
      float* S = row + static_cast<std::size_t>(u) * stride;
      float* T = S + k;
      if (acc[0] > 0.f) {  // α
        float g[3];
        for (int a = 0; a < 3; ++a)
          g[a] = w[0] * c[0]->gradient[a] + w[1] * c[1]->gradient[a] +
                 w[2] * c[2]->gradient[a] + w[3] * c[3]->gradient[a];
        const auto [shade, highlight] = phong(job.phong, g);
        const float hs = highlight * acc[1];
        for (int ch = 0; ch < k; ++ch)
          S[ch] += T[kSpectralT ? ch : 0] * (acc[2 + ch] * shade + white[ch] * hs);
      }
      float tmax = 0.f;
      for (int ch = 0; ch < kt; ++ch) {
        T[ch] *= acc[2 + k + ch];
        tmax = std::max(tmax, T[ch]);
      }
      return tmax < job.threshold;
    };
  });
}

// compositeSlice for shearwarp.classification=pre: the four corners' classified records
// blended bilinearly, each shaded from the view's table by its normal index; the interpolated
// α and t corrected for the slice spacing.
template <int K, bool kSpectralT>
[[gnu::always_inline]] inline void compositeSlicePre(const CompositeJob& job, int v, int slice,
                                                     int* links) {
  const ClassifiedVolume& cv = *job.volume;
  const PreclassifiedAxis& pre = *job.pre;
  const int k = K > 0 ? K : cv.k;
  const int kt = kSpectralT ? k : 1;
  const float* white = cv.white.data();
  const float* terms = job.shading->terms.data();
  const int rs = pre.stride();
  float* row = job.image->pixel(0, v);
  const int stride = job.image->channels();
  forEachSample(job, v, slice, links, [&](int j0, float fj) {
    const float* rec0 = pre.rowRecords(slice, j0);
    const float* rec1 = pre.rowRecords(slice, j0 + 1);
    const std::uint16_t* nrm0 = pre.rowNormals(slice, j0);
    const std::uint16_t* nrm1 = pre.rowNormals(slice, j0 + 1);
    return [&, rec0, rec1, nrm0, nrm1, fj](int u, int i0, float fi) {
      const float* c[4] = {rec0 + i0 * rs, rec0 + (i0 + 1) * rs, rec1 + i0 * rs,
                           rec1 + (i0 + 1) * rs};
      const std::uint16_t nidx[4] = {nrm0[i0], nrm0[i0 + 1], nrm1[i0], nrm1[i0 + 1]};
      const float w[4] = {(1 - fi) * (1 - fj), fi * (1 - fj), (1 - fi) * fj, fi * fj};
      float* S = row + static_cast<std::size_t>(u) * stride;
      float* T = S + k;
      const float a = w[0] * c[0][0] + w[1] * c[1][0] + w[2] * c[2][0] + w[3] * c[3][0];
      if (a > 0.f) {
        // S += T ⊙ (α'/α) Σ w (α·ρ · shade + α·s · highlight · white).
        const float scale = (1.f - (*job.opacity_power)(1.f - a)) / a;
        float ws[4], wh = 0.f;
        for (int n = 0; n < 4; ++n) {
          ws[n] = scale * w[n] * terms[2 * nidx[n]];
          wh += scale * w[n] * c[n][1] * terms[2 * nidx[n] + 1];
        }
        for (int ch = 0; ch < k; ++ch)
          S[ch] += T[kSpectralT ? ch : 0] *
                   (ws[0] * c[0][2 + ch] + ws[1] * c[1][2 + ch] + ws[2] * c[2][2 + ch] +
                    ws[3] * c[3][2 + ch] + wh * white[ch]);
      }
      float tmax = 0.f;
      for (int ch = 0; ch < kt; ++ch) {
        const int o = 2 + k + ch;
        T[ch] *= (*job.transmission_power)(w[0] * c[0][o] + w[1] * c[1][o] + w[2] * c[2][o] +
                                           w[3] * c[3][o]);
        tmax = std::max(tmax, T[ch]);
      }
      return tmax < job.threshold;
    };
  });
}

// Intermediate scanlines [v0, v1) through every slice, front to back. Slice by slice over the
// band (not scanline by scanline through all slices): a slice's rows for neighbouring scanlines
// are neighbours in memory, so the records stream in order; scanline-major order jumped
// between all slices' records from one sample to the next, and a sixth of the compositing time
// was the first load of a voxel record. A band's scanlines only ever receive their own rays,
// so bands composite independently: no barrier per slice.
template <int K, bool kSpectralT, bool kPre>
void compositeBand(const CompositeJob& job, int v0, int v1, std::vector<int>& links) {
  const int width = job.image->width;
  const int n_k = job.slice_end - job.slice_begin;
  const int lines = v1 - v0;
  links.resize(static_cast<std::size_t>(lines) * (width + 1));
  for (int l = 0; l < lines; ++l)
    for (int u = 0; u <= width; ++u) links[static_cast<std::size_t>(l) * (width + 1) + u] = u;
  int live_lines = lines;
  for (int step = 0; step < n_k && live_lines > 0; ++step) {
    const int slice = job.view->increasing ? job.slice_begin + step : job.slice_end - 1 - step;
    live_lines = 0;
    for (int l = 0; l < lines; ++l) {
      int* line = links.data() + static_cast<std::size_t>(l) * (width + 1);
      if (nextLive(line, 0) >= width) continue;  // the whole scanline is opaque
      if constexpr (kPre)
        compositeSlicePre<K, kSpectralT>(job, v0 + l, slice, line);
      else
        compositeSlice<K, kSpectralT>(job, v0 + l, slice, line);
      ++live_lines;
    }
  }
}

}  // namespace svr::shearwarp
