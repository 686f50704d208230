#include "renderers/splat/direct_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/core/fast_exp.h"
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
    bool attenuates = false;
    for (int c = 0; c < kt; ++c) attenuates = attenuates || sigma_t[c] > 0.f;
    // One exponential where the splat attenuates as it scatters (not x-ray, achromatic).
    const bool same = kt == 1 && sigma_t[0] == coef.sigma_alpha;
    for (int y = ya; y <= yb; ++y) {
      const float dy = y + 0.5f - s.y;
      const float qy = fp.c * dy * dy, bxy = 2.f * fp.b * dy;
      int lo, hi;
      ellipseRow(fp, s.x, dy, cut2, xa, xb, lo, hi);
      for (int x = lo; x <= hi; ++x) {
        const float dx = x + 0.5f - s.x;
        const float q = (fp.a * dx + bxy) * dx + qy;
        if (q >= cut2 || state.done(x, y)) continue;
        const float length = fp.norm * table.gaussian(q);  // world length of kernel on the ray
        const std::size_t p = state.pixel(x, y);
        const float kept = fastExp(-coef.sigma_alpha * length);
        const float alpha = 1.f - kept;
        if (kt == 1) {
          // One T for every channel: read once (S and T share the image's storage, so the
          // compiler would reload it after each S store), with the loop's arithmetic below.
          const float t_alpha = state.transmittance(0)[p] * alpha;
          for (int c = 0; c < k; ++c) state.scattered(c)[p] += t_alpha * colour[c];
        } else {
          for (int c = 0; c < k; ++c)
            state.scattered(c)[p] += state.transmittance(c)[p] * alpha * colour[c];
        }
        if (!attenuates) continue;
        if (same) {
          state.transmittance(0)[p] *= kept;
        } else {
          for (int c = 0; c < kt; ++c)
            if (sigma_t[c] > 0.f) state.transmittance(c)[p] *= fastExp(-sigma_t[c] * length);
        }
        state.update(x, y);
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
