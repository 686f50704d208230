// Colour maps from ParaView (its default, Cool to Warm, as its JSON export writes it) and Slicer
// (a CT muscle-and-bone .vp) made into svr materials: the designed reflectances show the map's
// colours under D65, between control points as well as at them, and an opaque slab of one
// material, lit only by ambient light and relit under D65, shows its colour.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "base/error.h"
#include "renderers/registry.h"
#include "renderers/scene/colour_map.h"
#include "renderers/scene/imported_transfer_function.h"
#include "renderers/scene/scene.h"
#include "spectral/colour_model.h"
#include "spectral/componentwise_model.h"
#include "spectral/post_illumination.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

const std::string kDir = std::string(SVR_SOURCE_DIR) + "/tests/data/formats/";

const Spectrum& d65() { return test::rendererLibrary().get("D65"); }

// ParaView's Cool to Warm is Moreland's diverging map: its middle point (0.865, 0.865, 0.865)
// is what the Msh blend of its two ends gives halfway. A two-point Diverging map must therefore
// reproduce the three-point preset everywhere.
TEST(ColourMaps, DivergingBlendReproducesParaViewsCoolToWarm) {
  const ColourMap preset = readParaViewColourMap(kDir + "cool_to_warm.json");
  ASSERT_EQ(preset.space, ColourSpace::kDiverging);
  ColourMap ends = preset;
  ends.colours = {preset.colours.front(), preset.colours.back()};
  for (double x = 0; x <= 1.0; x += 0.05)
    EXPECT_LT(deltaE2000(srgbLab(ends.colourAt(x)), srgbLab(preset.colourAt(x))), 1.0) << x;
  EXPECT_LT((ends.colourAt(0.5) - Eigen::Vector3d::Constant(0.865003)).norm(), 0.01);
}

TEST(ColourMaps, ParaViewOpacityPointsAndMidpoints) {
  ColourMap map = readParaViewColourMap(kDir + "cool_to_warm.json");
  EXPECT_DOUBLE_EQ(map.alphaAt(0.25), 0.25);  // midpoint 0.5, sharpness 0: linear
  map.opacity[0].midpoint = 0.25;              // the mean is reached a quarter of the way
  EXPECT_DOUBLE_EQ(map.alphaAt(0.25), 0.5);
  map.opacity[0].sharpness = 1.0;  // a step at the midpoint
  EXPECT_DOUBLE_EQ(map.alphaAt(0.2), 0.0);
  EXPECT_DOUBLE_EQ(map.alphaAt(0.3), 1.0);
}

void expectMatchesTheMap(const ColourMap& map) {
  const ImportedTransferFunction imported =
      importTransferFunction(map, test::rendererLibrary(), test::rendererObserver());
  ASSERT_EQ(imported.control_point_de2000.size(), map.colours.size());
  for (std::size_t i = 0; i < map.colours.size(); ++i) {
    // Recomputed here from the materials, not taken from the import's own report.
    const double x = map.colours[i].x;
    EXPECT_LT(deltaE2000(transferFunctionLab(imported.tf, x, d65(), test::rendererObserver()),
                         srgbLab(map.colours[i].srgb)),
              1.0)
        << "control point " << i;
  }
  // Between the points too: the knots are dense enough for the blend to follow the map.
  const double lo = map.colours.front().x, hi = map.colours.back().x;
  for (int s = 0; s <= 200; ++s) {
    const double x = lo + (hi - lo) * s / 200;
    EXPECT_LT(deltaE2000(transferFunctionLab(imported.tf, x, d65(), test::rendererObserver()),
                         srgbLab(map.colourAt(x))),
              1.0)
        << "x " << x;
  }
  for (const Material& m : imported.tf.materials)
    EXPECT_TRUE((m.reflectance.values().array() >= 0).all() &&
                (m.reflectance.values().array() <= 1).all())
        << m.name << " is not a physical reflectance";
}

TEST(ImportedTransferFunction, ParaViewPresetColoursUnderD65) {
  expectMatchesTheMap(readParaViewColourMap(kDir + "cool_to_warm.json"));
}

TEST(ImportedTransferFunction, SlicerVolumePropertyColoursUnderD65) {
  const ColourMap map = readSlicerVolumeProperty(kDir + "ct_muscle_bone.vp");
  ASSERT_EQ(map.colours.size(), 7u);
  ASSERT_EQ(map.opacity.size(), 7u);
  EXPECT_DOUBLE_EQ(map.alphaAt(139.919), 0.589286);
  expectMatchesTheMap(map);
}

