#pragma once
// The compositing inner loop of shear-warp: one intermediate scanline through every slice,
// front to back, templated on the channel count K (0 = dynamic) and on spectral (k-channel) or
// scalar transmittance. Per sample it does what raycast_kernel.h does (classify the
// interpolated value, or interpolate the classified labels; Phong with the interpolated
// gradient; S += T ⊙ α(ρ·shade + white·spec·highlight); T ⊙= t), with the entries corrected
// for the slice spacing and laid out as the raycaster's sample table (SliceTable: α, α·s, α·ρ,
// t per entry, so the opacity-weighted blend needs no division).
//
// Skipping: only the runs of non-transparent cells are visited (rle_volume.h), and pixels that
// became opaque are jumped over through links in the scanline (Lacroute & Levoy §4.2): links[u]
// = u while pixel u is live, else a pointer towards the next live pixel, path-compressed.
//
// Included by one translation unit per instruction set (shearwarp_kernel_portable.cpp,
// shearwarp_kernel_avx2.cpp), as raycast_kernel.h is: SVR_SHEARWARP_ISA names the namespace
// its instantiations live in, SVR_SHEARWARP_TARGET the function attribute that compiles them
// for the instruction set.

#if !defined(SVR_SHEARWARP_ISA)
#error "define SVR_SHEARWARP_ISA (the instruction set's namespace) before including shearwarp_kernel.h"
#endif
#if !defined(SVR_SHEARWARP_TARGET)
#define SVR_SHEARWARP_TARGET
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "renderers/simd/channel_widths.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/simd/float4.h"
#include "renderers/shearwarp/shearwarp_kernels.h"

