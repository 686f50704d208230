#pragma once
// A spectrum sampled on a WavelengthGrid, and resampling from any tabulated grid.

#include <Eigen/Core>
#include <span>
#include <string>

#include "spectral/wavelength_grid.h"

namespace svr {

// What to do where the target grid reaches outside the measured range of a table.
enum class OutsideRange {
  kError,  // the usual case: we do not invent data
  kZero,   // physically right for e.g. colour-matching functions (the eye stops seeing)
};

class Spectrum {
 public:
  Spectrum() = default;
  Spectrum(WavelengthGrid grid, Eigen::VectorXd values);
  static Spectrum constant(const WavelengthGrid& grid, double value);

  // Linear interpolation of a tabulated function (wavelengths strictly increasing) onto grid.
  // `what` names the source in error messages (e.g. "file.csv column D65").
  static Spectrum resample(const WavelengthGrid& grid, std::span<const double> wavelengths_nm,
                           std::span<const double> values, OutsideRange outside,
                           const std::string& what);

  const WavelengthGrid& grid() const { return grid_; }
  const Eigen::VectorXd& values() const { return values_; }
  int size() const { return static_cast<int>(values_.size()); }
  double operator[](int i) const { return values_[i]; }

  Spectrum operator*(const Spectrum& other) const;  // pointwise product (checks grids)
  Spectrum operator*(double s) const { return {grid_, values_ * s}; }
  Spectrum operator+(const Spectrum& other) const;
  Spectrum pow(double exponent) const;  // pointwise power, e.g. a transmittance applied m times

  bool allFinite() const { return values_.allFinite(); }

 private:
  WavelengthGrid grid_;
  Eigen::VectorXd values_;
};

}  // namespace svr
