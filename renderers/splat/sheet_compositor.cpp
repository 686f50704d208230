#include "renderers/splat/sheet_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/core/fast_exp.h"
#include "renderers/splat/band_state.h"

namespace svr::splat {
namespace {

// A splat while its kernel reaches the current sheet: its footprint box within the band, the
// kernel's world length at each pixel of the box (0 outside the footprint), computed once when
// it becomes active rather than on each of the 3–4 sheets it reaches, and its coefficients.
struct ActiveSplat {
  std::uint32_t id;
  int xa, xb, ya, yb;
  std::size_t weights;  // offset of the box's (xb − xa + 1)(yb − ya + 1) lengths in the pool
  std::size_t coefs;    // offset of sigma_alpha, kt sigma_t, k colour in the pool
};

// Composite the sheet like one raycast sample: α = 1 − exp(−τ), colour = E / τ; the pixels
// are then cleared for the next sheet. (Extinctions are never negative, so a pixel with no
// optical depth holds no colour either.)
void compositeSheet(std::vector<float>& sheet, int stride, int k, int kt, int rx0, int rx1,
                    int ry0, int ry1, BandState& state) {
  const int width = state.width(), y0 = state.y0();
  for (int y = ry0; y <= ry1; ++y)
    for (int x = rx0; x <= rx1; ++x) {
      float* b = &sheet[(static_cast<std::size_t>(y - y0) * width + x) * stride];
      const float tau = b[0];
      bool empty = !(tau > 0.f);
      for (int c = 0; c < kt && empty; ++c) empty = !(b[1 + c] > 0.f);
      if (empty) continue;  // nothing reached this pixel in this sheet: it is still all zero
      const std::size_t p = state.pixel(x, y);
      // exp(−τ) serves the transmission too where the sheet attenuates as it scatters there.
      const float kept = fastExp(-tau);
      if (tau > 0.f) {
        const float alpha_per_tau = (1.f - kept) / tau;
        for (int c = 0; c < k; ++c) {
          const float t = state.transmittance(kt > 1 ? c : 0)[p];
          state.scattered(c)[p] += t * alpha_per_tau * b[1 + kt + c];
        }
      }
      bool attenuated = false;
      for (int c = 0; c < kt; ++c)
        if (b[1 + c] > 0.f) {
          state.transmittance(c)[p] *= b[1 + c] == tau ? kept : fastExp(-b[1 + c]);
          attenuated = true;
        }
      if (attenuated) state.update(x, y);
      std::fill(b, b + stride, 0.f);
    }
}

// One band, sheet by sheet. The sheet buffer holds per pixel: the optical depth of the
// scattering extinction, kt optical depths of the attenuating extinction, and k
// opacity-weighted colours. Splats are front to back, and every splat of one render reaches
// the same depth either side (the kernel seen along the view axis), so they become active and
// retire in the same order: the ones still in reach are always active[live, end).
void compositeBand(const SplatList& list, const FootprintTable& table,
                   std::span<const std::uint32_t> ids, double first_sheet, double thickness,
                   BandState& state) {
  const int k = list.channels(), kt = list.transmittanceChannels();
  const int stride = 1 + kt + k;
  const int width = state.width(), y0 = state.y0(), y1 = state.y1();
  std::vector<float> sheet(static_cast<std::size_t>(y1 - y0) * width * stride, 0.f);
  const auto splats = list.splats();
  const float cut = static_cast<float>(table.cutoff()), cut2 = table.cutoffSquared();
  const float depth_sigma = list.maxDepthSigma();
  const float depth_cut = static_cast<float>(std::min(table.cutoff(), kSheetDepthCut));
  const float reach = depth_cut * depth_sigma;
  const auto below = [&](double t) {
    return t <= -depth_cut ? 0.f : t >= depth_cut ? 1.f : table.cdf(static_cast<float>(t));
  };

  std::vector<ActiveSplat> active;  // front to back; those before `live` have retired
  std::vector<float> pool;          // weights and coefficients of the active splats
  std::size_t live = 0, next = 0;   // next: the first of ids not yet active
  std::vector<float> sigma_t(kt), colour(k);
  long j = 0;
  while (!state.allDone()) {
    if (live == active.size()) {
      if (next == ids.size()) break;
      active.clear();
      pool.clear();
      live = 0;
      // Jump over empty sheets to the first one the next splat reaches.
      j = std::max(j, static_cast<long>(
                          std::floor((splats[ids[next]].depth - reach - first_sheet) / thickness)));
    }
    const double z0 = first_sheet + j * thickness, z1 = z0 + thickness;
    while (live < active.size() && splats[active[live].id].depth + reach <= z0) ++live;
    if (live > active.size() / 2 && live < active.size()) {
      // Drop the retired half of the active list and its pool entries.
      const std::size_t from = active[live].coefs;
      active.erase(active.begin(), active.begin() + static_cast<long>(live));
      live = 0;
      pool.erase(pool.begin(), pool.begin() + static_cast<long>(from));
      for (ActiveSplat& a : active) {
        a.weights -= from;
        a.coefs -= from;
      }
    }
    while (next < ids.size() && splats[ids[next]].depth - reach < z1) {
      const Splat& s = splats[ids[next]];
      const Footprint& fp = list.footprint(ids[next]);
      ActiveSplat a{ids[next]};
      pixelRange(s.x, fp.half_w, width, a.xa, a.xb);
      pixelRange(s.y, fp.half_h, y1, a.ya, a.yb);
      a.ya = std::max(a.ya, y0);
      a.coefs = pool.size();
      SplatCoefficients coef{0.f, sigma_t, colour};
      list.coefficients(s, coef);
      pool.push_back(coef.sigma_alpha);
      pool.insert(pool.end(), sigma_t.begin(), sigma_t.end());
      pool.insert(pool.end(), colour.begin(), colour.end());
      a.weights = pool.size();
      for (int y = a.ya; y <= a.yb; ++y) {
        const float dy = y + 0.5f - s.y;
        const float qy = fp.c * dy * dy, bxy = 2.f * fp.b * dy;
        for (int x = a.xa; x <= a.xb; ++x) {
          const float dx = x + 0.5f - s.x;
          const float q = (fp.a * dx + bxy) * dx + qy;
          pool.push_back(q < cut2 ? fp.norm * table.gaussian(q) : 0.f);
        }
      }
      active.push_back(a);
      ++next;
    }
    int rx0 = width, rx1 = -1, ry0 = y1, ry1 = y0 - 1;  // the sheet's dirty rectangle
    for (std::size_t i = live; i < active.size(); ++i) {
      const ActiveSplat& a = active[i];
      const Splat& s = splats[a.id];
      if (a.xa > a.xb || a.ya > a.yb) continue;
      const float share = below((z1 - s.depth) / depth_sigma) - below((z0 - s.depth) / depth_sigma);
      if (!(share > 0.f) || state.columnsDone(a.xa, a.xb)) continue;
      const float* coef = &pool[a.coefs];
      const float sigma_alpha = coef[0];
      const float* st = coef + 1;
      const float* col = coef + 1 + kt;
      const float* w = &pool[a.weights];
      rx0 = std::min(rx0, a.xa);
      rx1 = std::max(rx1, a.xb);
      ry0 = std::min(ry0, a.ya);
      ry1 = std::max(ry1, a.yb);
      for (int y = a.ya; y <= a.yb; ++y)
        for (int x = a.xa; x <= a.xb; ++x, ++w) {
          if (!(*w > 0.f) || state.done(x, y)) continue;
          const float length = share * *w;  // world length of the kernel in this sheet
          float* b = &sheet[(static_cast<std::size_t>(y - y0) * width + x) * stride];
          const float scatter = sigma_alpha * length;
          b[0] += scatter;
          for (int c = 0; c < kt; ++c) b[1 + c] += st[c] * length;
          for (int c = 0; c < k; ++c) b[1 + kt + c] += scatter * col[c];
        }
    }
    compositeSheet(sheet, stride, k, kt, rx0, rx1, ry0, ry1, state);
    ++j;
  }
}

}  // namespace

void compositeSheets(const SplatList& list, const FootprintTable& table, const Bands& bands,
                     double thickness, float termination, LightIndependentImage& image,
                     ProgressCounter& progress) {
  const auto splats = list.splats();
  // One sheet lattice for the whole image, so neighbouring bands agree.
  const double first_sheet =
      splats.empty() ? 0.0 : splats.front().depth - table.cutoff() * list.maxDepthSigma();
  progress.stage(bands.count);
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands.count; ++b) {
    BandState state(image, b * bands.rows, std::min((b + 1) * bands.rows, image.height()),
                    termination);
    compositeBand(list, table, bands.of(b), first_sheet, thickness, state);
    progress.advance();
  }
}

}  // namespace svr::splat