namespace svr::shearwarp::SVR_SHEARWARP_ISA {

// The helpers and the lambdas in the kernels carry no target attribute of their own (GCC
// would refuse to inline a target function into a lambda without it): they are always_inline,
// and compositeBand, which has the attribute, compiles them for its instruction set. The one
// lambda left out of line (forEachSample's flush) carries the attribute itself.
#define SVR_SHEARWARP_INLINE [[gnu::always_inline]] inline

SVR_SHEARWARP_INLINE int nextLive(int* links, int u) {
  if (links[u] == u) return u;  // live: most pixels, most of the time
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
SVR_SHEARWARP_INLINE int firstPixel(double target, double base, double inv_scale, int scale,
                                    bool strict) {
  // A guess within one of the answer (truncation: std::ceil is a libm call on the baseline
  // x86-64 target), then corrected.
  int u = static_cast<int>((target - base) * scale);
  const auto reached = [&](int w) {
    const double q = w * inv_scale + base;
    return strict ? q > target : q >= target;
  };
  while (reached(u - 1)) --u;
  while (!reached(u)) ++u;
  return u;
}

// A label map's sample: the four corners' table rows (one per label) weighted bilinearly.
SVR_SHEARWARP_INLINE void blendLabels(const SliceTable& table,
                                      const VoxelRecord* const c[4], const float w[4],
                                      int width, float* acc) {
  for (int j = 0; j < width; j += 4) {
    Float4 sum = w[0] * load4(table.row(static_cast<int>(c[0]->bin)) + j);
    for (int n = 1; n < 4; ++n) sum += w[n] * load4(table.row(static_cast<int>(c[n]->bin)) + j);
    store4(acc + j, sum);
  }
}

// Lanes [0, n) of `fresh`, the others of `kept`.
SVR_SHEARWARP_INLINE Float4 firstLanes(Float4 fresh, Float4 kept, int n) {
  const Int4 lane{0, 1, 2, 3};
  return lane < n ? fresh : kept;
}

// max(m, each lane of v), as std::max over the lanes in turn.
SVR_SHEARWARP_INLINE float maxLanes(float m, Float4 v) {
  for (int lane = 0; lane < 4; ++lane) m = std::max(m, v[lane]);
  return m;
}

// One sample composited into its pixel (S: k channels, then T: 1 or k, then padding to a
// multiple of four floats) from its classification, a table row's channels (acc: α, α·s, α·ρ,
// t; or two rows r0, r1 blended by frac, read in place): S += T ⊙ (α·ρ shade + white α·s
// highlight) where α > 0, then T ⊙= t. Four channels at a time, each lane with the scalar
// arithmetic, so that fixed-k and dynamic-k agree bit for bit. S's last vector, where partial,
// ends in the pixel's own T or padding: those lanes are stored back unchanged (before T is
// updated), or, with one T channel, updated there. Returns the largest T. white: k
// coefficients and SliceTable::kSlack more.
template <int K, bool kSpectralT>
SVR_SHEARWARP_INLINE float compositeSample(float* S, int k, const float* r0, const float* r1,
                                           float frac, float shade, float highlight,
                                           const float* white) {
  const int kt = kSpectralT ? k : 1;
  float* T = S + k;
  const Float4 f = splat4(frac);
  const auto lerp4 = [&](int j) {
    const Float4 a = load4(r0 + j);
    return a + f * (load4(r1 + j) - a);
  };
  const auto lerp1 = [&](int j) { return r0[j] + frac * (r1[j] - r0[j]); };
  if (lerp1(0) > 0.f) {  // α
    const float hs = highlight * lerp1(1);
    const Float4 shade4 = splat4(shade), hs4 = splat4(hs), t1 = splat4(T[0]);
    for (int ch = 0; ch < k; ch += 4) {
      const Float4 s = load4(S + ch);
      const Float4 c = lerp4(2 + ch);
      const Float4 t = kSpectralT ? load4(T + ch) : t1;
      const Float4 lit = s + t * (c * shade4 + load4(white + ch) * hs4);
      if (ch + 4 <= k) {
        store4(S + ch, lit);
      } else if (!kSpectralT) {
        // The vector holds the pixel's one T (lane k − ch, then padding), and c's lane there
        // is its t: T ⊙= t done here, as the loop below would (the padding stays 0).
        const Float4 both = firstLanes(lit, s * c, k - ch);
        store4(S + ch, both);
        return both[k - ch];
      } else {
        store4(S + ch, firstLanes(lit, s, k - ch));
      }
    }
  }
  float tmax = 0.f;
  int ch = 0;
  for (; ch + 4 <= kt; ch += 4) {
    const Float4 t = load4(T + ch) * lerp4(2 + k + ch);
    store4(T + ch, t);
    tmax = maxLanes(tmax, t);
  }
  for (; ch < kt; ++ch) {
    T[ch] *= lerp1(2 + k + ch);
    tmax = std::max(tmax, T[ch]);
  }
  return tmax;
}

// Up to kMax live pixels of one scanline in one slice, with their cells along i and fractions.
// A slice's samples are independent of each other, so the kernels take them in batches, one
// stage at a time over the whole batch (blend the records and shade, then composite): the
// processor overlaps one pixel's loads and arithmetic with the next pixel's, instead of waiting
// on each pixel's chain of loads, square root and power in turn. Each pixel's arithmetic is the
// same as when it is taken alone.
struct SampleBatch {
  static constexpr int kMax = 32;
  int count = 0;
  int u[kMax];
  // The records of the sample's cell's corners i0 and i0 + 1 in its two voxel rows: r0, r0 + 1
  // and r1, r1 + 1 of the slice's records (CellRun::record0 / record1).
  int r0[kMax], r1[kMax];
  float fi[kMax];
};

// A pixel whose largest T fell below the threshold is opaque: links skips it from the next
// slice on (set as the kernel composites it, not in a pass over the batch afterwards).
SVR_SHEARWARP_INLINE void markIfOpaque(int* links, int u, float tmax, float threshold) {
  if (tmax < threshold) links[u] = u + 1;
}

// Every live intermediate pixel u of scanline v that slice `slice`'s cell runs cover, in
// batches: perRow(j0, fj) is called once with the cell row and its fraction along j, and
// returns the function composite(SampleBatch&), which composites the batch's pixels and marks
// those that became opaque (markIfOpaque).
template <class PerRow>
SVR_SHEARWARP_INLINE void forEachSample(const CompositeJob& job, int v, int slice,
                                        int* links, const PerRow& perRow) {
  const AxisEncoding& enc = *job.encoding;
  const ShearWarpFactorization& f = *job.view;
  const int width = job.image->width;
  const int n_i = enc.rowLength(), n_j = enc.rowCount();
  const double inv_scale = 1.0 / f.scale;
  // Positions are computed in the whole grid, as a whole render computes them, then moved to
  // the brick's stored voxels (exact: integer offsets of doubles a few thousand voxels wide).
  // The slice's place along the axis in whole-grid voxels (slice_samples to a voxel slice:
  // exact for one, as the division by 1 is).
  const int m = f.slice_samples;
  const double whole_slice =
      static_cast<double>(slice + job.origin[f.axis] * m) / static_cast<double>(m);
  const double qj_whole = v * inv_scale + f.offset_j + f.shear_j * whole_slice;
  if (!(qj_whole >= job.lo[f.axis_j] && qj_whole < job.hi[f.axis_j])) return;
  const double qj = qj_whole - job.origin[f.axis_j];
  if (!(qj >= 0.0 && qj <= n_j - 1)) return;
  const int j0 = std::min(static_cast<int>(qj), n_j - 2);
  const auto composite = perRow(j0, static_cast<float>(qj - j0));
  const double base_i = f.offset_i + f.shear_i * whole_slice;
  const int oi = job.origin[f.axis_i];
  // The brick's own pixels along the scanline.
  const int own_begin = std::isfinite(job.lo[f.axis_i])
                            ? firstPixel(job.lo[f.axis_i], base_i, inv_scale, f.scale, false)
                            : 0;
  const int own_end = std::isfinite(job.hi[f.axis_i])
                          ? firstPixel(job.hi[f.axis_i], base_i, inv_scale, f.scale, false)
                          : width;
  // With one intermediate pixel a voxel (supersample 1, the default) every sample of the
  // scanline has the same fraction along i, and pixel u's cell is u + i_shift (before the
  // clamp to its run): no arithmetic a pixel. (Each pixel's own (u + base_i) − oi rounds
  // differently only within 2⁻⁴⁴ of the fraction, far below its float.)
  const double q0 = base_i - oi;
  int i_shift = static_cast<int>(q0);
  if (i_shift > q0) --i_shift;  // the floor (std::floor is a libm call on the baseline target)
  const float fi_shared = static_cast<float>(q0 - i_shift);
  const auto cellOf = [&](const CellRun& run, int u, int& i0, float& fi) {
    if (f.scale == 1) {
      i0 = u + i_shift, fi = fi_shared;
      if (i0 < run.begin) i0 = run.begin, fi = 0.f;
      if (i0 > run.end - 1) i0 = run.end - 1, fi = 1.f;
    } else {
      const double qi = (u * inv_scale + base_i) - oi;
      i0 = std::clamp(static_cast<int>(qi), run.begin, run.end - 1);
      // Clamped by max and min, without branches (std::clamp's value for any finite qi).
      fi = std::min(std::max(static_cast<float>(qi - i0), 0.f), 1.f);
    }
  };
  SampleBatch batch;
  // Out of line (see the count below), so it needs the instruction set's attribute itself:
  // without it the batch's whole arithmetic, inlined here, was compiled for the baseline.
  const auto flush = [&]() SVR_SHEARWARP_TARGET {
    job.image->touch(v, batch.u[0], batch.u[batch.count - 1] + 1);  // u rises along a scanline
    composite(batch);
    batch.count = 0;
  };
  for (const CellRun& run : enc.runs(slice, j0)) {
    const int u_begin = std::max(
        {firstPixel(run.begin + oi, base_i, inv_scale, f.scale, false), 0, own_begin});
    // The last cell of a row also holds the samples exactly on the row's last voxel.
    const int u_end = std::min(
        {firstPixel(run.end + oi, base_i, inv_scale, f.scale, run.end == n_i - 1), width,
         own_end});
    // The count in a register (flush, out of line, sees it only when called).
    int n = batch.count;
    const int to_row0 = run.record0 - run.begin, to_row1 = run.record1 - run.begin;
    for (int u = nextLive(links, u_begin); u < u_end; u = nextLive(links, u + 1)) {
      batch.u[n] = u;
      int i0;
      cellOf(run, u, i0, batch.fi[n]);
      batch.r0[n] = i0 + to_row0;
      batch.r1[n] = i0 + to_row1;
      if (++n == SampleBatch::kMax) {
        batch.count = n;
        flush();
        n = 0;
      }
    }
    batch.count = n;
  }
  if (batch.count > 0) flush();
}

// One slice's samples on intermediate scanline v, post-classified.
template <int K, bool kSpectralT>
SVR_SHEARWARP_INLINE void compositeSlice(const CompositeJob& job, int v, int slice,
                                         int* links) {
  const ClassifiedVolume& cv = *job.volume;
  const AxisEncoding& enc = *job.encoding;
  const SliceTable& table = *job.table;
  const int k = K > 0 ? K : cv.k;
  constexpr int kStride = K > 0 ? SliceTable::strideFor(2 + K + (kSpectralT ? K : 1)) : 0;
  constexpr int kWidthCap = SliceTable::strideFor(2 + kMaxChannels + kMaxChannels);
  constexpr int kMax = SampleBatch::kMax;
  const float* white = table.white.data();
  float* row = job.image->pixel(0, v);
  const int stride = job.image->stride;
  forEachSample(job, v, slice, links, [&](int j0, float fj) __attribute__((always_inline)) {
    const VoxelRecord* rec = enc.sliceRecords(slice).data();
    // The row the next scanline adds (rows follow each other in the slice's records): fetched
    // while this scanline composites, a line per sample, since the records stream from beyond
    // the caches. Its voxel is taken to lie as far beyond the sample's record of row j0 + 1 as
    // that row's records are long: exact where the two rows hold the same segments; a hint.
    const int ahead = j0 + 2 < enc.rowCount()
                          ? enc.rowFirst(slice, j0 + 2) - enc.rowFirst(slice, j0 + 1)
                          : 0;
    return [&, rec, ahead, fj](SampleBatch& b) __attribute__((always_inline)) {
      const auto corners = [&](int p, const VoxelRecord* c[4], float w[4]) {
        const int r0 = b.r0[p], r1 = b.r1[p];
        const float fi = b.fi[p];
        c[0] = rec + r0, c[1] = rec + r0 + 1, c[2] = rec + r1, c[3] = rec + r1 + 1;
        w[0] = (1 - fi) * (1 - fj), w[1] = fi * (1 - fj), w[2] = (1 - fi) * fj, w[3] = fi * fj;
      };
      // Stage 1, eight pixels at a time: the records (bin coordinate and gradient, one vector
      // each) interpolated, turned into vectors of bins and of each gradient component (four
      // pixels a vector), then the Phong terms and the two table entries around each bin.
      // Lanes past the batch's end repeat its first pixel and are not used.
      alignas(16) float shade[kMax], highlight[kMax], fracs[kMax];
      alignas(16) int e0s[kMax], e1s[kMax];
      static_assert(sizeof(VoxelRecord) == sizeof(Float4));
      const Float4 fj4 = splat4(fj);
      // Bilinear as three lerps (along i in both rows, then along j): no corner weights.
      const auto blended = [&](int p) {
        const int r0 = b.r0[p], r1 = b.r1[p];
        __builtin_prefetch(rec + r1 + ahead);
        const Float4 fi4 = splat4(b.fi[p]);
        const Float4 a0 = load4(&rec[r0].bin), a1 = load4(&rec[r0 + 1].bin);
        const Float4 b0 = load4(&rec[r1].bin), b1 = load4(&rec[r1 + 1].bin);
        const Float4 top = a0 + fi4 * (a1 - a0), bottom = b0 + fi4 * (b1 - b0);
        return top + fj4 * (bottom - top);
      };
      for (int p = 0; p < b.count; p += 8) {
        const auto lane = [&](int n) { return p + n < b.count ? p + n : 0; };
        Float4 bins[2], gx[2], gy[2], gz[2], lit[2], shiny[2];
        for (int h = 0; h < 2; ++h) {
          bins[h] = blended(lane(4 * h)), gx[h] = blended(lane(4 * h + 1));
          gy[h] = blended(lane(4 * h + 2)), gz[h] = blended(lane(4 * h + 3));
          transpose4(bins[h], gx[h], gy[h], gz[h]);
        }
        phongN<2>(job.phong, gx, gy, gz, lit, shiny);
        for (int h = 0; h < 2; ++h) {
          const int q = p + 4 * h;
          store4(shade + q, lit[h]);
          store4(highlight + q, shiny[h]);
          if (!cv.labels) {
            Int4 e0, e1;
            Float4 frac;
            entriesOfBins(cv, bins[h], e0, e1, frac);
            std::memcpy(e0s + q, &e0, sizeof e0);
            std::memcpy(e1s + q, &e1, sizeof e1);
            store4(fracs + q, frac);
          }
        }
      }
      // Stage 2: classify (the entries found above, or the corners' labels blended) and
      // composite.
      for (int p = 0; p < b.count; ++p) {
        float* S = row + static_cast<std::size_t>(b.u[p]) * stride;
        float tmax;
        if (cv.labels) {
          alignas(16) float acc[(K > 0 ? kStride : kWidthCap) + SliceTable::kSlack];
          const VoxelRecord* c[4];
          float w[4];
          corners(p, c, w);
          blendLabels(table, c, w, K > 0 ? kStride : table.stride, acc);
          tmax = compositeSample<K, kSpectralT>(S, k, acc, acc, 0.f, shade[p], highlight[p],
                                                white);
        } else {
          tmax = compositeSample<K, kSpectralT>(S, k, table.row(e0s[p]), table.row(e1s[p]),
                                                fracs[p], shade[p], highlight[p], white);
        }
        markIfOpaque(links, b.u[p], tmax, job.threshold);
      }
    };
  });
}

// compositeSlice for shearwarp.classification=pre: the four corners' classified records
// blended bilinearly, each shaded from the view's table by its normal index; the interpolated
// α and t corrected for the slice spacing.
template <int K, bool kSpectralT>
SVR_SHEARWARP_INLINE void compositeSlicePre(const CompositeJob& job, int v, int slice,
                                            int* links) {
  const ClassifiedVolume& cv = *job.volume;
  const PreclassifiedAxis& pre = *job.pre;
  const int k = K > 0 ? K : cv.k;
  const int kt = kSpectralT ? k : 1;
  const float* white = cv.white.data();
  const float* terms = job.shading->terms.data();
  const int rs = pre.stride();
  float* row = job.image->pixel(0, v);
  const int stride = job.image->stride;
  forEachSample(job, v, slice, links, [&](int j0, float fj) __attribute__((always_inline)) {
    const float* rec = pre.sliceRecords(slice);
    const std::uint16_t* nrm = pre.sliceNormals(slice);
    return [&, rec, nrm, fj](SampleBatch& b) __attribute__((always_inline)) {
      for (int p = 0; p < b.count; ++p) {
        const int r0 = b.r0[p], r1 = b.r1[p];
        const float fi = b.fi[p];
        const float* c[4] = {rec + std::size_t(r0) * rs, rec + std::size_t(r0 + 1) * rs,
                             rec + std::size_t(r1) * rs, rec + std::size_t(r1 + 1) * rs};
        const std::uint16_t nidx[4] = {nrm[r0], nrm[r0 + 1], nrm[r1], nrm[r1 + 1]};
        const float w[4] = {(1 - fi) * (1 - fj), fi * (1 - fj), (1 - fi) * fj, fi * fj};
        float* S = row + static_cast<std::size_t>(b.u[p]) * stride;
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
          T[ch] *= (*job.transmission_power)(w[0] * c[0][o] + w[1] * c[1][o] +
                                             w[2] * c[2][o] + w[3] * c[3][o]);
          tmax = std::max(tmax, T[ch]);
        }
        markIfOpaque(links, b.u[p], tmax, job.threshold);
      }
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
SVR_SHEARWARP_TARGET void compositeBand(const CompositeJob& job, int v0, int v1,
                                        std::vector<int>& links) {
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

template <bool kSpectralT, bool kPre>
BandFn pickFor(int k, bool dynamic_width) {
  return pickWidth(k, dynamic_width, []<int N>() -> BandFn {
    return &compositeBand<N, kSpectralT, kPre>;
  });
}

inline BandFn pickKernel(const KernelKey& key) {
  if (key.spectral_t)
    return key.pre ? pickFor<true, true>(key.k, key.dynamic_width)
                   : pickFor<true, false>(key.k, key.dynamic_width);
  return key.pre ? pickFor<false, true>(key.k, key.dynamic_width)
                 : pickFor<false, false>(key.k, key.dynamic_width);
}

#undef SVR_SHEARWARP_INLINE

}  // namespace svr::shearwarp::SVR_SHEARWARP_ISA
