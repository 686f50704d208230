#include "renderers/splat/sheet_compositor.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderers/simd/fast_exp.h"
#include "renderers/simd/float4.h"
#include "renderers/splat/band_state.h"
#include "renderers/splat/splat_coverage.h"

namespace svr::splat {
namespace {

// A splat while its kernel reaches the current sheet: its footprint box within the band, per row
// of the box the chord of its ellipse, the kernel's world length at each pixel of the chords
// (computed once when it becomes active rather than on each of the 3–4 sheets it reaches), and
// its coefficients. Its depth is copied here because the splat itself, read through a band's
// sparse list of ids, is a cache miss each time.
struct ActiveSplat {
  std::uint32_t id;
  float depth = 0.f;
  int xa = 0, xb = -1, ya = 0, yb = -1;
  std::size_t chords = 0;  // offset of its rows' chords in the chord pool
  std::size_t coefs = 0;   // offset of its payload (SheetContent::payload) in the pool
  // Sheet j's near side in the kernel's σ along the view axis: t0 + j · (thickness / σ).
  double t0 = 0.0;
  // The kernel's share below the far side of the last sheet it reached (sheet `below_sheet`),
  // which is its share below the near side of the next one.
  long below_sheet = -2;
  float below_far = 0.f;
};

// Composite one sheet pixel like one raycast sample: α = 1 − exp(−τ), colour = E / τ, from the
// optical depth τ of the extinction that scatters, kt optical depths of the extinction that
// attenuates and the k opacity-weighted colours E. (Extinctions are never negative, so a pixel
// with no optical depth holds no colour either.)
void compositePixel(int x, int y, float tau, const float* tau_t, const float* e, int k, int kt,
                    BandState& state) {
  const std::size_t p = state.pixel(x, y);
  // exp(−τ) serves the transmission too where the sheet attenuates as it scatters there.
  const float kept = fastExp(-tau);
  if (tau > 0.f) {
    const float alpha_per_tau = (1.f - kept) / tau;
    for (int c = 0; c < k; ++c) {
      const float t = state.transmittance(kt > 1 ? c : 0)[p];
      state.scattered(c)[p] += t * alpha_per_tau * e[c];
    }
  }
  bool attenuated = false;
  for (int c = 0; c < kt; ++c)
    if (tau_t[c] > 0.f) {
      state.transmittance(c)[p] *= tau_t[c] == tau ? kept : fastExp(-tau_t[c]);
      attenuated = true;
    }
  if (attenuated) state.update(x, y);
}

// What a sheet pixel accumulates, and how it becomes a sample.
//
// Pre-classified: the splats' own optical depths and opacity-weighted colours add up.
// Post-classified ("splatting without the blur", Mueller, Möller & Crawfis 1999): the kernels'
// world lengths L, and their sums weighted by each splat's bin coordinate, shade and highlight;
// the pixel's value is the normalised sum, classified and shaded there, over the length L.
class SheetContent {
 public:
  SheetContent(const SplatList& list, bool post)
      : list_(list),
        post_(post),
        k_(list.channels()),
        kt_(list.transmittanceChannels()),
        sigma_t_(kt_),
        colour_(k_),
        tau_t_(kt_),
        e_(k_) {}
  int stride() const { return post_ ? 4 : 1 + kt_ + k_; }
  // Appends what a splat contributes per unit length: post, 1 (for L), its bin, shade and
  // highlight, so that a pixel takes it as one four-lane multiply-add; pre, sigma_alpha, kt
  // sigma_t and k colours.
  void payload(const Splat& s, std::vector<float>& pool) {
    if (post_) {
      pool.insert(pool.end(), {1.f, static_cast<float>(s.entry) + s.frac, s.shade, s.highlight});
      return;
    }
    SplatCoefficients coef{0.f, sigma_t_, colour_};
    list_.coefficients(s, coef);
    pool.push_back(coef.sigma_alpha);
    pool.insert(pool.end(), sigma_t_.begin(), sigma_t_.end());
    pool.insert(pool.end(), colour_.begin(), colour_.end());
  }
  // A splat's kernel over `length` world units of the sheet at pixel b.
  void add(const float* payload, float length, float* b) const {
    if (post_) {
      store4(b, load4(b) + length * load4(payload));
      return;
    }
    const float scatter = payload[0] * length;
    b[0] += scatter;
    for (int c = 0; c < kt_; ++c) b[1 + c] += payload[1 + c] * length;
    for (int c = 0; c < k_; ++c) b[1 + kt_ + c] += scatter * payload[1 + kt_ + c];
  }
  // Composites pixel (x, y) of the sheet, if anything reached it and it is not finished, and
  // clears it.
  void composite(float* b, int x, int y, BandState& state) {
    bool empty = !(b[0] > 0.f);
    for (int c = 0; c < kt_ && empty && !post_; ++c) empty = !(b[1 + c] > 0.f);
    if (empty) return;  // nothing reached this pixel in this sheet: it is still all zero
    if (state.done(x, y)) {
      // Splats are added to finished pixels too (one test a sheet pixel, not one a kernel
      // there); what they added is dropped, as early termination drops the rest of a ray.
    } else if (!post_) {
      compositePixel(x, y, b[0], b + 1, b + 1 + kt_, k_, kt_, state);
    } else {
      const float length = b[0], inv = 1.f / length;
      SplatCoefficients coef{0.f, sigma_t_, colour_};
      list_.classifyBin(b[1] * inv, b[2] * inv, b[3] * inv, coef);
      const float tau = coef.sigma_alpha * length;
      for (int c = 0; c < kt_; ++c) tau_t_[c] = sigma_t_[c] * length;
      for (int c = 0; c < k_; ++c) e_[c] = tau * colour_[c];
      compositePixel(x, y, tau, tau_t_.data(), e_.data(), k_, kt_, state);
    }
    std::fill(b, b + stride(), 0.f);
  }

