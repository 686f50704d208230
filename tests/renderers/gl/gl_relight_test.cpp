// GL post-illumination against the CPU relight (PostIlluminator): the same 8-bit sRGB to one
// code value per channel, for float and half images, with and without transmittance planes.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "renderers/gl/gl_relighter.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/post_illumination.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

// Random S in [0, 0.8) (a quarter of it over-exposed by the light's scale) and T in [0, 1).
LightIndependentImage randomImage(int w, int h, int k, int kt, unsigned seed) {
  LightIndependentImage img(w, h, k, kt);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int p = 0; p < img.planes(); ++p)
    for (float& v : img.planeFloat(p)) v = p < k ? 0.8f * u(rng) : u(rng);
  return img;
}

Spectrum unitLight(const char* name) {
  return test::rendererObserver().unitLuminance(test::rendererLibrary().get(name));
}

TEST(GlRelight, EqualsTheCpuRelightToOneCodeValue) {
  struct Case {
    int k, kt;
    SampleStorage storage;
    bool background;
  };
  for (const Case c : {Case{3, 0, SampleStorage::kFloat, false}, {6, 1, SampleStorage::kFloat, true},
                       {6, 6, SampleStorage::kHalf, true}, {16, 16, SampleStorage::kFloat, true},
                       {31, 1, SampleStorage::kFloat, false}}) {
    SCOPED_TRACE(::testing::Message() << "k " << c.k << " kt " << c.kt << " half "
                                      << (c.storage == SampleStorage::kHalf));
    const auto model = makeSpectralModel(test::rendererObserver(), c.k);
    const auto image = randomImage(67, 45, c.k, c.kt, 7 + c.k).withStorage(c.storage);
    PostIlluminator post(*model);
    GlRelighter gl;
    gl.setImage(image);
    for (const char* light : {"D65", "A", "F11"}) {
      post.setLight(unitLight(light), 1.3);
      if (c.background)
        post.setBackground(model->project(test::rendererLibrary().get("ColorChecker/cyan")));
      std::vector<std::uint8_t> cpu(3 * image.pixels()), gpu(3 * image.pixels());
      post.relightSrgb8(image, cpu);
      gl.relightSrgb8(post.foldedMatrix(image, RelitSpace::kLinearSrgb), gpu);
      int worst = 0, differing = 0, clipped = 0;
      for (std::size_t i = 0; i < cpu.size(); ++i) {
        const int d = std::abs(int(cpu[i]) - int(gpu[i]));
        worst = std::max(worst, d);
        differing += d != 0;
        clipped += cpu[i] == 255;
      }
      EXPECT_LE(worst, 1) << light;
      // Most pixels are identical (the CPU's 2^14-entry table rounds the input first).
      EXPECT_LT(differing, int(cpu.size() / 20)) << light;
      EXPECT_GT(clipped, 0) << light;  // the test covers clamping too
    }
  }
}

TEST(GlRelight, NonFiniteSampleIsReportedWithItsPixel) {
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  auto image = randomImage(20, 10, 4, 0, 3);
  image.setSample(2, 13, 7, std::numeric_limits<float>::quiet_NaN());
  PostIlluminator post(*model);
  GlRelighter gl;
  gl.setImage(image);
  std::vector<std::uint8_t> rgb(3 * image.pixels());
  try {
    gl.relightSrgb8(post.foldedMatrix(image, RelitSpace::kLinearSrgb), rgb);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-finite result at pixel (13, 7)"), std::string::npos)
        << e.what();
  }
}

TEST(GlRelight, WrongMatrixOrOutputSizeIsAnError) {
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const auto image = randomImage(8, 8, 4, 1, 5);
  GlRelighter gl;
  gl.setImage(image);
  std::vector<std::uint8_t> rgb(3 * image.pixels());
  EXPECT_THROW(gl.relightSrgb8(Eigen::MatrixXd::Zero(3, 4), rgb), Error);  // 5 planes
  std::vector<std::uint8_t> small(10);
  EXPECT_THROW(gl.relightSrgb8(Eigen::MatrixXd::Zero(3, 5), small), Error);
}

}  // namespace
}  // namespace svr
