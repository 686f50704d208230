#pragma once
// An orthographic footprint in factors. Every splat of an orthographic view has the same
// footprint, q = a dx² + 2b dx dy + c dy², and only its sub-pixel phase differs. Taking the pixel
// offsets from the pixel ⌊s − ½⌋ under the centre, dx = I − fx and dy = J − fy with whole I, J
// and phases fx, fy in [0, 1):
//   q = q(I, J) − 2 I gx − 2 J gy + q(fx, fy),   gx = a fx + b fy,  gy = b fx + c fy,
// so exp(−q/2) = exp(−q(I, J)/2) · Px^I · Py^J · exp(−q(fx, fy)/2), Px = e^gx, Py = e^gy. The
// first factor, and q(I, J), are the same for every splat: they are tabulated here once a frame.
// The rest are a splat's four exponentials (one vector) and powers of them, and each pixel then
// takes two multiplies and, for the truncation test q < cutoff², two adds; where evaluating the
// footprint row by row took a square root and a division a row and a quadratic and a table
// lookup a pixel. The lengths are the footprint's own: no phase is rounded.

#include <cstddef>
#include <optional>
#include <vector>

#include "renderers/kernels/splat_footprint.h"

namespace svr::splat {

class FootprintFactors {
 public:
  // nullopt where a factor could leave float's range (an exponent reaching ±80 within the box:
  // a footprint hundreds of pixels wide, or very elongated), which is left to the row-by-row
  // evaluation.
  static std::optional<FootprintFactors> of(const Footprint& fp);

  int radiusX() const { return radius_x_; }  // I runs over [−radiusX, radiusX + 1]
  int radiusY() const { return radius_y_; }  // J over [−radiusY, radiusY + 1]
  int rows() const { return rows_; }
  int stride() const { return stride_; }  // columns padded to whole vectors, plus one
  // Row r (J = r − radiusY) of exp(−q(I, J)/2) and of q(I, J), at column i (I = i − radiusX);
  // past the last column 0 and +∞, so that those columns fail the truncation test.
  const float* lengths(int r) const { return &lengths_[static_cast<std::size_t>(r) * stride_]; }
  const float* q(int r) const { return &q_[static_cast<std::size_t>(r) * stride_]; }

 private:
  FootprintFactors() = default;
  int radius_x_ = 0, radius_y_ = 0, columns_ = 0, rows_ = 0, stride_ = 0;
  std::vector<float> lengths_, q_;
};

}  // namespace svr::splat
