#include "renderers/splat/footprint_factors.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace svr::splat {

std::optional<FootprintFactors> FootprintFactors::of(const Footprint& fp) {
  // The pixels within half_w of a centre c = i0 + fx lie in columns i0 − radius … i0 + radius + 1
  // once radius ≥ half_w (0.01 more for float rounding).
  const double rx = std::ceil(fp.half_w + 0.01), ry = std::ceil(fp.half_h + 0.01);
  // The largest exponent of any factor over the box and every phase in [0, 1]².
  const double a = fp.a, b = fp.b, c = fp.c, ab = std::abs(b);
  const double worst =
      std::max({0.5 * (a * (rx + 1) * (rx + 1) + 2 * ab * (rx + 1) * (ry + 1) + c * (ry + 1) * (ry + 1)),
                (rx + 1) * (a + ab), (ry + 1) * (ab + c) + 0.5 * (a + 2 * ab + c)});
  if (!(worst < 80.0)) return std::nullopt;
  FootprintFactors f;
  f.radius_x_ = static_cast<int>(rx);
  f.radius_y_ = static_cast<int>(ry);
  f.columns_ = 2 * f.radius_x_ + 2;
  f.rows_ = 2 * f.radius_y_ + 2;
  f.stride_ = (f.columns_ + 3) / 4 * 4 + 4;
  f.lengths_.assign(static_cast<std::size_t>(f.rows_) * f.stride_, 0.f);
  f.q_.assign(f.lengths_.size(), std::numeric_limits<float>::infinity());
  for (int r = 0; r < f.rows_; ++r)
    for (int i = 0; i < f.columns_; ++i) {
      const double x = i - f.radius_x_, y = r - f.radius_y_;
      const double q = a * x * x + 2 * b * x * y + c * y * y;
      f.lengths_[static_cast<std::size_t>(r) * f.stride_ + i] = static_cast<float>(std::exp(-0.5 * q));
      f.q_[static_cast<std::size_t>(r) * f.stride_ + i] = static_cast<float>(q);
    }
  return f;
}

}  // namespace svr::splat
