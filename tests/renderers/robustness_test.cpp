// Robustness of every registered backend (issue 9): extreme but legal parameters stay finite
// and bounded, and renders are deterministic across thread counts, repeated runs and renders
// running in parallel. Every test iterates rendererNames(), so backends added later are covered.

#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include "renderers/classification/classification.h"
#include "renderers/render/scene_render.h"
#include "renderers/model/scene_model.h"
#include "renderers/registry.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

LightIndependentImage renderWith(const Scene& scene, const ColourModel& model,
                                 const std::string& backend) {
  return test::render(*makeRenderer(backend), scene, model);
}

// The image's bytes, plane by plane: equality here is bit-for-bit equality of the render.
std::vector<std::uint8_t> bytesOf(const LightIndependentImage& image) {
  std::vector<std::uint8_t> bytes;
  for (int p = 0; p < image.planes(); ++p) {
    const auto plane = image.planeFloat(p);
    const auto* b = reinterpret_cast<const std::uint8_t*>(plane.data());
    bytes.insert(bytes.end(), b, b + plane.size_bytes());
  }
  return bytes;
}

// Every sample finite; S within [lo, hi]; T within [0, 1] (up to rounding) when `bounded_t`.
void expectFiniteAndBounded(const LightIndependentImage& image, double lo, double hi,
                            bool bounded_t, const std::string& what) {
  for (int p = 0; p < image.planes(); ++p) {
    const bool is_t = p >= image.channels();
    for (float v : image.planeFloat(p)) {
      ASSERT_TRUE(std::isfinite(v)) << what << ": plane " << p;
      if (is_t && bounded_t) {
        ASSERT_GE(v, -1e-6f) << what << ": plane " << p;
        ASSERT_LE(v, 1.0f + 1e-6f) << what << ": plane " << p;
      } else if (!is_t) {
        ASSERT_GE(v, lo) << what << ": plane " << p;
        ASSERT_LE(v, hi) << what << ": plane " << p;
      }
    }
  }
}

Scene smallPhantom(int size) {
  Scene scene = test::phantomScene();
  scene.width = scene.height = size;
  return scene;
}

// Opacity 0, 1 and 1e6 per unit length, spectral and achromatic absorption: with the exact
// spectral model S ≥ 0 and T within [0, 1]. The phantom's x-ray material scatters without
// occluding, so its S grows with σ × chord (about 21 at σ = 1 here); bounded means < 1000.
TEST(Robustness, ExtremeOpacityStaysFiniteAndBounded) {
  const auto model = makeSpectralModel(test::rendererObserver(), 31);
  for (const std::string& backend : rendererNames()) {
    for (double sigma : {0.0, 1.0, 1e6}) {
      for (bool achromatic : {true, false}) {
        Scene scene = smallPhantom(24);
        for (auto& m : scene.transfer_function.materials) {
          m.extinction = sigma;
          if (achromatic) {
            m.absorption.reset();
          } else if (!m.absorption) {
            m.absorption = test::rendererLibrary().get("HbO2");
          }
        }
        const auto image = renderWith(scene, *model, backend);
        const std::string what = backend + " sigma " + std::to_string(sigma);
        expectFiniteAndBounded(image, -1e-6, 1000.0, true, what);
        if (sigma == 0.0) {
          // Nothing absorbs: the backdrop is fully visible everywhere.
          for (int p = image.channels(); p < image.planes(); ++p)
            for (float v : image.planeFloat(p)) ASSERT_NEAR(v, 1.0f, 1e-6f) << what;
        }
        if (sigma == 1e6) {
          // The centre ray meets the phantom's opaque shell: the backdrop is gone (up to the
          // early-termination threshold, 0.01, at which the ray stops).
          for (int p = image.channels(); p < image.planes(); ++p)
            EXPECT_LT(image.sample(p, 12, 12), 0.01f) << what;
        }
      }
    }
  }
}

TEST(Robustness, StepFromHundredthToTenVoxelsStaysFinite) {
  const auto model = makeSpectralModel(test::rendererObserver(), 31);
  for (const std::string& backend : rendererNames()) {
    for (double step : {0.01, 0.1, 1.0, 10.0}) {
      Scene scene = smallPhantom(step < 0.05 ? 8 : 24);
      scene.step_voxels = step;
      const auto image = renderWith(scene, *model, backend);
      expectFiniteAndBounded(image, -1e-6, 20.0, true,
                             backend + " step " + std::to_string(step));
    }
  }
}

