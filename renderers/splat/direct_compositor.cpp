#include "renderers/splat/direct_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/splat/band_state.h"

namespace svr::splat {
namespace {

void compositeBand(const SplatList& list, const FootprintTable& table,
                   std::span<const std::uint32_t> ids, BandState& state) {
  const int k = list.channels(), kt = list.transmittanceChannels();
  const int width = state.width(), y0 = state.y0(), y1 = state.y1();
  std::vector<float> sigma_t(kt), colour(k);
  SplatCoefficients coef{0.f, sigma_t, colour};
  const auto splats = list.splats();
  const float cut2 = table.cutoffSquared();
  for (const std::uint32_t id : ids) {
    if (state.allDone()) break;
    const Splat& s = splats[id];
    const Footprint& fp = list.footprint(id);
    int xa, xb, ya, yb;
    pixelRange(s.x, fp.half_w, width, xa, xb);
    pixelRange(s.y, fp.half_h, y1, ya, yb);
    ya = std::max(ya, y0);
    if (xa > xb || ya > yb || state.columnsDone(xa, xb)) continue;
    list.coefficients(s, coef);
    for (int y = ya; y <= yb; ++y) {
      const float dy = y + 0.5f - s.y;
      for (int x = xa; x <= xb; ++x) {
        const float dx = x + 0.5f - s.x;
        const float q = fp.a * dx * dx + 2.f * fp.b * dx * dy + fp.c * dy * dy;
        if (q >= cut2 || state.done(x, y)) continue;
        const float length = fp.norm * table.gaussian(q);  // world length of kernel on the ray
        const std::size_t p = state.pixel(x, y);
        const float alpha = -std::expm1(-coef.sigma_alpha * length);
        for (int c = 0; c < k; ++c)
          state.scattered(c)[p] += state.transmittance(kt > 1 ? c : 0)[p] * alpha * colour[c];
        bool attenuated = false;
        for (int c = 0; c < kt; ++c)
          if (sigma_t[c] > 0.f) {
            state.transmittance(c)[p] *= std::exp(-sigma_t[c] * length);
            attenuated = true;
          }
        if (attenuated) state.update(x, y);
      }
    }
  }
}

}  // namespace

void compositeDirect(const SplatList& list, const FootprintTable& table, const Bands& bands,
                     float termination, LightIndependentImage& image, ProgressCounter& progress) {
  progress.stage(bands.count);
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands.count; ++b) {
    BandState state(image, b * bands.rows, std::min((b + 1) * bands.rows, image.height()),
                    termination);
    compositeBand(list, table, bands.of(b), state);
    progress.advance();
  }
}

}  // namespace svr::splat
