#include "spectral/colorimetry.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "spectral/csv_table.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

TEST(DeltaE2000, ReproducesAll34SharmaPairsBothWays) {
  const CsvTable t = loadCsvTable(test::dataDir() + "/spectra/ciede2000_sharma2005_testdata.csv");
  ASSERT_EQ(t.wavelengths_nm.size(), 34u);  // column 1 is the pair number here
  for (size_t i = 0; i < 34; ++i) {
    const Lab a{t.columns[0][i], t.columns[1][i], t.columns[2][i]};
    const Lab b{t.columns[3][i], t.columns[4][i], t.columns[5][i]};
    const double expected = t.columns[6][i];
    EXPECT_NEAR(deltaE2000(a, b), expected, 1e-4) << "pair " << t.wavelengths_nm[i];
    EXPECT_NEAR(deltaE2000(b, a), expected, 1e-4) << "pair " << t.wavelengths_nm[i] << " swapped";
  }
}

TEST(DeltaE2000, ZeroForIdenticalColoursAndAchromaticPairs) {
  EXPECT_EQ(deltaE2000({50, 10, -20}, {50, 10, -20}), 0.0);
  // Achromatic colours differ in lightness only: ΔE00 = ΔL / SL.
  const double dl = 10.0, lbar = 55.0;
  const double sl = 1 + 0.015 * (lbar - 50) * (lbar - 50) / std::sqrt(20 + (lbar - 50) * (lbar - 50));
  EXPECT_NEAR(deltaE2000({50, 0, 0}, {60, 0, 0}), dl / sl, 1e-12);
}

TEST(DeltaE76, IsEuclidean) { EXPECT_DOUBLE_EQ(deltaE76({50, 3, 0}, {50, 0, 4}), 5.0); }

TEST(Colorimetry, WhitePointsMatchCie015) {
  // Chromaticities on the 380–780 nm, 5 nm grid; CIE 015 gives D65 (0.31272, 0.32903) and
  // A (0.44757, 0.40745) over 360–830 nm; the shorter range moves them by < 2e-4.
  const auto& lib = test::library();
  auto xy = [](const Xyz& v) { return Eigen::Vector2d(v.x() / v.sum(), v.y() / v.sum()); };
  const Eigen::Vector2d d65 = xy(test::observer().xyz(lib.get("D65")));
  EXPECT_NEAR(d65.x(), 0.31272, 2e-4);
  EXPECT_NEAR(d65.y(), 0.32903, 2e-4);
  const Eigen::Vector2d a = xy(test::observer().xyz(lib.get("A")));
  EXPECT_NEAR(a.x(), 0.44757, 2e-4);
  EXPECT_NEAR(a.y(), 0.40745, 2e-4);
}

TEST(Colorimetry, UnitLuminanceGivesWhiteYOne) {
  const Spectrum l = test::observer().unitLuminance(test::library().get("F11"));
  EXPECT_NEAR(test::observer().xyz(l).y(), 1.0, 1e-12);
}

TEST(Colorimetry, SrgbMatricesAreInverseAndD65WhiteIsOne) {
  const Eigen::Matrix3d m = xyzToLinearSrgbMatrix() * linearSrgbToXyzMatrix();
  EXPECT_TRUE(m.isIdentity(1e-12));
  const Eigen::Vector3d white = xyzToLinearSrgbMatrix() * Eigen::Vector3d(0.95047, 1.0, 1.08883);
  EXPECT_NEAR(white.x(), 1.0, 1e-3);
  EXPECT_NEAR(white.y(), 1.0, 1e-3);
  EXPECT_NEAR(white.z(), 1.0, 1e-3);
}

TEST(Colorimetry, SrgbTransferCurveKnownValuesAndRoundTrip) {
  EXPECT_DOUBLE_EQ(srgbEncode(0.0), 0.0);
  EXPECT_NEAR(srgbEncode(1.0), 1.0, 1e-12);
  EXPECT_NEAR(srgbEncode(0.0031308), 0.0031308 * 12.92, 1e-12);
  EXPECT_NEAR(srgbEncode(0.18), 0.46135612950044164, 1e-12);  // 18 % grey
  for (double v = 0.0; v <= 1.0; v += 0.01) EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-12);
}

TEST(Colorimetry, LabOfWhiteAndKnownValue) {
  const Xyz white{0.95047, 1.0, 1.08883};
  const Lab l = xyzToLab(white, white);
  EXPECT_NEAR(l[0], 100.0, 1e-12);
  EXPECT_NEAR(l[1], 0.0, 1e-12);
  EXPECT_NEAR(l[2], 0.0, 1e-12);
  // Y = 0.18 of white: L* = 116·0.18^(1/3) − 16.
  const Lab grey = xyzToLab(white * 0.18, white);
  EXPECT_NEAR(grey[0], 116 * std::cbrt(0.18) - 16, 1e-12);
  // Below the linear-segment threshold (t < (6/29)^3): L* = 903.3·t.
  const Lab dark = xyzToLab(white * 0.001, white);
  EXPECT_NEAR(dark[0], 0.001 * 24389.0 / 27.0, 1e-9);
}

TEST(Colorimetry, ColorCheckerRedUnderD65IsPlausible) {
  // shared/data/spectra README: red under D65 ≈ sRGB (178, 47, 58).
  const auto& lib = test::library();
  const Spectrum d65 = test::observer().unitLuminance(lib.get("D65"));
  const Xyz xyz = test::observer().xyz(d65 * lib.get("ColorChecker/red"));
  const Eigen::Vector3d rgb = xyzToLinearSrgbMatrix() * xyz;
  EXPECT_NEAR(srgbEncode(rgb.x()) * 255, 178, 3);
  EXPECT_NEAR(srgbEncode(std::max(rgb.y(), 0.0)) * 255, 47, 5);
  EXPECT_NEAR(srgbEncode(rgb.z()) * 255, 58, 3);
}

}  // namespace
}  // namespace svr
