#include "spectral/spectrum_library.h"

#include <gtest/gtest.h>

#include "base/error.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

TEST(SpectrumLibrary, HoldsEveryFamily) {
  const auto& lib = test::library();
  EXPECT_EQ(lib.colorCheckerNames().size(), 24u);
  EXPECT_EQ(lib.munsellNames().size(), 1269u);
  EXPECT_EQ(lib.lightNames().size(), 3u + 12u + 9u + 1u);  // A D50 D65, F1–F12, LED, E
  for (const char* name : {"A", "D50", "D65", "E", "F1", "F12", "LED-B1", "LED-V2",
                           "ColorChecker/dark skin", "Munsell/2.5R 9/2", "HbO2", "Hb"})
    EXPECT_TRUE(lib.contains(name)) << name;
  EXPECT_EQ(lib.kind("D65"), SpectrumKind::kLight);
  EXPECT_EQ(lib.kind("Munsell/2.5R 9/2"), SpectrumKind::kReflectance);
  EXPECT_EQ(lib.kind("Hb"), SpectrumKind::kAbsorbance);
}

TEST(SpectrumLibrary, KnownSampleValues) {
  const auto& lib = test::library();
  EXPECT_DOUBLE_EQ(lib.get("ColorChecker/dark skin")[0], 0.048);  // 380 nm, Ohta table
  EXPECT_DOUBLE_EQ(lib.get("F1")[1], 2.36);                        // 385 nm
  EXPECT_DOUBLE_EQ(lib.get("D65")[36], 100.0);                     // 560 nm, normalised there
  EXPECT_DOUBLE_EQ(lib.get("E")[40], 100.0);
  EXPECT_NEAR(lib.get("HbO2").values().maxCoeff(), 1.0, 1e-12);
}

TEST(SpectrumLibrary, UnknownNamesListCloseMatches) {
  try {
    test::library().get("D56");
    FAIL();
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown spectrum 'D56'; closest known names: D50, D65"), std::string::npos) << msg;
  }
  const auto close = test::library().closestNames("dark skin", 1);
  EXPECT_EQ(close.front(), "ColorChecker/dark skin");
}

TEST(SpectrumLibrary, EditDistance) {
  EXPECT_EQ(editDistance("kitten", "sitting"), 3);
  EXPECT_EQ(editDistance("D65", "d65"), 0);
  EXPECT_EQ(editDistance("", "abc"), 3);
}

}  // namespace
}  // namespace svr