TEST(ImportedTransferFunction, OpacityIsExtinctionPerUnitDistance) {
  ColourMap map = readSlicerVolumeProperty(kDir + "ct_muscle_bone.vp");
  ImportOptions options;
  options.unit_distance = 2.0;
  const auto imported =
      importTransferFunction(map, test::rendererLibrary(), test::rendererObserver(), options);
  // α over the unit distance: 1 − exp(−σ · share · d) at each of the map's points.
  for (const OpacityPoint& p : map.opacity) {
    const double share = imported.tf.opacityFactor(p.x);
    EXPECT_NEAR(1 - std::exp(-imported.sigma * share * 2.0), p.alpha, 1e-3) << p.x;
  }
}

// An opaque slab of each of the map's end materials (Cool to Warm's blue and red), ambient light
// only, relit under D65 through every backend: the pixel shows the map's colour there.
TEST(ImportedTransferFunction, OpaqueSlabShowsTheMapsColourThroughEveryBackend) {
  const ColourMap map = readParaViewColourMap(kDir + "cool_to_warm.json");
  const ImportedTransferFunction imported =
      importTransferFunction(map, test::rendererLibrary(), test::rendererObserver());
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  const Observer& observer = test::rendererObserver();
  const Xyz white = observer.xyz(observer.unitLuminance(d65()));
  for (const bool last : {false, true}) {
    Scene scene = test::slabScene(imported.sigma, "", 0.5);
    // The slab is 12 voxels of σ = 6.9 per voxel: T = e^−83, opaque.
    scene.transfer_function.materials[0] =
        imported.tf.materials[last ? imported.tf.materials.size() - 1 : 0];
    scene.shading = {1.0, 0.0, 0.0, 24.0};
    const Lab want = srgbLab((last ? map.colours.back() : map.colours.front()).srgb);
    for (const std::string& backend : rendererNames()) {
      SCOPED_TRACE(backend + (last ? ", red end" : ", blue end"));
      const LightIndependentImage image = test::render(*makeRenderer(backend), scene, *model);
      PostIlluminator post(*model);
      post.setLight(observer.unitLuminance(d65()));
      std::vector<float> xyz(3 * image.pixels());
      post.relightLinear(image, xyz, RelitSpace::kXyz);
      const std::size_t centre = 3 * (static_cast<std::size_t>(16) * image.width() + 16);
      const Xyz got(xyz[centre], xyz[centre + 1], xyz[centre + 2]);
      EXPECT_LT(deltaE2000(xyzToLab(got, white), want), 1.0)
          << "Lab " << xyzToLab(got, white).transpose() << " want " << want.transpose();
    }
  }
}

std::string importError(const std::string& name, const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(path) << text;
  try {
    name.ends_with(".vp") ? readSlicerVolumeProperty(path) : readParaViewColourMap(path);
  } catch (const Error& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "no error";
}

TEST(ColourMaps, BadMapsAreRefusedNamingFileAndField) {
  EXPECT_NE(importError("svr_decreasing.json", R"({"RGBPoints": [1, 0, 0, 0, 0, 1, 1, 1]})")
                .find("x must increase"),
            std::string::npos);
  EXPECT_NE(importError("svr_count.json", R"({"RGBPoints": [0, 0, 0]})").find("holds 3 numbers"),
            std::string::npos);
  EXPECT_NE(importError("svr_red.json", R"({"RGBPoints": [0, 2, 0, 0]})").find("red is 2"),
            std::string::npos);
  EXPECT_NE(importError("svr_space.json", R"({"RGBPoints": [0, 0, 0, 0], "ColorSpace": "XYZ"})")
                .find("ColorSpace 'XYZ'"),
            std::string::npos);
  EXPECT_NE(importError("svr_presets.json", R"([{"Name": "a", "RGBPoints": [0, 0, 0, 0]},
                                                 {"Name": "b", "RGBPoints": [0, 0, 0, 0]}])")
                .find("'a', 'b'"),
            std::string::npos);
  const std::string head = "1\n1\n0.9\n0.1\n0.2\n10\n";
  EXPECT_NE(importError("svr_nan.vp", head + "4 0 nan 1 1\n4 0 1 255 1\n4 0 0 0 0\n")
                .find("line 7 (scalar opacity): value 1 is nan"),
            std::string::npos);
  EXPECT_NE(importError("svr_short.vp", head + "6 0 0 1 1\n4 0 1 255 1\n4 0 0 0 0\n")
                .find("starts with the count 6 but holds 4"),
            std::string::npos);
  EXPECT_NE(importError("svr_lines.vp", "1\n1\n").find("holds 2 lines"), std::string::npos);
}

}  // namespace
}  // namespace svr
