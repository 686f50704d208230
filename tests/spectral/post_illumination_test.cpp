#include "spectral/post_illumination.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <random>

#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/factor_training.h"
#include "spectral/light_mixer.h"
#include "spectral/linear_model.h"
#include "tests/spectral/test_data.h"

namespace svr {
namespace {

// A k-channel image of random scattered radiance (and transmittance) in [0, 0.6).
LightIndependentImage randomImage(int w, int h, int k, int t_channels, unsigned seed) {
  LightIndependentImage img(w, h, k, t_channels);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 0.6f);
  for (int p = 0; p < img.planes(); ++p)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) img.setSample(p, x, y, u(rng));
  return img;
}

TEST(PostIllumination, RelightOfAKnownImage) {
  // Two pixels under rgb (projected light matrices) with the light's coefficients l = P·L:
  // XYZ = toXyz · (l ⊙ S).
  const auto rgb = makeRgbModel(test::observer());
  LightIndependentImage img(2, 1, 3, 0);
  const float s0[3] = {0.2f, 0.4f, 0.6f}, s1[3] = {1.0f, 0.0f, 0.5f};
  for (int c = 0; c < 3; ++c) img.setSample(c, 0, 0, s0[c]), img.setSample(c, 1, 0, s1[c]);
  const Spectrum spectrum = test::observer().unitLuminance(test::library().get("A"));
  const Eigen::Vector3d light = rgb->project(spectrum);
  PostIlluminator post(*rgb);
  post.setLight(spectrum, 1.5);
  std::vector<float> xyz(6);
  post.relightLinear(img, xyz, RelitSpace::kXyz);
  for (int px = 0; px < 2; ++px) {
    const float* s = px == 0 ? s0 : s1;
    const Eigen::Vector3d expect =
        1.5 * rgb->toXyz() * light.cwiseProduct(Eigen::Vector3d(s[0], s[1], s[2]));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[3 * px + c], expect[c], 1e-6 * expect.norm());
  }
  // 8-bit sRGB of the same pixels = encode(clamp(XYZ→linear sRGB)), to one code value.
  std::vector<std::uint8_t> srgb(6);
  post.relightSrgb8(img, srgb);
  for (int px = 0; px < 2; ++px) {
    const Eigen::Vector3d lin =
        xyzToLinearSrgbMatrix() * Eigen::Vector3d(xyz[3 * px], xyz[3 * px + 1], xyz[3 * px + 2]);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(srgb[3 * px + c], 255.0 * srgbEncode(std::clamp(lin[c], 0.0, 1.0)), 0.75);
  }
}

// Relighting the image of a flat white surface under light l gives the XYZ the model computes
// for l × white to float rounding (projected light matrices: post-illumination equals baking
// the light in); under the exact spectral:81 model that is the light's own white, Y = 1.
TEST(PostIllumination, RelitWhiteEqualsTheModelsProductAndTheLightsWhite) {
  std::vector<std::unique_ptr<ColourModel>> models;
  models.push_back(makeSpectralModel(test::observer(), 81, LightMatrixKind::kProjected));
  models.push_back(trainFactorModel(test::observer(), test::smallTrainingSet(), 6,
                                    FactorVariant::kRefined, LightMatrixKind::kProjected));
  for (const auto& model : models) {
    const int k = model->channels();
    LightIndependentImage img(4, 3, k, 0);
    for (int c = 0; c < k; ++c)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) img.setSample(c, x, y, 1.0f);
    PostIlluminator post(*model);
    for (const char* name : {"D65", "A", "F11"}) {
      SCOPED_TRACE(model->name() + " " + name);
      const Spectrum l = test::observer().unitLuminance(test::library().get(name));
      post.setLight(l);
      std::vector<float> xyz(3 * 12);
      post.relightLinear(img, xyz, RelitSpace::kXyz);
      const Xyz baked = model->toXyz() * model->project(l).cwiseProduct(model->white());
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[3 * 7 + c], baked[c], 1e-6);
      if (k == 81) {
        const Xyz exact = test::observer().xyz(l);
        EXPECT_NEAR(xyz[3 * 7 + 1], 1.0, 1e-6);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[3 * 7 + c], exact[c], 1e-6);
      }
    }
  }
}

