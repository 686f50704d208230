#pragma once
// A uniform wavelength grid. Every Spectrum lives on one; integrals over wavelength are plain
// sums weighted by the step (the CIE practice for tabulated data).

#include <string>

namespace svr {

struct WavelengthGrid {
  double start_nm = 380.0;
  double step_nm = 5.0;
  int count = 81;

  static WavelengthGrid standard() { return {}; }  // 380–780 nm at 5 nm

  double wavelength(int i) const { return start_nm + step_nm * i; }
  double end_nm() const { return wavelength(count - 1); }
  double weight() const { return step_nm; }  // quadrature weight of every sample
  std::string describe() const;

  bool operator==(const WavelengthGrid&) const = default;
};

// Throws svr::Error unless start > 0, step > 0 and 2 <= count <= 100000.
void validate(const WavelengthGrid& grid);

}  // namespace svr