// Every channel count k = 3..16 (spectral:k band models, cheap to build, exercise each
// fixed-width kernel; factor training per k takes minutes, so factor:6 stands in for the
// trained models), relit under a light mix whose weights sum to 0, an all-zero mix and one light
// with weight 0: the coefficients stay bounded and the relit pixels finite.
TEST(Robustness, ChannelCounts3To16AndZeroSumMixesStayFinite) {
  const Scene scene = smallPhantom(16);
  for (int k = 3; k <= 17; ++k) {
    const std::unique_ptr<ColourModel> model =
        k <= 16 ? std::unique_ptr<ColourModel>(makeSpectralModel(test::rendererObserver(), k))
                : makeSceneModel("factor:6", scene, test::rendererObserver()).model;
    ASSERT_EQ(model->channels(), k <= 16 ? k : 6);
    const auto light = [&](const char* name) {
      return test::rendererObserver().unitLuminance(test::rendererLibrary().get(name)).values();
    };
    const std::vector<Eigen::VectorXd> lights = {light("A"), light("F11")};
    for (const std::string& backend : rendererNames()) {
      const auto image = renderWith(scene, *model, backend);
      // The factor basis is refined to keep coefficients within [−1, 3] (README).
      expectFiniteAndBounded(image, -50.0, 50.0, false, backend + " " + model->name());
      PostIlluminator post(*model);
      for (const std::vector<double>& w : {std::vector<double>{1.0, -1.0}, {0.0, 0.0}, {0.0, 1.0}}) {
        post.setLight(Spectrum(model->grid(), mixLights(lights, w)));
        std::vector<float> relit(3 * image.pixels());
        post.relightLinear(image, relit);
        for (float v : relit) ASSERT_TRUE(std::isfinite(v)) << backend << " k " << k;
        if (w[0] == 0.0 && w[1] == 0.0) {
          for (float v : relit) ASSERT_EQ(v, 0.0f) << backend << " k " << k;
        }
      }
    }
  }
}

// Identical bytes with 1 and 2 OpenMP threads and across repeated runs.
TEST(Determinism, SameBytesWithOneAndTwoThreadsAndAcrossRuns) {
  const Scene scene = smallPhantom(40);
  const auto model = makeSceneModel("factor:6", scene, test::rendererObserver()).model;
  const int threads_before = omp_get_max_threads();
  for (const std::string& backend : rendererNames()) {
    omp_set_num_threads(1);
    const auto one = bytesOf(renderWith(scene, *model, backend));
    omp_set_num_threads(2);
    const auto two = bytesOf(renderWith(scene, *model, backend));
    const auto again = bytesOf(renderWith(scene, *model, backend));
    ASSERT_FALSE(one.empty());
    EXPECT_TRUE(one == two) << backend << ": 1 and 2 threads differ";
    EXPECT_TRUE(two == again) << backend << ": two runs differ";
  }
  omp_set_num_threads(threads_before);
}

// Two renders of different scenes on two std::threads give the bytes of sequential renders:
// backends hold no hidden global state.
TEST(Determinism, ParallelRendersEqualSequentialOnes) {
  Scene a = smallPhantom(32);
  Scene b = test::slabScene(0.05, "ColorChecker/cyan", 0.5);
  const auto model_a = makeSpectralModel(test::rendererObserver(), 31);
  const auto model_b = makeRgbModel(test::rendererObserver());
  for (const std::string& backend : rendererNames()) {
    const auto seq_a = bytesOf(renderWith(a, *model_a, backend));
    const auto seq_b = bytesOf(renderWith(b, *model_b, backend));
    std::vector<std::uint8_t> par_a, par_b;
    std::thread ta([&] { par_a = bytesOf(renderWith(a, *model_a, backend)); });
    std::thread tb([&] { par_b = bytesOf(renderWith(b, *model_b, backend)); });
    ta.join();
    tb.join();
    EXPECT_TRUE(seq_a == par_a) << backend << ": phantom differs when rendered in parallel";
    EXPECT_TRUE(seq_b == par_b) << backend << ": slab differs when rendered in parallel";
  }
}

// A render asked to stop (RenderRequest::stop, the Python module's Ctrl-C) throws Cancelled
// and returns no image, from every backend that looks at the flag, whether it was set before
// the render or by the progress callback at its first report; the same request without it
// renders. One thread, so that the reporting thread is the one that works (with more, the
// others may finish every tile before it reports).
TEST(Robustness, StopFlagCancelsTheRender) {
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto model = makeSpectralModel(test::rendererObserver(), 6);
  const Scene scene = smallPhantom(64);
  const ClassifiedVolume cv = classifyScene(scene, *model);
  for (const std::string& backend : rendererNames()) {
    if (backendEntry(backend).info.supports.needs_gl) continue;  // one pass: nothing to skip
    const auto renderer = makeRenderer(backend);
    std::atomic<bool> stop{true};
    RenderRequest request = sceneRequest(scene, cv);
    request.stop = &stop;
    EXPECT_THROW(renderer->render(request), Cancelled) << backend;
    stop = false;
    int calls = 0;
    const ProgressFn first_report = [&](double) {
      ++calls;
      stop = true;
    };
    EXPECT_THROW(renderer->render(request, first_report), Cancelled) << backend;
    EXPECT_GT(calls, 0) << backend;
    stop = false;
    EXPECT_NO_THROW(renderer->render(request)) << backend;
  }
  omp_set_num_threads(threads);
}

}  // namespace
}  // namespace svr
