#include "spectral/colour_model.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/factor_training.h"
#include "spectral/linear_model.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

TEST(ModelName, ParsesEveryKindAndRejectsBadText) {
  EXPECT_EQ(parseModelName("rgb").k, 3);
  EXPECT_EQ(parseModelName("factor:6").kind, ModelKind::kFactor);
  EXPECT_EQ(parseModelName("spectral:81").k, 81);
  EXPECT_EQ(parseModelName("linear:9").str(), "linear:9");
  EXPECT_THROW(parseModelName("factor"), Error);
  EXPECT_THROW(parseModelName("factor:0"), Error);
  EXPECT_THROW(parseModelName("factor:100"), Error);
  EXPECT_THROW(parseModelName("factor:6x"), Error);
  EXPECT_THROW(parseModelName("cmyk:4"), Error);
}

TEST(RgbModel, WhiteMapsToOnesAndProductsMatchLinearSrgb) {
  const auto rgb = makeRgbModel(test::observer());
  EXPECT_TRUE(rgb->white().isApprox(Eigen::Vector3d::Ones(), 1e-12));
  // XYZ of the white coefficients is XYZ of the flat spectrum.
  const Spectrum flat = Spectrum::constant(test::observer().grid(), 1.0);
  EXPECT_TRUE((rgb->toXyz() * rgb->white()).isApprox(test::observer().xyz(flat), 1e-12));
  // A single reflectance under the flat light is exact: it is a linear map of XYZ.
  const Spectrum r = test::library().get("ColorChecker/red");
  const Eigen::VectorXd c = rgb->project(flat).cwiseProduct(rgb->project(r));
  EXPECT_TRUE((rgb->toXyz() * c).isApprox(test::observer().xyz(r), 1e-10));
}

TEST(SpectralModel, FullResolutionProductIsExact) {
  const auto exact = makeSpectralModel(test::observer(), 81);
  EXPECT_TRUE(exact->white().isApprox(Eigen::VectorXd::Ones(81), 1e-15));
  const Spectrum light = test::library().get("F11");
  const Spectrum refl = test::library().get("Munsell/5R 5/10");
  const Spectrum absorber = test::library().get("ColorChecker/cyan");
  const Eigen::VectorXd c = exact->project(light)
                                .cwiseProduct(exact->project(refl))
                                .cwiseProduct(exact->project(absorber).array().pow(4).matrix());
  const Xyz expected = test::observer().xyz(light * refl * absorber.pow(4));
  EXPECT_TRUE((exact->toXyz() * c).isApprox(expected, 1e-12));
}

TEST(SpectralModel, BandsAverageTheirSamples) {
  const auto bands = makeSpectralModel(test::observer(), 3);
  EXPECT_TRUE(bands->white().isApprox(Eigen::Vector3d::Ones(), 1e-15));
  // 81 samples in 3 bands: 27 each; a ramp's band mean is the ramp at the band centre.
  Eigen::VectorXd ramp(81);
  for (int i = 0; i < 81; ++i) ramp[i] = i;
  const Eigen::VectorXd c = bands->project(Spectrum(test::observer().grid(), ramp));
  EXPECT_NEAR(c[0], 13.0, 1e-12);
  EXPECT_NEAR(c[1], 40.0, 1e-12);
  EXPECT_NEAR(c[2], 67.0, 1e-12);
}

TEST(FactorModel, WhiteMapsToOnesForEverySharpenedVariant) {
  for (auto matrix : {LightMatrixKind::kFull, LightMatrixKind::kProjected})
    for (auto variant : {FactorVariant::kSharp, FactorVariant::kRefined})
      for (int k : {3, 5, 6}) {
        const auto m =
            trainFactorModel(test::observer(), test::smallTrainingSet(), k, variant, matrix);
        EXPECT_TRUE(m->white().isApprox(Eigen::VectorXd::Ones(k), 1e-9))
            << toString(variant) << " k=" << k << ": " << m->white().transpose();
        EXPECT_EQ(m->name(), "factor:" + std::to_string(k) +
                                 (matrix == LightMatrixKind::kFull ? "" : "/projected"));
        // The basis reconstructs its coefficients: P·B = I.
        EXPECT_TRUE((m->projection() * m->basis()).isIdentity(1e-9)) << m->name();
      }
}

