#pragma once
// CIE colorimetry on a wavelength grid: spectrum → XYZ (CIE 1931 2°), XYZ ↔ linear sRGB,
// the sRGB transfer curve, CIELAB and the ΔE76 / ΔE2000 colour differences.

#include <Eigen/Core>
#include <string>

#include "spectral/spectrum.h"

namespace svr {

using Xyz = Eigen::Vector3d;
using Lab = Eigen::Vector3d;

class Observer {
 public:
  // The CIE 1931 2° observer from data/spectra, resampled onto grid (zero outside 360–830 nm).
  static Observer cie1931(const std::string& data_dir, const WavelengthGrid& grid);
  Observer(WavelengthGrid grid, Eigen::Matrix<double, Eigen::Dynamic, 3> cmf);

  const WavelengthGrid& grid() const { return grid_; }
  // n×3 colour-matching functions times the quadrature weight: XYZ = weightedCmf()ᵀ · s.
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& weightedCmf() const { return weighted_cmf_; }

  Xyz xyz(const Spectrum& s) const;
  // The light scaled so that a perfect white diffuser under it has Y = 1.
  Spectrum unitLuminance(const Spectrum& light) const;

 private:
  WavelengthGrid grid_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> weighted_cmf_;
};

// IEC 61966-2-1 (sRGB, D65 primaries), no chromatic adaptation.
Eigen::Matrix3d xyzToLinearSrgbMatrix();
Eigen::Matrix3d linearSrgbToXyzMatrix();
double srgbEncode(double linear);  // transfer curve, linear [0,1] → encoded [0,1]
double srgbDecode(double encoded);
// Encoded sRGB (each 0…1) as XYZ, the sRGB white (D65) at Y = 1.
Xyz encodedSrgbToXyz(const Eigen::Vector3d& encoded);

Lab xyzToLab(const Xyz& xyz, const Xyz& white);
// ∂Lab/∂XYZ of xyzToLab at xyz (its f is cbrt above (6/29)³, linear below).
Eigen::Matrix3d labJacobian(const Xyz& xyz, const Xyz& white);
double deltaE76(const Lab& a, const Lab& b);
// CIEDE2000 with kL = kC = kH = 1 (Sharma, Wu & Dalal 2005), symmetric in its arguments.
double deltaE2000(const Lab& a, const Lab& b);

}  // namespace svr
