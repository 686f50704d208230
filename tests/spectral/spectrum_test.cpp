#include "spectral/spectrum.h"

#include <gtest/gtest.h>

#include "base/error.h"

namespace svr {
namespace {

TEST(Spectrum, ResampleIsExactOnASubsetGridAndLinearBetween) {
  const WavelengthGrid grid{400, 10, 3};  // 400, 410, 420
  const std::vector<double> wl{395, 400, 405, 415, 425};
  const std::vector<double> v{9, 1, 2, 4, 8};
  const Spectrum s = Spectrum::resample(grid, wl, v, OutsideRange::kError, "t");
  EXPECT_DOUBLE_EQ(s[0], 1.0);
  EXPECT_DOUBLE_EQ(s[1], 3.0);  // halfway between 405 (2) and 415 (4)
  EXPECT_DOUBLE_EQ(s[2], 6.0);  // halfway between 415 (4) and 425 (8)
}

TEST(Spectrum, OutsideMeasuredRangeIsAnErrorUnlessZeroIsRight) {
  const WavelengthGrid grid{380, 5, 81};
  const std::vector<double> wl{400, 700}, v{1, 1};
  EXPECT_THROW(Spectrum::resample(grid, wl, v, OutsideRange::kError, "t"), Error);
  const Spectrum z = Spectrum::resample(grid, wl, v, OutsideRange::kZero, "t");
  EXPECT_EQ(z[0], 0.0);
  EXPECT_EQ(z[4], 1.0);  // 400 nm
  EXPECT_EQ(z[80], 0.0);
}

TEST(Spectrum, RejectsNanAndUnorderedWavelengths) {
  const WavelengthGrid grid{400, 10, 3};
  const std::vector<double> wl{400, 410, 420};
  EXPECT_THROW(Spectrum::resample(grid, wl, std::vector<double>{1, NAN, 1}, OutsideRange::kError, "t"),
               Error);
  const std::vector<double> bad{400, 420, 410};
  try {
    Spectrum::resample(grid, bad, std::vector<double>{1, 1, 1}, OutsideRange::kError, "file.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("file.csv: wavelengths must strictly increase"),
              std::string::npos);
  }
}

TEST(Spectrum, ProductsRequireTheSameGrid) {
  const Spectrum a = Spectrum::constant({400, 10, 3}, 2.0);
  const Spectrum b = Spectrum::constant({400, 5, 3}, 2.0);
  EXPECT_THROW(a * b, Error);
  EXPECT_DOUBLE_EQ((a * a)[1], 4.0);
  EXPECT_DOUBLE_EQ(a.pow(3)[2], 8.0);
}

TEST(WavelengthGrid, ValidatesParameters) {
  EXPECT_NO_THROW(validate(WavelengthGrid::standard()));
  EXPECT_THROW(validate({380, 0, 81}), Error);
  EXPECT_THROW(validate({380, 5, 1}), Error);
  EXPECT_THROW(validate({NAN, 5, 81}), Error);
  EXPECT_EQ(WavelengthGrid::standard().end_nm(), 780.0);
}

}  // namespace
}  // namespace svr
