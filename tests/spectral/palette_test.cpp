#include "spectral/palette.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(Palette, LoadsLibraryCsvAndInlineSpectra) {
  writeTemp("svr_palette_refl.csv", "wavelength_nm,grey\n300,0.5\n900,0.5\n");
  const auto path = writeTemp("svr_palette.json", R"({
    "lights": ["D65", {"name": "warm", "library": "A"}],
    "materials": [
      "ColorChecker/red",
      {"name": "grey", "csv": "svr_palette_refl.csv", "column": "grey"},
      {"name": "ramp", "wavelengths": [380, 780], "values": [0, 1]}
    ]})");
  const Palette p = loadPalette(path, test::library());
  ASSERT_EQ(p.lights.size(), 2u);
  ASSERT_EQ(p.materials.size(), 3u);
  EXPECT_EQ(p.lights[1].name, "warm");
  EXPECT_DOUBLE_EQ(p.materials[1].spectrum[40], 0.5);
  EXPECT_DOUBLE_EQ(p.materials[2].spectrum[40], 0.5);  // 580 nm on the 380–780 ramp
}

TEST(Palette, ErrorsNameFileKeyAndValue) {
  auto errorOf = [](const std::string& text) {
    try {
      loadPalette(writeTemp("svr_bad_palette.json", text), test::library());
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(errorOf(R"({"lights": ["D65"], "materials": ["nope"]})").find("unknown spectrum 'nope'"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": [], "materials": ["ColorChecker/red"]})")
                .find("svr_bad_palette.json: lights: must be a non-empty array"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": ["D65"], "materials": [{"name": "x", "colour": 1}]})")
                .find("svr_bad_palette.json: unknown key 'materials[0].colour'"),
            std::string::npos);
  EXPECT_NE(errorOf("{not json").find("invalid JSON"), std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": ["D65"], "materials": [{"name": "x", "wavelengths": [400, 700],
             "values": [1, 2]}]})").find("does not cover 380 nm"),
            std::string::npos);
}

}  // namespace
}  // namespace svr