TEST(ColourModel, NamesCarryTheLightMatrix) {
  EXPECT_EQ(parseModelName("factor:6").light_matrix, LightMatrixKind::kFull);
  EXPECT_EQ(parseModelName("spectral:31").light_matrix, LightMatrixKind::kFull);
  EXPECT_EQ(parseModelName("rgb").light_matrix, LightMatrixKind::kProjected);
  EXPECT_EQ(parseModelName("factor:6/projected").light_matrix, LightMatrixKind::kProjected);
  EXPECT_EQ(parseModelName("factor:6/projected").str(), "factor:6/projected");
  EXPECT_EQ(parseModelName("spectral:9/full").str(), "spectral:9");
  for (const char* bad : {"rgb/full", "linear:4/full", "factor:6/spectral", "factor:6/"})
    EXPECT_THROW(parseModelName(bad), Error) << bad;
}

TEST(LinearModel, InteractionOfFlatWhiteIsIdentityAndMatchesFullSpectrum) {
  const auto lin = trainLinearModel(test::observer(), test::smallTrainingSet(), 6);
  const Spectrum flat = Spectrum::constant(test::observer().grid(), 1.0);
  EXPECT_TRUE(lin->interaction(flat).isIdentity(1e-12));  // orthonormal basis
  // A spectrum inside the basis span is multiplied exactly: R(s)·a reproduces B0ᵀ(s ⊙ l)
  // when l lies in the span.
  const Spectrum s = test::library().get("Munsell/5R 5/10");
  const Eigen::VectorXd a = lin->project(flat);
  const Spectrum in_span(flat.grid(), lin->basis() * a);
  EXPECT_TRUE((lin->interaction(s) * a).isApprox(lin->project(s * in_span), 1e-12));
  EXPECT_EQ(lin->imageChannels(), 36);
}

TEST(ColourModel, SavesAndLoadsEveryKind) {
  const auto dir = std::filesystem::temp_directory_path() / "svr_model_io_test";
  std::filesystem::create_directories(dir);
  std::vector<std::unique_ptr<ColourModel>> models;
  models.push_back(makeRgbModel(test::observer()));
  models.push_back(makeSpectralModel(test::observer(), 31));
  models.push_back(makeSpectralModel(test::observer(), 31, LightMatrixKind::kProjected));
  models.push_back(trainFactorModel(test::observer(), test::smallTrainingSet(), 4,
                                    FactorVariant::kRefined, LightMatrixKind::kFull));
  models.push_back(trainFactorModel(test::observer(), test::smallTrainingSet(), 4,
                                    FactorVariant::kRefined, LightMatrixKind::kProjected));
  models.push_back(trainLinearModel(test::observer(), test::smallTrainingSet(), 4));
  const Spectrum s = test::library().get("ColorChecker/orange");
  for (const auto& m : models) {
    const auto path = (dir / (toString(m->kind()) + ".json")).string();
    saveModel(*m, path);
    const auto back = loadModel(path);
    EXPECT_EQ(back->name(), m->name());
    EXPECT_EQ(back->lightMatrixKind(), m->lightMatrixKind());
    const Spectrum f11 = test::library().get("F11");
    EXPECT_TRUE(back->lightMatrix(f11).isApprox(m->lightMatrix(f11), 1e-12)) << m->name();
    EXPECT_EQ(back->variant(), m->variant());
    EXPECT_TRUE(back->project(s).isApprox(m->project(s), 1e-12)) << m->name();
    EXPECT_TRUE(back->toXyz().isApprox(m->toXyz(), 1e-12)) << m->name();
    EXPECT_TRUE(back->white().isApprox(m->white(), 1e-12)) << m->name();
  }
  std::filesystem::remove_all(dir);
}

TEST(ColourModel, LoadRejectsBrokenFiles) {
  const auto path = (std::filesystem::temp_directory_path() / "svr_bad_model.json").string();
  {
    std::ofstream f(path);
    f << R"({"model": "factor:4", "grid": {"start_nm": 380, "step_nm": 5, "count": 81},
             "to_xyz": [[1,2],[3,4],[5,6]], "basis": [], "projection": []})";
  }
  try {
    loadModel(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("to_xyz is 3×2, expected 3×4"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(loadModel("/nonexistent/model.json"), Error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace svr
