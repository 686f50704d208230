#include "renderers/splat/sheet_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/splat/band_state.h"

namespace svr::splat {
namespace {

// One band, sheet by sheet. The sheet buffer holds per pixel: the optical depth of the
// scattering extinction, kt optical depths of the attenuating extinction, and k
// opacity-weighted colours.
void compositeBand(const SplatList& list, const FootprintTable& table,
                   std::span<const std::uint32_t> ids, double first_sheet, double thickness,
                   BandState& state) {
  const int k = list.channels(), kt = list.transmittanceChannels();
  const int stride = 1 + kt + k;
  const int width = state.width(), y0 = state.y0(), y1 = state.y1();
  std::vector<float> sheet(static_cast<std::size_t>(y1 - y0) * width * stride, 0.f);
  // The coefficients of every active splat, computed once when it becomes active rather than
  // on each of the sheets it reaches: sigma_alpha, kt sigma_t, k colour per splat.
  const int coef_stride = 1 + kt + k;
  std::vector<float> coefs;
  const auto splats = list.splats();
  const float cut = static_cast<float>(table.cutoff()), cut2 = table.cutoffSquared();
  // Every splat of one render has the same depth σ (the kernel seen along the view axis).
  const float depth_sigma = list.maxDepthSigma();
  const float reach = cut * depth_sigma;

  std::vector<std::uint32_t> active;  // positions in ids, front to back
  std::size_t next = 0;
  long j = 0;
  while (!state.allDone()) {
    if (active.empty()) {
      if (next == ids.size()) break;
      // Jump over empty sheets to the first one the next splat reaches.
      j = std::max(j, static_cast<long>(
                          std::floor((splats[ids[next]].depth - reach - first_sheet) / thickness)));
    }
    const double z0 = first_sheet + j * thickness, z1 = z0 + thickness;
    while (next < ids.size() && splats[ids[next]].depth - reach < z1) {
      const std::size_t at = coefs.size();
      coefs.resize(at + coef_stride);
      SplatCoefficients coef{0.f, {&coefs[at + 1], static_cast<std::size_t>(kt)},
                             {&coefs[at + 1 + kt], static_cast<std::size_t>(k)}};
      list.coefficients(splats[ids[next]], coef);
      coefs[at] = coef.sigma_alpha;
      active.push_back(next++);
    }
    int rx0 = width, rx1 = -1, ry0 = y1, ry1 = y0 - 1;  // the sheet's dirty rectangle
    std::size_t kept = 0;
    for (std::size_t slot = 0; slot < active.size(); ++slot) {
      const std::uint32_t a = active[slot];
      const std::uint32_t id = ids[a];
      const Splat& s = splats[id];
      if (s.depth + reach <= z0) continue;  // wholly in front of this sheet: retired
      float* coef = &coefs[kept * coef_stride];
      if (kept != slot)
        std::copy_n(&coefs[slot * coef_stride], coef_stride, coef);
      active[kept++] = a;
      const float share = table.cdf(static_cast<float>((z1 - s.depth) / depth_sigma)) -
                          table.cdf(static_cast<float>((z0 - s.depth) / depth_sigma));
      if (!(share > 0.f)) continue;
      const Footprint& fp = list.footprint(id);
      int xa, xb, ya, yb;
      pixelRange(s.x, fp.half_w, width, xa, xb);
      pixelRange(s.y, fp.half_h, y1, ya, yb);
      ya = std::max(ya, y0);
      if (xa > xb || ya > yb || state.columnsDone(xa, xb)) continue;
      const float sigma_alpha = coef[0];
      const float* sigma_t = coef + 1;
      const float* colour = coef + 1 + kt;
      const float weight = fp.norm * share;
      for (int y = ya; y <= yb; ++y) {
        const float dy = y + 0.5f - s.y;
        for (int x = xa; x <= xb; ++x) {
          const float dx = x + 0.5f - s.x;
          const float q = fp.a * dx * dx + 2.f * fp.b * dx * dy + fp.c * dy * dy;
          if (q >= cut2 || state.done(x, y)) continue;
          const float length = weight * table.gaussian(q);  // world length of kernel in sheet
          float* b = &sheet[(static_cast<std::size_t>(y - y0) * width + x) * stride];
          const float scatter = sigma_alpha * length;
          b[0] += scatter;
          for (int c = 0; c < kt; ++c) b[1 + c] += sigma_t[c] * length;
          for (int c = 0; c < k; ++c) b[1 + kt + c] += scatter * colour[c];
          rx0 = std::min(rx0, x);
          rx1 = std::max(rx1, x);
          ry0 = std::min(ry0, y);
          ry1 = std::max(ry1, y);
        }
      }
    }
    active.resize(kept);
    coefs.resize(kept * coef_stride);

    // Composite the sheet like one raycast sample: α = 1 − exp(−τ), colour = E / τ.
    for (int y = ry0; y <= ry1; ++y)
      for (int x = rx0; x <= rx1; ++x) {
        float* b = &sheet[(static_cast<std::size_t>(y - y0) * width + x) * stride];
        const std::size_t p = state.pixel(x, y);
        const float tau = b[0];
        if (tau > 0.f) {
          const float alpha_per_tau = -std::expm1(-tau) / tau;
          for (int c = 0; c < k; ++c) {
            const float t = state.transmittance(kt > 1 ? c : 0)[p];
            state.scattered(c)[p] += t * alpha_per_tau * b[1 + kt + c];
          }
        }
        bool attenuated = false;
        for (int c = 0; c < kt; ++c)
          if (b[1 + c] > 0.f) {
            state.transmittance(c)[p] *= std::exp(-b[1 + c]);
            attenuated = true;
          }
        if (attenuated) state.update(x, y);
        std::fill(b, b + stride, 0.f);
      }
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
