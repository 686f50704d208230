#pragma once
// The pixels a splat covers and its kernel's world length at each, row by row: one mechanism
// for the bands and both compositing modes. Under an orthographic camera the lengths come from
// the frame's footprint factors (footprint_factors.h), four pixels at a time; otherwise
// (perspective, or a footprint too elongated to factor) from the splat's own footprint, one
// pixel at a time through the kernel table.

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "renderers/core/fast_exp.h"
#include "renderers/core/float4.h"
#include "renderers/core/splat_footprint.h"
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

  // The box of splat i within the image: columns [xa, xb], rows [ya, yb] (empty when xa > xb or
  // ya > yb). Every pixel whose centre lies inside the footprint's ellipse lies inside it.
  struct Box {
    int xa, xb, ya, yb;
  };
  Box start(std::size_t i);
  // The same box, without preparing its rows.
  Box box(std::size_t i) const;

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

}  // namespace svr::splat