 private:
  const SplatList& list_;
  bool post_;
  int k_, kt_;
  std::vector<float> sigma_t_, colour_, tau_t_, e_;  // scratch
};

// Composite the sheet's dirty rectangle; its pixels are cleared for the next sheet.
void compositeSheet(std::vector<float>& sheet, SheetContent& content, int rx0, int rx1, int ry0,
                    int ry1, BandState& state) {
  const int width = state.width(), y0 = state.y0(), stride = content.stride();
  for (int y = ry0; y <= ry1; ++y)
    for (int x = rx0; x <= rx1; ++x)
      content.composite(&sheet[(static_cast<std::size_t>(y - y0) * width + x) * stride], x, y,
                        state);
}

// A row of an active splat: its pixels [lo, hi] and where their kernel lengths start in the pool.
struct Chord {
  int lo, hi;
  std::size_t lengths;
};

// Splat `id` made active: its box within the band, its payload and its rows' chords and lengths
// appended to the pools. A splat over finished pixels adds nothing: it stays in the list (to
// retire in order) with an empty box, and its rows are never evaluated.
ActiveSplat activate(std::uint32_t id, double t0, SplatRows& rows, SheetContent& content,
                     const BandState& state, std::vector<float>& pool,
                     std::vector<Chord>& chord_pool) {
  const Splat& s = rows.coverage().list().splats()[id];
  ActiveSplat a{id, s.depth};
  a.t0 = t0;
  const SplatRows::Box box = rows.start(id);
  a.xa = box.xa;
  a.xb = box.xb;
  a.ya = std::max(box.ya, state.y0());
  a.yb = std::min(box.yb, state.y1() - 1);
  if (a.xa <= a.xb && a.ya <= a.yb && state.columnsDone(a.xa, a.xb)) a.xb = a.xa - 1;
  a.coefs = pool.size();
  a.chords = chord_pool.size();
  if (a.xa > a.xb || a.ya > a.yb) return a;
  content.payload(s, pool);
  for (int y = a.ya; y <= a.yb; ++y) {
    Chord c;
    const float* lengths = rows.row(y, c.lo, c.hi);
    c.lengths = pool.size();
    if (c.lo <= c.hi) pool.insert(pool.end(), lengths, lengths + (c.hi - c.lo + 1));
    chord_pool.push_back(c);
  }
  return a;
}

// One band, sheet by sheet; the sheet buffer holds per pixel what SheetContent accumulates.
// Splats are front to back, and every splat of one render reaches
// the same depth either side (the kernel seen along the view axis), so they become active and
// retire in the same order: the ones still in reach are always active[live, end).
void compositeBand(const SplatCoverage& coverage, std::span<const std::uint32_t> ids,
                   double first_sheet, double thickness, bool post, BandState& state) {
  const SplatList& list = coverage.list();
  const FootprintTable& table = coverage.table();
  SplatRows rows(coverage);
  SheetContent content(list, post);
  const int stride = content.stride();
  const int width = state.width(), y0 = state.y0(), y1 = state.y1();
  std::vector<float> sheet(static_cast<std::size_t>(y1 - y0) * width * stride, 0.f);
  const auto splats = list.splats();
  const float depth_sigma = list.maxDepthSigma();
  const float depth_cut = static_cast<float>(std::min(table.cutoff(), kSheetDepthCut));
  const float reach = depth_cut * depth_sigma;
  const auto below = [&](double t) {
    return t <= -depth_cut ? 0.f : t >= depth_cut ? 1.f : table.cdf(static_cast<float>(t));
  };
  const double sheet_sigmas = thickness / depth_sigma;  // a sheet's thickness in σ

  std::vector<ActiveSplat> active;  // front to back; those before `live` have retired
  std::vector<float> pool;          // payloads (and evaluated lengths) of the active splats
  std::vector<Chord> chord_pool;    // their rows' chords
  std::size_t live = 0, next = 0;   // next: the first of ids not yet active
  long j = 0;
  while (!state.allDone()) {
    if (live == active.size()) {
      if (next == ids.size()) break;
      active.clear();
      pool.clear();
      chord_pool.clear();
      live = 0;
      // Jump over empty sheets to the first one the next splat reaches.
      j = std::max(j, static_cast<long>(
                          std::floor((splats[ids[next]].depth - reach - first_sheet) / thickness)));
    }
    // Both sides by the same formula, so that a sheet's far side is the next one's near side
    // to the bit (ActiveSplat::below_far).
    const double z0 = first_sheet + j * thickness, z1 = first_sheet + (j + 1) * thickness;
    while (live < active.size() && active[live].depth + reach <= z0) ++live;
    if (live > active.size() / 2 && live < active.size()) {
      // Drop the retired half of the active list and its pool entries.
      const std::size_t from = active[live].coefs, chords_from = active[live].chords;
      active.erase(active.begin(), active.begin() + static_cast<long>(live));
      live = 0;
      pool.erase(pool.begin(), pool.begin() + static_cast<long>(from));
      chord_pool.erase(chord_pool.begin(), chord_pool.begin() + static_cast<long>(chords_from));
      for (ActiveSplat& a : active) {
        a.coefs -= from;
        a.chords -= chords_from;
      }
      for (Chord& c : chord_pool) c.lengths -= from;
    }
    while (next < ids.size() && splats[ids[next]].depth - reach < z1) {
      // The band's ids rise with gaps the hardware prefetcher cannot follow: ask for a later one.
      constexpr std::size_t kAhead = 8;
      if (next + kAhead < ids.size()) __builtin_prefetch(&splats[ids[next + kAhead]]);
      active.push_back(activate(ids[next], (first_sheet - splats[ids[next]].depth) / depth_sigma,
                                rows, content, state, pool, chord_pool));
      ++next;
    }
    int rx0 = width, rx1 = -1, ry0 = y1, ry1 = y0 - 1;  // the sheet's dirty rectangle
    for (std::size_t i = live; i < active.size(); ++i) {
      ActiveSplat& a = active[i];
      if (a.xa > a.xb || a.ya > a.yb) continue;
      // Both sides by the same formula (a sheet's far side is the next one's near side).
      const float near = a.below_sheet == j - 1 ? a.below_far : below(a.t0 + j * sheet_sigmas);
      a.below_far = below(a.t0 + (j + 1) * sheet_sigmas);
      a.below_sheet = j;
      const float share = a.below_far - near;
      if (!(share > 0.f) || state.columnsDone(a.xa, a.xb)) continue;
      const float* payload = &pool[a.coefs];
      const float* lengths = pool.data();
      const Chord* chord = &chord_pool[a.chords];
      rx0 = std::min(rx0, a.xa);
      rx1 = std::max(rx1, a.xb);
      ry0 = std::min(ry0, a.ya);
      ry1 = std::max(ry1, a.yb);
      // Every pixel of the chords, finished ones too (composite() drops those), and those
      // just outside the ellipse, whose length 0 adds nothing: no test a pixel.
      for (int y = a.ya; y <= a.yb; ++y, ++chord) {
        float* b = &sheet[(static_cast<std::size_t>(y - y0) * width + chord->lo) * stride];
        const float* w = lengths + chord->lengths;
        if (post) {
          // SheetContent::add's post-classified case, its payload held in one register.
          const Float4 p = load4(payload);
          for (int x = chord->lo; x <= chord->hi; ++x, ++w, b += 4)
            store4(b, load4(b) + (share * *w) * p);
        } else {
          for (int x = chord->lo; x <= chord->hi; ++x, ++w, b += stride)
            content.add(payload, share * *w, b);  // the kernel's world length in this sheet
        }
      }
    }
    compositeSheet(sheet, content, rx0, rx1, ry0, ry1, state);
    ++j;
  }
}

}  // namespace

void compositeSheets(const SplatCoverage& coverage, const Bands& bands, double thickness,
                     bool post, float termination, LightIndependentImage& image,
                     ProgressCounter& progress) {
  const SplatList& list = coverage.list();
  const FootprintTable& table = coverage.table();
  const auto splats = list.splats();
  // One sheet lattice for the whole image, so neighbouring bands agree.
  const double first_sheet =
      splats.empty() ? 0.0 : splats.front().depth - table.cutoff() * list.maxDepthSigma();
  progress.stage(bands.count);
#pragma omp parallel for schedule(dynamic)
  for (int b = 0; b < bands.count; ++b) {
    if (progress.stopped()) continue;  // the rest is skipped, then Cancelled
    BandState state(image, b * bands.rows, std::min((b + 1) * bands.rows, image.height()),
                    termination);
    compositeBand(coverage, bands.of(b), first_sheet, thickness, post, state);
    progress.advance();
  }
}

}  // namespace svr::splat
