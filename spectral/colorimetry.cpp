#include "spectral/colorimetry.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "spectral/csv_table.h"
#include "base/error.h"

namespace svr {

Observer Observer::cie1931(const std::string& data_dir, const WavelengthGrid& grid) {
  const CsvTable table = loadCsvTable(data_dir + "/spectra/cie1931_2deg_xyz_cmf_1nm.csv");
  Eigen::Matrix<double, Eigen::Dynamic, 3> cmf(grid.count, 3);
  for (int c = 0; c < 3; ++c)
    cmf.col(c) = table.spectrum(c, grid, OutsideRange::kZero).values();
  return Observer(grid, cmf);
}

Observer::Observer(WavelengthGrid grid, Eigen::Matrix<double, Eigen::Dynamic, 3> cmf)
    : grid_(grid), weighted_cmf_(cmf * grid.weight()) {}

Xyz Observer::xyz(const Spectrum& s) const {
  if (!(s.grid() == grid_))
    throw Error(fmt::format("observer on {} cannot integrate a spectrum on {}", grid_.describe(),
                            s.grid().describe()));
  return weighted_cmf_.transpose() * s.values();
}

Spectrum Observer::unitLuminance(const Spectrum& light) const {
  const double y = xyz(light).y();
  if (!(y > 0) || !std::isfinite(y))
    throw Error(fmt::format("light has luminance Y = {}; it must be positive to normalise", y));
  return light * (1.0 / y);
}

Eigen::Matrix3d linearSrgbToXyzMatrix() {
  Eigen::Matrix3d m;
  m << 0.4124564, 0.3575761, 0.1804375,  //
      0.2126729, 0.7151522, 0.0721750,   //
      0.0193339, 0.1191920, 0.9503041;
  return m;
}

Eigen::Matrix3d xyzToLinearSrgbMatrix() { return linearSrgbToXyzMatrix().inverse(); }

double srgbEncode(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double e) {
  return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

Xyz encodedSrgbToXyz(const Eigen::Vector3d& encoded) {
  return linearSrgbToXyzMatrix() *
         Eigen::Vector3d(srgbDecode(encoded.x()), srgbDecode(encoded.y()), srgbDecode(encoded.z()));
}

Lab xyzToLab(const Xyz& xyz, const Xyz& white) {
  constexpr double d = 6.0 / 29.0;
  auto f = [](double t) { return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0; };
  const double fx = f(xyz.x() / white.x()), fy = f(xyz.y() / white.y()),
               fz = f(xyz.z() / white.z());
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Eigen::Matrix3d labJacobian(const Xyz& xyz, const Xyz& white) {
  constexpr double d = 6.0 / 29.0;
  Eigen::Vector3d fp;  // f'(t) / white
  for (int i = 0; i < 3; ++i) {
    const double t = xyz[i] / white[i];
    const double c = std::cbrt(t);
    fp[i] = (t > d * d * d ? 1.0 / (3.0 * c * c) : 1.0 / (3.0 * d * d)) / white[i];
  }
  Eigen::Matrix3d j;
  j << 0.0, 116.0 * fp[1], 0.0,  //
      500.0 * fp[0], -500.0 * fp[1], 0.0,  //
      0.0, 200.0 * fp[1], -200.0 * fp[2];
  return j;
}

double deltaE76(const Lab& a, const Lab& b) { return (a - b).norm(); }

double deltaE2000(const Lab& lab1, const Lab& lab2) {
  using std::atan2, std::cos, std::sin, std::sqrt, std::pow, std::exp, std::abs;
  constexpr double pi = std::numbers::pi;
  constexpr double deg = pi / 180.0;
  const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
  const double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];

  const double C1 = sqrt(a1 * a1 + b1 * b1), C2 = sqrt(a2 * a2 + b2 * b2);
  const double Cbar7 = pow((C1 + C2) / 2.0, 7.0);
  const double G = 0.5 * (1.0 - sqrt(Cbar7 / (Cbar7 + pow(25.0, 7.0))));
  const double a1p = (1.0 + G) * a1, a2p = (1.0 + G) * a2;
  const double C1p = sqrt(a1p * a1p + b1 * b1), C2p = sqrt(a2p * a2p + b2 * b2);
  // Hue angles in degrees in [0, 360); defined as 0 for achromatic colours.
  auto hue = [&](double b, double ap) {
    if (b == 0.0 && ap == 0.0) return 0.0;
    double h = atan2(b, ap) / deg;
    return h < 0 ? h + 360.0 : h;
  };
  const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);

  const double dLp = L2 - L1;
  const double dCp = C2p - C1p;
  double dhp = 0.0;
  if (C1p * C2p != 0.0) {
    dhp = h2p - h1p;
    if (dhp > 180.0) dhp -= 360.0;
    else if (dhp < -180.0) dhp += 360.0;
  }
  const double dHp = 2.0 * sqrt(C1p * C2p) * sin(dhp * deg / 2.0);

  const double Lbarp = (L1 + L2) / 2.0;
  const double Cbarp = (C1p + C2p) / 2.0;
  double hbarp = h1p + h2p;
  if (C1p * C2p != 0.0) {
    if (abs(h1p - h2p) <= 180.0) hbarp = (h1p + h2p) / 2.0;
    else if (h1p + h2p < 360.0) hbarp = (h1p + h2p + 360.0) / 2.0;
    else hbarp = (h1p + h2p - 360.0) / 2.0;
  }
  const double T = 1.0 - 0.17 * cos((hbarp - 30.0) * deg) + 0.24 * cos(2.0 * hbarp * deg) +
                   0.32 * cos((3.0 * hbarp + 6.0) * deg) - 0.20 * cos((4.0 * hbarp - 63.0) * deg);
  const double dTheta = 30.0 * exp(-pow((hbarp - 275.0) / 25.0, 2.0));
  const double Cbarp7 = pow(Cbarp, 7.0);
  const double RC = 2.0 * sqrt(Cbarp7 / (Cbarp7 + pow(25.0, 7.0)));
  const double SL = 1.0 + 0.015 * pow(Lbarp - 50.0, 2.0) / sqrt(20.0 + pow(Lbarp - 50.0, 2.0));
  const double SC = 1.0 + 0.045 * Cbarp;
  const double SH = 1.0 + 0.015 * Cbarp * T;
  const double RT = -sin(2.0 * dTheta * deg) * RC;

  const double tl = dLp / SL, tc = dCp / SC, th = dHp / SH;
  return sqrt(tl * tl + tc * tc + th * th + RT * tc * th);
}

}  // namespace svr
