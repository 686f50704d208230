#pragma once
// The compositing inner loop of shear-warp: one intermediate scanline through every slice,
// front to back, templated on the channel count K (0 = dynamic) and on spectral (k-channel) or
// scalar transmittance. Per sample it does exactly what raycast_kernel.h does (classify the
// interpolated value, or interpolate the classified labels; Phong with the interpolated
// gradient; S += T ⊙ α(ρ·shade + white·spec·highlight); T ⊙= t), with the tables corrected for
// the slice spacing. Included only by shearwarp_renderer.cpp.
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
#include "renderers/shearwarp/rle_volume.h"
#include "renderers/shearwarp/shear_warp_factorization.h"

namespace svr::shearwarp {

inline constexpr int kMaxChannels = 128;

struct CompositeJob {
  const ClassifiedVolume* volume;
  const AxisEncoding* encoding;
  const ShearWarpFactorization* view;
  const float* alpha;         // entries: opacity for the slice spacing
  const float* transmission;  // entries × t_channels: transmission for the slice spacing
  float threshold;
  PhongSetup phong;  // light and half vectors are unit, world
  IntermediateImage* image;
};

inline int nextLive(std::vector<int>& links, int u) {
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

template <int K, bool kSpectralT>
void compositeScanline(const CompositeJob& job, int v, std::vector<int>& links) {
  const ClassifiedVolume& cv = *job.volume;
  const AxisEncoding& enc = *job.encoding;
  const ShearWarpFactorization& f = *job.view;
  IntermediateImage& im = *job.image;
  const int k = K > 0 ? K : cv.k;
  constexpr int kCap = K > 0 ? K : kMaxChannels;
  const int kt = kSpectralT ? k : 1;
  const int width = im.width;
  const int n_i = enc.rowLength(), n_j = enc.rowCount(), n_k = enc.slices();
  const double inv_scale = 1.0 / f.scale;

  links.resize(width + 1);
  for (int u = 0; u <= width; ++u) links[u] = u;
  float* row = im.pixel(0, v);
  const int stride = im.channels();

  for (int step = 0; step < n_k; ++step) {
    const int slice = f.increasing ? step : n_k - 1 - step;
    const double qj = v * inv_scale + f.offset_j + f.shear_j * slice;
    if (!(qj >= 0.0 && qj <= n_j - 1)) continue;
    const int j0 = std::min(static_cast<int>(qj), n_j - 2);
    const float fj = static_cast<float>(qj - j0);
    const double base_i = f.offset_i + f.shear_i * slice;
    for (const CellRun& run : enc.runs(slice, j0)) {
      const int u_begin = std::max(firstPixel(run.begin, base_i, inv_scale, f.scale, false), 0);
      // The last cell of a row also holds the samples exactly on the row's last voxel.
      const int u_end =
          std::min(firstPixel(run.end, base_i, inv_scale, f.scale, run.end == n_i - 1), width);
      for (int u = nextLive(links, u_begin); u < u_end; u = nextLive(links, u + 1)) {
        const double qi = u * inv_scale + base_i;
        const int i0 = std::clamp(static_cast<int>(std::floor(qi)), run.begin, run.end - 1);
        const float fi = std::clamp(static_cast<float>(qi - i0), 0.f, 1.f);
        const VoxelRecord* c[4] = {
            &enc.voxel(slice, j0, i0), &enc.voxel(slice, j0, i0 + 1),
            &enc.voxel(slice, j0 + 1, i0), &enc.voxel(slice, j0 + 1, i0 + 1)};
        const float w[4] = {(1 - fi) * (1 - fj), fi * (1 - fj), (1 - fi) * fj, fi * fj};

        float alpha, spec_w, refl[kCap], trans[kSpectralT ? kCap : 1];
        if (cv.labels) {
          int entry[4];
          for (int n = 0; n < 4; ++n) entry[n] = static_cast<int>(c[n]->value);
          blendEntries(cv, job.alpha, job.transmission, entry, w, 4, k, kt, alpha, spec_w, refl,
                       trans);
        } else {
          float value = 0.f;
          for (int n = 0; n < 4; ++n) value += w[n] * c[n]->value;
          int entry[2];
          float frac;
          binOf(cv, value, entry[0], entry[1], frac);
          const float wb[2] = {1.f - frac, frac};
          blendEntries(cv, job.alpha, job.transmission, entry, wb, 2, k, kt, alpha, spec_w, refl,
                       trans);
        }
        float* px = row + static_cast<std::size_t>(u) * stride;
        float* S = px;
        float* T = px + k;
        if (alpha > 0.f) {
          float g[3] = {0.f, 0.f, 0.f};
          for (int n = 0; n < 4; ++n)
            for (int a = 0; a < 3; ++a) g[a] += w[n] * c[n]->gradient[a];
          const auto [shade, highlight] = phong(job.phong, g);
          const float hs = highlight * spec_w;
          for (int ch = 0; ch < k; ++ch)
            S[ch] += T[kSpectralT ? ch : 0] * alpha * (refl[ch] * shade + cv.white[ch] * hs);
        }
        float tmax = 0.f;
        for (int ch = 0; ch < kt; ++ch) {
          T[ch] *= trans[ch];
          tmax = std::max(tmax, T[ch]);
        }
        if (tmax < job.threshold) links[u] = u + 1;  // opaque: skip it from now on
      }
    }
    if (nextLive(links, 0) >= width) break;  // the whole scanline is opaque
  }
}

}  // namespace svr::shearwarp
