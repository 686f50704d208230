#include "renderers/splat/splat_coverage.h"

#include <algorithm>

namespace svr::splat {

SplatRows::SplatRows(const SplatCoverage& coverage)
    : cov_(coverage),
      factors_(coverage.factors()),
      cut2_(coverage.table().cutoffSquared()),
      scratch_(coverage.width() + 8, 0.f) {
  if (factors_) {
    const int columns = factors_->stride(), rows = factors_->rows();
    column_.assign(columns, 0.f);
    column_q_.assign(columns, 0.f);
    row_.assign((rows + 3) / 4 * 4, 0.f);
    row_q_.assign(row_.size(), 0.f);
    scratch_.resize(std::max<std::size_t>(scratch_.size(), columns + 8), 0.f);
  }
}

SplatRows::Box SplatRows::start(std::size_t i) {
  splat_ = &cov_.list().splats()[i];
  fp_ = &cov_.list().footprint(i);
  box_ = cov_.box(i);
  prepared_ = false;
  return box_;
}

void SplatRows::prepareFactors() {
  prepared_ = true;
  // The phases, and the splat's factors (footprint_factors.h): Px^I for the columns and
  // norm · Py^J · exp(−q(fx, fy)/2) for the rows, as powers of one vector of exponentials, with
  // their terms of q.
  const Footprint& fp = *fp_;
  const float u = splat_->x - 0.5f, v = splat_->y - 0.5f;
  const int ix = floorToInt(u), iy = floorToInt(v);
  const float fx = u - static_cast<float>(ix), fy = v - static_cast<float>(iy);
  const int rx = factors_->radiusX(), ry = factors_->radiusY();
  x0_ = ix - rx;
  y0_ = iy - ry;
  const float gx = fp.a * fx + fp.b * fy, gy = fp.b * fx + fp.c * fy;
  const float q_phase = (fp.a * fx + 2.f * fp.b * fy) * fx + fp.c * fy * fy;
  const Float4 e = fastExp(Float4{-static_cast<float>(rx) * gx, gx,
                                  -static_cast<float>(ry) * gy - 0.5f * q_phase, gy});
  const auto powers = [](float first, float ratio, float q_first, float q_step, float* out,
                         float* out_q, std::size_t n) {
    const float r2 = ratio * ratio;
    const Float4 step = splat4(r2 * r2);
    Float4 p = first * Float4{1.f, ratio, r2, r2 * ratio};
    Float4 q = q_first + q_step * Float4{0.f, 1.f, 2.f, 3.f};
    for (std::size_t i = 0; i < n; i += 4, p *= step, q += 4.f * q_step) {
      store4(out + i, p);
      store4(out_q + i, q);
    }
  };
  powers(e[0], e[1], 2.f * static_cast<float>(rx) * gx, -2.f * gx, column_.data(),
         column_q_.data(), column_.size());
  powers(fp.norm * e[2], e[3], 2.f * static_cast<float>(ry) * gy + q_phase, -2.f * gy,
         row_.data(), row_q_.data(), row_.size());
}

const float* SplatRows::evaluatedRow(int y, int& lo, int& hi) {
  const Footprint& fp = *fp_;
  const float dy = y + 0.5f - splat_->y;
  const float qy = fp.c * dy * dy, bxy = 2.f * fp.b * dy;
  ellipseRow(fp, splat_->x, dy, cut2_, box_.xa, box_.xb, lo, hi);
  int n = 0;
  for (int x = lo; x <= hi; ++x, ++n) {
    const float dx = x + 0.5f - splat_->x;
    const float q = (fp.a * dx + bxy) * dx + qy;
    scratch_[n] = q < cut2_ ? fp.norm * cov_.table().gaussian(q) : 0.f;
  }
  std::fill_n(scratch_.begin() + n, 3, 0.f);
  return scratch_.data();
}

}  // namespace svr::splat