// Full-spectrum light matrices relight a pixel c as the spectrum B·c times the light's whole
// spectrum, X = Σ_λ x̄(λ) L(λ) (B·c)(λ) Δλ: checked against the observer's own XYZ of that
// product, for band models and a trained factor model, with a backdrop seen through T.
TEST(PostIllumination, FullLightMatricesTakeTheLastProductWithTheWholeSpectrum) {
  std::vector<std::unique_ptr<ComponentwiseModel>> models;
  models.push_back(makeSpectralModel(test::observer(), 5));
  models.push_back(makeSpectralModel(test::observer(), 81));
  models.push_back(trainFactorModel(test::observer(), test::smallTrainingSet(), 6,
                                    FactorVariant::kRefined, LightMatrixKind::kFull));
  for (const auto& model : models) {
    ASSERT_EQ(model->lightMatrixKind(), LightMatrixKind::kFull);
    const int k = model->channels();
    const auto img = randomImage(3, 2, k, k, 19);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k, 0.3, 0.8);
    PostIlluminator post(*model);
    post.setBackground(b);
    for (const char* name : {"F11", "LED-B1"}) {
      SCOPED_TRACE(model->name() + " " + name);
      const Spectrum l = test::observer().unitLuminance(test::library().get(name));
      post.setLight(l, 0.8);
      std::vector<float> xyz(3 * img.pixels());
      post.relightLinear(img, xyz, RelitSpace::kXyz);
      Eigen::VectorXd c(k);
      for (int ch = 0; ch < k; ++ch)
        c[ch] = img.scattered(ch, 2, 1) + img.transmittance(ch, 2, 1) * b[ch];
      const Xyz exact = 0.8 * test::observer().xyz(l * Spectrum(l.grid(), model->basis() * c));
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(xyz[3 * 5 + a], exact[a], 1e-5 * (1 + exact[a]));
    }
  }
  // Band means of a spiky light lose what the full spectrum keeps: under F11 the 5-band model's
  // relit flat white is off by more than 1 % projected, and equals the light's white full.
  const auto projected = makeSpectralModel(test::observer(), 5, LightMatrixKind::kProjected);
  const auto full = makeSpectralModel(test::observer(), 5, LightMatrixKind::kFull);
  const Spectrum f11 = test::observer().unitLuminance(test::library().get("F11"));
  const Xyz white = test::observer().xyz(f11);
  const Xyz via_full = full->lightMatrix(f11) * full->white();
  const Xyz via_projected = projected->lightMatrix(f11) * projected->white();
  EXPECT_NEAR((via_full - white).norm(), 0.0, 1e-9);
  EXPECT_GT((via_projected - white).norm(), 0.01);
}

TEST(PostIllumination, EveryWidthAndInstructionSetGivesTheSamePixels) {
  for (int k : {3, 4, 6, 8, 13, 16}) {
    const auto model = makeSpectralModel(test::observer(), k);
    for (int t_channels : {0, 1, k}) {
      for (auto storage : {SampleStorage::kFloat, SampleStorage::kHalf}) {
        // 37 and 45 columns: the fused kernel's steps of sixteen, then (45) one of eight, and a
        // tail in every row.
        for (int width : {37, 45}) {
          const auto img = randomImage(width, 5, k, t_channels, 7 + k).withStorage(storage);
          PostIlluminator post(*model);
          post.setLight(test::observer().unitLuminance(test::library().get("F2")));
          post.setBackground(Eigen::VectorXd::LinSpaced(k, 0.2, 0.9));
          post.forceKernel({.dynamic_width = true, .isa = KernelIsa::kPortable});
          std::vector<float> reference(3 * img.pixels());
          std::vector<std::uint8_t> reference8(reference.size());
          post.relightLinear(img, reference);
          post.relightSrgb8(img, reference8);
          for (KernelIsa isa : availableKernelIsas())
            for (bool dynamic : {false, true}) {
              SCOPED_TRACE(fmt::format("k={} T={} {} {} {}", k, t_channels, toString(isa),
                                       dynamic ? "dynamic" : "fixed",
                                       storage == SampleStorage::kHalf ? "half" : "float"));
              post.forceKernel({.dynamic_width = dynamic, .isa = isa});
              std::vector<float> out(reference.size());
              std::vector<std::uint8_t> out8(reference.size());
              post.relightLinear(img, out);
              post.relightSrgb8(img, out8);
              // The same sums to float rounding (the AVX2 kernels fuse multiply-adds), so the
              // same table gives the same code except where a value lies within that rounding
              // of an entry boundary: then one code apart, and rarely.
              int differing = 0;
              for (size_t i = 0; i < out.size(); ++i) {
                ASSERT_NEAR(out[i], reference[i], 1e-6 * (1 + std::abs(reference[i]))) << i;
                ASSERT_LE(std::abs(int(out8[i]) - int(reference8[i])), 1) << i;
                differing += out8[i] != reference8[i];
              }
              EXPECT_LE(differing, std::max<int>(2, out8.size() / 200));
            }
        }
      }
    }
  }
}

TEST(PostIllumination, SpectralEightyOneTakesTheDynamicPathAndIsExact) {
  const auto model = makeSpectralModel(test::observer(), 81);
  const auto img = randomImage(9, 4, 81, 0, 3);
  const Spectrum l = test::observer().unitLuminance(test::library().get("LED-B1"));
  PostIlluminator post(*model);
  post.setLight(l);
  std::vector<float> xyz(3 * img.pixels());
  post.relightLinear(img, xyz, RelitSpace::kXyz);
  Eigen::VectorXd s(81);
  for (int c = 0; c < 81; ++c) s[c] = img.scattered(c, 5, 2);
  const Xyz exact = test::observer().xyz(l * Spectrum(l.grid(), s));
  const size_t px = 2 * 9 + 5;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[3 * px + c], exact[c], 1e-5 * (1 + exact[c]));
}

