#include "renderers/core/unit_power.h"

#include <gtest/gtest.h>

#include <cmath>

namespace svr {
namespace {

// Against libm over (0, 1] and the exponents scenes use (Phong shininess 1..1000): relative
// error within the 2e-6 · s the header states, plus float rounding of the result.
TEST(UnitPower, MatchesPowWithinTheStatedBound) {
  for (float s : {0.5f, 1.f, 5.f, 24.f, 100.f, 1000.f}) {
    double worst = 0.0;
    for (int i = 1; i <= 100000; ++i) {
      const float x = static_cast<float>(i) / 100000.f;
      const double exact = std::pow(static_cast<double>(x), static_cast<double>(s));
      if (exact < 1e-30) continue;  // underflows to 0 in float either way
      worst = std::max(worst, std::abs(unitPower(x, s) - exact) / exact);
    }
    EXPECT_LT(worst, 2e-6 * s + 1e-6) << "s = " << s;
  }
}

TEST(UnitPower, EdgesAreExact) {
  EXPECT_EQ(unitPower(0.f, 24.f), 0.f);
  EXPECT_EQ(unitPower(-0.f, 24.f), 0.f);
  EXPECT_EQ(unitPower(0.f, 0.f), 1.f);  // x⁰ = 1, as std::pow
  EXPECT_NEAR(unitPower(1.f, 24.f), 1.f, 1e-6f);
  EXPECT_NEAR(unitPower(0.5f, 2.f), 0.25f, 1e-6f);
  EXPECT_EQ(unitPower(1e-30f, 100.f), 0.f);  // far below float's range
}

}  // namespace
}  // namespace svr
