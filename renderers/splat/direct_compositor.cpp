#include "renderers/splat/direct_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/core/channel_widths.h"
#include "renderers/core/fast_exp.h"
#include "renderers/core/float4.h"
#include "renderers/splat/band_state.h"

namespace svr::splat {
namespace {

// One splat on one band: its coefficients, and where and how it draws.
struct SplatInk {
  float sigma_alpha;
  std::span<const float> sigma_t;
  const float* colour;
  bool attenuates;  // some σ_t > 0 (not x-ray)
  bool same;        // one transmittance channel and σ_t = σ_α: one exponential (achromatic)
};

// The image's planes: channel c of pixel p at S[c · plane + p] and T[c · plane + p].
struct Planes {
  float* S;
  float* T;
  std::size_t plane;
};

// Row y's pixels x, x + 1, … four at a time while four remain within hi, for one transmittance
// channel: each lane takes the one-at-a-time loop's operations in its order (so a pixel gets
// the same floats either way), pixels outside the ellipse or finished given α = 0 and kept = 1,
// which leave S and T as they are. Returns the first pixel it left.
template <int K>
int compositeFours(const Footprint& fp, float sx, float bxy, float qy, const FootprintTable& table,
                   float cut2, const SplatInk& ink, int k, const Planes& img, BandState& state,
                   int y, int x, int hi) {
  const Float4 offsets{0.5f, 1.5f, 2.5f, 3.5f};
  const Float4 one = splat4(1.f);
  const std::uint8_t* done = state.doneRow(y);
  for (; x + 3 <= hi; x += 4) {
    const Float4 dx = (splat4(static_cast<float>(x)) + offsets) - sx;
    const Float4 q = (fp.a * dx + bxy) * dx + qy;
    const Int4 finished{done[x], done[x + 1], done[x + 2], done[x + 3]};
    const Int4 draws = (q < cut2) & (finished == 0);
    if (!(draws[0] | draws[1] | draws[2] | draws[3])) continue;
    Float4 length;
    for (int m = 0; m < 4; ++m) length[m] = fp.norm * table.gaussian(draws[m] ? q[m] : 0.f);
    const Float4 kept = draws ? fastExp(-ink.sigma_alpha * length) : one;
    const Float4 alpha = one - kept;
    const std::size_t p = state.pixel(x, y);
    const Float4 t = load4(img.T + p);
    const Float4 t_alpha = t * alpha;
    for (int c = 0; c < (K > 0 ? K : k); ++c) {
      float* S = img.S + c * img.plane + p;
      store4(S, load4(S) + t_alpha * ink.colour[c]);
    }
    if (!ink.attenuates) continue;
    const Float4 kept_t =
        ink.same ? kept : (draws ? fastExp(-ink.sigma_t[0] * length) : one);
    const Float4 t_after = t * kept_t;
    store4(img.T + p, t_after);
    // update(): the drawn pixels whose T fell below the threshold are finished.
    const Int4 finishing = draws & (t_after < state.termination());
    if (finishing[0] | finishing[1] | finishing[2] | finishing[3])
      for (int m = 0; m < 4; ++m)
        if (finishing[m]) state.finish(x + m, y);
  }
  return x;
}

// K: the channel count when it is one of the compiled widths (channel_widths.h), so the
// per-pixel channel loops unroll; 0 for any k. Both do each pixel's arithmetic alike.
template <int K>
void compositeBand(const SplatList& list, const FootprintTable& table,
                   std::span<const std::uint32_t> ids, BandState& state) {
  const int k = K > 0 ? K : list.channels(), kt = list.transmittanceChannels();
  const int width = state.width(), y0 = state.y0(), y1 = state.y1();
  std::vector<float> sigma_t(kt), colour(k);
  SplatCoefficients coef{0.f, sigma_t, colour};
  const auto splats = list.splats();
  const float cut2 = table.cutoffSquared();
  const Planes img{state.scattered(0), state.transmittance(0), state.planePixels()};
  float* const S = img.S;
  float* const T = img.T;
  const std::size_t plane = img.plane;
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
    const SplatInk ink{coef.sigma_alpha, sigma_t, colour.data(), attenuates,
                       kt == 1 && sigma_t[0] == coef.sigma_alpha};
    const float* const col = ink.colour;
    for (int y = ya; y <= yb; ++y) {
      const float dy = y + 0.5f - s.y;
      const float qy = fp.c * dy * dy, bxy = 2.f * fp.b * dy;
      int lo, hi;
      ellipseRow(fp, s.x, dy, cut2, xa, xb, lo, hi);
      if (kt == 1)
        lo = compositeFours<K>(fp, s.x, bxy, qy, table, cut2, ink, k, img, state, y, lo, hi);
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
          const float t_alpha = T[p] * alpha;
          for (int c = 0; c < k; ++c) S[c * plane + p] += t_alpha * col[c];
        } else {
          for (int c = 0; c < k; ++c) S[c * plane + p] += T[c * plane + p] * alpha * col[c];
        }
        if (!attenuates) continue;
        if (ink.same) {
          T[p] *= kept;
        } else {
          for (int c = 0; c < kt; ++c)
            if (sigma_t[c] > 0.f) T[c * plane + p] *= fastExp(-sigma_t[c] * length);
        }
        state.update(x, y);
      }
    }
  }
}

}  // namespace

void compositeDirect(const SplatList& list, const FootprintTable& table, const Bands& bands,
                     float termination, bool dynamic_width, LightIndependentImage& image,
                     ProgressCounter& progress) {
  const auto band_kernel = pickWidth(list.channels(), dynamic_width,
                                     []<int N>() { return &compositeBand<N>; });
  progress.stage(bands.count);
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands.count; ++b) {
    BandState state(image, b * bands.rows, std::min((b + 1) * bands.rows, image.height()),
                    termination);
    band_kernel(list, table, bands.of(b), state);
    progress.advance();
  }
}

}  // namespace svr::splat