TEST(PostIllumination, BackgroundSeenThroughTransmittance) {
  // S = 0, T = 0.5 per channel, background b: XYZ = toXyz · (l ⊙ T ⊙ b), l = P·L (projected).
  const auto model = makeSpectralModel(test::observer(), 4, LightMatrixKind::kProjected);
  LightIndependentImage spectral_t(1, 1, 4, 4), scalar_t(1, 1, 4, 1);
  for (int c = 0; c < 4; ++c) spectral_t.setSample(4 + c, 0, 0, 0.5f);
  scalar_t.setSample(4, 0, 0, 0.5f);
  const Spectrum spectrum = test::observer().unitLuminance(test::library().get("D65"));
  const Eigen::Vector4d light = model->project(spectrum), b(0.1, 0.2, 0.3, 0.4);
  PostIlluminator post(*model);
  post.setLight(spectrum);
  post.setBackground(b);
  const Eigen::Vector3d expect = model->toXyz() * (0.5 * light.cwiseProduct(b));
  for (const auto* img : {&spectral_t, &scalar_t}) {
    std::vector<float> xyz(3);
    post.relightLinear(*img, xyz, RelitSpace::kXyz);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[c], expect[c], 1e-6 * (1 + expect[c]));
  }
}

TEST(PostIllumination, MixOfLightsIsTheWeightedSumOfRelitImages) {
  const auto model = makeSpectralModel(test::observer(), 6);
  const auto img = randomImage(16, 16, 6, 0, 11);
  const Spectrum a = test::observer().unitLuminance(test::library().get("A"));
  const Spectrum f = test::observer().unitLuminance(test::library().get("F11"));
  PostIlluminator post(*model);
  std::vector<float> ra(3 * img.pixels()), rf(ra.size()), rmix(ra.size());
  post.setLight(a);
  post.relightLinear(img, ra);
  post.setLight(f);
  post.relightLinear(img, rf);
  const std::vector<Eigen::VectorXd> lights{a.values(), f.values()};
  post.setLight(Spectrum(a.grid(), mixLights(lights, std::vector<double>{0.3, 0.7})));
  post.relightLinear(img, rmix);
  for (size_t i = 0; i < ra.size(); ++i) EXPECT_NEAR(rmix[i], 0.3 * ra[i] + 0.7 * rf[i], 1e-5);
}

TEST(PostIllumination, LinearModelRelightsItsMatrixImage) {
  // linear:k stores S as a k×k matrix per pixel; relit XYZ = toXyz · S · light.
  const auto lin = trainLinearModel(test::observer(), test::smallTrainingSet(), 4);
  const Spectrum refl = test::library().get("ColorChecker/blue");
  const Eigen::MatrixXd s = lin->interaction(refl);
  LightIndependentImage img(1, 1, 16, 0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) img.setSample(i + 4 * j, 0, 0, static_cast<float>(s(i, j)));
  const Spectrum spectrum = test::observer().unitLuminance(test::library().get("D65"));
  const Eigen::VectorXd light = lin->project(spectrum);
  PostIlluminator post(*lin);
  post.setLight(spectrum);
  std::vector<float> xyz(3);
  post.relightLinear(img, xyz, RelitSpace::kXyz);
  const Eigen::Vector3d expect = lin->toXyz() * (s * light);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(xyz[c], expect[c], 1e-5);
}

TEST(PostIllumination, NonFiniteInputIsReportedWithItsPixelNotWritten) {
  const auto model = makeSpectralModel(test::observer(), 6);
  auto img = randomImage(10, 8, 6, 0, 1);
  img.setSample(3, 7, 5, NAN);
  PostIlluminator post(*model);
  std::vector<std::uint8_t> out(3 * img.pixels());
  try {
    post.relightSrgb8(img, out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite result at pixel (7, 5)"), std::string::npos)
        << e.what();
  }
  img.setSample(3, 7, 5, INFINITY);
  std::vector<float> lin(3 * img.pixels());
  EXPECT_THROW(post.relightLinear(img, lin), Error);
}

TEST(PostIllumination, RejectsMismatchedShapes) {
  const auto model = makeSpectralModel(test::observer(), 6);
  PostIlluminator post(*model);
  EXPECT_THROW(post.setLight(Spectrum::constant(WavelengthGrid{400, 10, 31}, 1.0)), Error);
  EXPECT_THROW(post.setLight(Spectrum::constant(model->grid(), NAN)), Error);
  EXPECT_THROW(post.setLight(Spectrum::constant(model->grid(), 1.0), INFINITY), Error);
  LightIndependentImage wrong(2, 2, 4, 0);
  std::vector<float> out(12);
  EXPECT_THROW(post.relightLinear(wrong, out), Error);
  LightIndependentImage right(2, 2, 6, 0);
  std::vector<float> short_out(11);
  EXPECT_THROW(post.relightLinear(right, short_out), Error);
}

}  // namespace
}  // namespace svr
