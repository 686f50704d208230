#pragma once
// The pixels a splat covers and its kernel's world length at each, row by row: one mechanism
// for the bands and both compositing modes. Under an orthographic camera the lengths come from
// the frame's footprint factors (footprint_factors.h), four pixels at a time; otherwise
// (perspective, or a footprint too small or too elongated to factor) from the splat's own
// footprint, one pixel at a time through the kernel table.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <optional>
#include <vector>

#include "renderers/simd/fast_exp.h"
#include "renderers/simd/float4.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/splat/footprint_factors.h"
#include "renderers/splat/splat_list.h"

namespace svr::splat {

// What every thread shares: the list, the kernel table, the image size and the factors.
class SplatCoverage {
 public:
  SplatCoverage(const SplatList& list, const FootprintTable& table, int width, int height)
      : list_(list), table_(table), width_(width), height_(height) {
    if (list.orthographic()) factors_ = FootprintFactors::of(list.footprint(0));
  }
  const SplatList& list() const { return list_; }
  const FootprintTable& table() const { return table_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const FootprintFactors* factors() const { return factors_ ? &*factors_ : nullptr; }

  // The box of splat i within the image: columns [xa, xb], rows [ya, yb] (empty when xa > xb or
  // ya > yb). Every pixel whose centre lies inside the footprint's ellipse lies inside it.
  struct Box {
    int xa, xb, ya, yb;
  };
  Box box(std::size_t i) const {
    const Splat& s = list_.splats()[i];
    const Footprint& fp = list_.footprint(i);
    Box box;
    pixelRange(s.x, fp.half_w, width_, box.xa, box.xb);
    pixelRange(s.y, fp.half_h, height_, box.ya, box.yb);
    return box;
  }

 private:
  const SplatList& list_;
  const FootprintTable& table_;
  int width_, height_;
  std::optional<FootprintFactors> factors_;
};

// One thread's cursor over splats: start(i) places splat i, row(y) evaluates one of its rows.
class SplatRows {
 public:
  explicit SplatRows(const SplatCoverage& coverage);
  const SplatCoverage& coverage() const { return cov_; }

  // Places splat i for row(): its box (SplatCoverage::box).
  using Box = SplatCoverage::Box;
  Box start(std::size_t i);

  // Row y of a factored splat as four lengths at a time (zero outside the ellipse), for a
  // caller that consumes them as they come, without the row's copy: lengths4(x) are pixels
  // x … x + 3's, for x in the box (and up to three past it).
  struct FactoredRow {
    const float *lengths, *table_q, *column, *column_q;  // column 0 at pixel x0
    int x0;
    float row, row_q, cut2;
    Float4 lengths4(int x) const {
      const int i = x - x0;
      const Float4 q = (load4(table_q + i) + load4(column_q + i)) + row_q;
      const Float4 w = load4(lengths + i) * load4(column + i) * row;
      return q < splat4(cut2) ? w : splat4(0.f);
    }
  };
  bool factored() const { return factors_ != nullptr; }
  FactoredRow factoredLengths(int y);

  // Row y (within the box) of the splat last started: the pixels [lo, hi] of the row with a
  // non-zero length (lo > hi where the row misses the ellipse), and lengths w with w[x − lo] the
  // kernel's world length at pixel x, zero outside the ellipse and for three columns past hi.
  // Valid until the next call.
  const float* row(int y, int& lo, int& hi);

 private:
  // The splat's column and row factors, on its first row: a splat over finished pixels
  // needs none.
  void prepareFactors();
  const float* factoredRow(int y, int& lo, int& hi);
  const float* evaluatedRow(int y, int& lo, int& hi);

  const SplatCoverage& cov_;
  const FootprintFactors* factors_;
  float cut2_;
  const Splat* splat_ = nullptr;
  const Footprint* fp_ = nullptr;
  Box box_{};
  // Factored: the pixel of column 0 and row 0, and the splat's column and row factors and terms.
  int x0_ = 0, y0_ = 0;
  bool prepared_ = false;
  std::vector<float> column_, column_q_, row_, row_q_;
  std::vector<float> scratch_;
};

// Inline: called for every splat, and every row of one.
inline SplatRows::FactoredRow SplatRows::factoredLengths(int y) {
  if (!prepared_) prepareFactors();
  const int r = y - y0_;
  return {factors_->lengths(r), factors_->q(r), column_.data(), column_q_.data(), x0_,
          row_[r], row_q_[r], cut2_};
}

inline const float* SplatRows::factoredRow(int y, int& lo, int& hi) {
  const FactoredRow f = factoredLengths(y);
  const int n = box_.xb - box_.xa + 1;
  const Float4 zero = splat4(0.f);
  float* out = scratch_.data();
  int a = n, b = -1;  // the first and last columns inside the ellipse
  for (int i = 0; i < n; i += 4) {
    const Float4 w = f.lengths4(box_.xa + i);
    const Int4 inside = w > zero;
    store4(out + i, w);
    const unsigned lanes = laneMask(inside);
    if (lanes == 0) continue;
    a = std::min(a, i + std::countr_zero(lanes));
    b = i + 31 - std::countl_zero(lanes);
  }
  // Columns past the box are outside the ellipse unless the image's edge cut the box; then
  // hi is at that edge and nothing reads past it.
  b = std::min(b, n - 1);
  lo = box_.xa + a;
  hi = box_.xa + b;
  std::fill_n(out + b + 1, 3, 0.f);
  return out + std::min(a, n);
}

inline const float* SplatRows::row(int y, int& lo, int& hi) {
  return factors_ ? factoredRow(y, lo, hi) : evaluatedRow(y, lo, hi);
}

}  // namespace svr::splat
