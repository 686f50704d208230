#include "spectral/spectrum.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "base/error.h"

namespace svr {

Spectrum::Spectrum(WavelengthGrid grid, Eigen::VectorXd values)
    : grid_(grid), values_(std::move(values)) {
  if (values_.size() != grid_.count)
    throw Error(fmt::format("spectrum: {} values for a grid of {} samples", values_.size(),
                            grid_.count));
}

Spectrum Spectrum::constant(const WavelengthGrid& grid, double value) {
  return {grid, Eigen::VectorXd::Constant(grid.count, value)};
}

Spectrum Spectrum::resample(const WavelengthGrid& grid, std::span<const double> wl,
                            std::span<const double> v, OutsideRange outside,
                            const std::string& what) {
  if (wl.size() != v.size() || wl.empty())
    throw Error(fmt::format("{}: {} wavelengths but {} values", what, wl.size(), v.size()));
  for (size_t i = 0; i < wl.size(); ++i) {
    if (!std::isfinite(wl[i]) || !std::isfinite(v[i]))
      throw Error(fmt::format("{}: non-finite entry at row {} (wavelength {}, value {})", what,
                              i + 1, wl[i], v[i]));
    if (i > 0 && wl[i] <= wl[i - 1])
      throw Error(fmt::format(
          "{}: wavelengths must strictly increase, but {} nm follows {} nm at row {}", what,
          wl[i], wl[i - 1], i + 1));
  }
  constexpr double kTolerance = 1e-9;
  Eigen::VectorXd out(grid.count);
  for (int i = 0; i < grid.count; ++i) {
    const double x = grid.wavelength(i);
    if (x < wl.front() - kTolerance || x > wl.back() + kTolerance) {
      if (outside == OutsideRange::kZero) {
        out[i] = 0.0;
        continue;
      }
      throw Error(fmt::format("{}: measured over {}–{} nm, which does not cover {} nm of the grid {}",
                              what, wl.front(), wl.back(), x, grid.describe()));
    }
    auto hi = std::lower_bound(wl.begin(), wl.end(), x - kTolerance);
    const size_t j = static_cast<size_t>(hi - wl.begin());
    if (j == 0 || std::abs(wl[j] - x) <= kTolerance) {
      out[i] = v[j];
      continue;
    }
    const double t = (x - wl[j - 1]) / (wl[j] - wl[j - 1]);
    out[i] = (1.0 - t) * v[j - 1] + t * v[j];
  }
  return {grid, std::move(out)};
}

static void requireSameGrid(const Spectrum& a, const Spectrum& b) {
  if (!(a.grid() == b.grid()))
    throw Error(fmt::format("spectra on different grids: {} and {}", a.grid().describe(),
                            b.grid().describe()));
}

Spectrum Spectrum::operator*(const Spectrum& other) const {
  requireSameGrid(*this, other);
  return {grid_, values_.cwiseProduct(other.values_)};
}

Spectrum Spectrum::operator+(const Spectrum& other) const {
  requireSameGrid(*this, other);
  return {grid_, values_ + other.values_};
}

Spectrum Spectrum::pow(double exponent) const {
  return {grid_, values_.array().pow(exponent).matrix()};
}

}  // namespace svr
