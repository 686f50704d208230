#include "renderers/splat/direct_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/simd/channel_widths.h"
#include "renderers/simd/fast_exp.h"
#include "renderers/simd/float4.h"
#include "renderers/splat/band_state.h"
#include "renderers/splat/splat_coverage.h"

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

// Row y's pixels [lo, hi] of one splat, with the kernel's world length at each (zero outside
// the ellipse, and for three columns past hi). With one transmittance channel they
// go four at a time while four fit within the image, each lane taking the one-at-a-time loop's
// operations in its order (so a pixel gets the same floats either way); pixels outside the
// ellipse or finished are given α = 0 and kept = 1, which leave S and T as they are.
//
// Lengths: lengths4(x), pixels x … x + 3's lengths (from a copied row, or computed from the
// factors as they are needed).
template <int K, class Lengths>
void compositeRow(const Lengths& lengths4, int lo, int hi, const SplatInk& ink, int k, int kt,
                  const Planes& img, BandState& state, int y) {
  const std::uint8_t* done = state.doneRow(y);
  const std::size_t row = state.pixel(0, y);
  int x = lo;
  if (kt == 1) {
    const Float4 one = splat4(1.f), zero = splat4(0.f);
    const int last = std::min(hi, state.width() - 4);  // four columns fit from here on
    for (; x <= last; x += 4) {
      const Float4 length = lengths4(x);
      const Int4 finished{done[x], done[x + 1], done[x + 2], done[x + 3]};
      const Int4 draws = (length > zero) & (finished == 0);
      if (!(draws[0] | draws[1] | draws[2] | draws[3])) continue;
      const Float4 kept = draws ? fastExp(-ink.sigma_alpha * length) : one;
      const Float4 alpha = one - kept;
      const std::size_t p = row + x;
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
  }
  float* const S = img.S;
  float* const T = img.T;
  const std::size_t plane = img.plane;
  for (; x <= hi; ++x) {
    const float length = lengths4(x)[0];
    if (!(length > 0.f) || done[x]) continue;
    const std::size_t p = row + x;
    const float kept = fastExp(-ink.sigma_alpha * length);
    const float alpha = 1.f - kept;
    if (kt == 1) {
      // One T for every channel: read once (S and T share the image's storage, so the
      // compiler would reload it after each S store), with the loop's arithmetic below.
      const float t_alpha = T[p] * alpha;
      for (int c = 0; c < (K > 0 ? K : k); ++c) S[c * plane + p] += t_alpha * ink.colour[c];
    } else {
      for (int c = 0; c < k; ++c) S[c * plane + p] += T[c * plane + p] * alpha * ink.colour[c];
    }
    if (!ink.attenuates) continue;
    if (ink.same) {
      T[p] *= kept;
    } else {
      for (int c = 0; c < kt; ++c)
        if (ink.sigma_t[c] > 0.f) T[c * plane + p] *= fastExp(-ink.sigma_t[c] * length);
    }
    state.update(x, y);
  }
}

// K: the channel count when it is one of the compiled widths (channel_widths.h), so the
// per-pixel channel loops unroll; 0 for any k. Both do each pixel's arithmetic alike.
template <int K>
void compositeBand(const SplatCoverage& coverage, std::span<const std::uint32_t> ids,
                   BandState& state) {
  const SplatList& list = coverage.list();
  const int k = K > 0 ? K : list.channels(), kt = list.transmittanceChannels();
  const int y0 = state.y0(), y1 = state.y1();
  std::vector<float> sigma_t(kt), colour(k);
  SplatCoefficients coef{0.f, sigma_t, colour};
  const auto splats = list.splats();
  const Planes img{state.scattered(0), state.transmittance(0), state.planePixels()};
  SplatRows rows(coverage);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (state.allDone()) break;
    // The band's ids rise with gaps the hardware prefetcher cannot follow: ask for a later one.
    constexpr std::size_t kAhead = 8;
    if (i + kAhead < ids.size()) __builtin_prefetch(&splats[ids[i + kAhead]]);
    const std::uint32_t id = ids[i];
    SplatRows::Box box = rows.start(id);
    box.ya = std::max(box.ya, y0);
    box.yb = std::min(box.yb, y1 - 1);
    if (box.xa > box.xb || box.ya > box.yb || state.columnsDone(box.xa, box.xb)) continue;
    list.coefficients(splats[id], coef);
    bool attenuates = false;
    for (int c = 0; c < kt; ++c) attenuates = attenuates || sigma_t[c] > 0.f;
    const SplatInk ink{coef.sigma_alpha, sigma_t, colour.data(), attenuates,
                       kt == 1 && sigma_t[0] == coef.sigma_alpha};
    for (int y = box.ya; y <= box.yb; ++y) {
      if (rows.factored()) {
        // The box's columns, their lengths computed four at a time as they are composited.
        const SplatRows::FactoredRow f = rows.factoredLengths(y);
        compositeRow<K>([&f](int x) { return f.lengths4(x); }, box.xa, box.xb, ink, k, kt, img,
                        state, y);
        continue;
      }
      int lo, hi;
      const float* w = rows.row(y, lo, hi);
      if (lo <= hi)
        compositeRow<K>([w, lo](int x) { return load4(w + (x - lo)); }, lo, hi, ink, k, kt, img,
                        state, y);
    }
  }
}

}  // namespace

void compositeDirect(const SplatCoverage& coverage, const Bands& bands, float termination,
                     bool dynamic_width, LightIndependentImage& image, ProgressCounter& progress) {
  const auto band_kernel = pickWidth(coverage.list().channels(), dynamic_width,
                                     []<int N>() { return &compositeBand<N>; });
  progress.stage(bands.count);
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands.count; ++b) {
    if (progress.stopped()) continue;  // the rest is skipped, then Cancelled
    BandState state(image, b * bands.rows, std::min((b + 1) * bands.rows, image.height()),
                    termination);
    band_kernel(coverage, bands.of(b), state);
    progress.advance();
  }
}

}  // namespace svr::splat
