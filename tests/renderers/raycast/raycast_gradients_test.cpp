// The raycaster's gradient sources and kernels: precomputed gradients against the analytic
// gradient and against central differences on the fly, the memory-budget fallback, and the
// AVX2 kernels against the portable ones.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "renderers/classification/classification.h"
#include "renderers/kernels/gradient_volume.h"
#include "renderers/model/scene_model.h"
#include "renderers/render/scene_render.h"
#include "renderers/raycast/raycast_renderer.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

// f = 2x − 3y + 0.5z (voxel coordinates) with spacing (1, 2, 0.5): ∇f in world units is
// (2, −1.5, 1), everywhere inside, exactly; at the border the one-sided differences halve it.
TEST(GradientVolume, IsExactOnALinearField) {
  const Dims d{9, 7, 5};
  std::vector<float> f;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) f.push_back(2.f * x - 3.f * y + 0.5f * z);
  ClassifiedVolume cv;
  cv.dims = d;
  cv.spacing = {1.0, 2.0, 0.5};
  cv.values = f;
  const GradientVolume g = buildGradientVolume(cv);
  ASSERT_EQ(g.count, 4 * f.size());
  const auto decoded = [&](std::size_t i, int lane) {
    return g.q[4 * i + lane] * g.scale[lane] + g.offset[lane];
  };
  const double expected[3] = {2.0, -1.5, 1.0};
  const double range = 2.0 * 8 + 3.0 * 6 + 0.5 * 4;  // the field's span
  for (int z = 1; z < d[2] - 1; ++z)
    for (int y = 1; y < d[1] - 1; ++y)
      for (int x = 1; x < d[0] - 1; ++x) {
        const std::size_t i = (static_cast<std::size_t>(z) * d[1] + y) * d[0] + x;
        // 16 bits over the field's range, and 15 over the largest gradient component (2: x).
        EXPECT_NEAR(decoded(i, 0), f[i], 0.5 * range / 65534 + 1e-6);
        for (int a = 0; a < 3; ++a)
          EXPECT_NEAR(decoded(i, 1 + a), expected[a], 0.5 * 2.0 / 32767 + 1e-6) << x << y << z << a;
      }
  EXPECT_NEAR(decoded(0, 1), 1.0, 1e-4);  // x one-sided at voxel 0: (f[1] − f[0]) / 2
}

struct Pair {
  LightIndependentImage a, b;
};

Pair renderBoth(const Scene& scene, const ClassifiedVolume& cv, const nlohmann::json& a,
                const nlohmann::json& b, const RaycastRenderer& ra = RaycastRenderer(),
                const RaycastRenderer& rb = RaycastRenderer()) {
  return {test::render(ra, scene, cv, a), test::render(rb, scene, cv, b)};
}

// The phantom classified for rgb, a scene-trained factor:6 (trained once) and spectral:31.
const std::vector<std::pair<std::string, ClassifiedVolume>>& phantomClassified() {
  static const auto all = [] {
    const Scene scene = test::phantomScene();
    std::vector<std::pair<std::string, ClassifiedVolume>> out;
    for (const char* name : {"rgb", "factor:6", "spectral:31"}) {
      const auto model = makeSceneModel(name, scene, test::rendererObserver()).model;
      out.emplace_back(name, classifyScene(scene, *model));
    }
    return out;
  }();
  return all;
}

double largestDifference(const LightIndependentImage& a, const LightIndependentImage& b) {
  double worst = 0.0;
  for (int p = 0; p < a.planes(); ++p)
    for (std::size_t i = 0; i < a.pixels(); ++i)
      worst = std::max(worst, std::abs(double(a.planeFloat(p)[i]) - b.planeFloat(p)[i]));
  return worst;
}

// Interpolated voxel differences are the on-the-fly central differences away from the border;
// what is left is float rounding and the last voxel layer.
TEST(RaycastGradients, PrecomputedAgreeWithOnTheFly) {
  const Scene scene = test::phantomScene();
  for (const auto& [model, cv] : phantomClassified()) {
    const Pair p = renderBoth(scene, cv, {{"raycast", {{"gradients", "precomputed"}}}},
                              {{"raycast", {{"gradients", "on-the-fly"}}}});
    EXPECT_LT(largestDifference(p.a, p.b), 1e-4) << model;
  }
}

TEST(RaycastGradients, OverTheBudgetFallBackWithANote) {
  const Scene scene = test::phantomScene();
  const auto model = makeRgbModel(test::rendererObserver());
  const ClassifiedVolume cv = classifyScene(scene, *model);
  RenderRequest request = sceneRequest(scene, cv);
  request.width = request.height = 128;  // large enough that auto would precompute (64³ voxels)
  const std::uint64_t held = cv.values.size() * sizeof(float) +
                             LightIndependentImage::bytesFor(128, 128, cv.k, cv.t_channels);
  request.memory_budget = held + GradientVolume::bytesFor(cv.dims) / 2;
  std::vector<std::string> notes;
  request.note = [&](const std::string& n) { notes.push_back(n); };
  const auto fallback = RaycastRenderer().render(request);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("gradients computed per sample"), std::string::npos) << notes[0];
  EXPECT_NE(notes[0].find("over the memory budget"), std::string::npos) << notes[0];
  request.options = {{"raycast", {{"gradients", "on-the-fly"}}}};
  request.note = nullptr;
  EXPECT_EQ(largestDifference(fallback, RaycastRenderer().render(request)), 0.0);
  // Asked for explicitly, they are refused with the budget named rather than dropped.
  request.options = {{"raycast", {{"gradients", "precomputed"}}}};
  try {
    RaycastRenderer().render(request);
    FAIL() << "precomputed gradients over the budget were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("over the memory budget"), std::string::npos) << e.what();
  }
}

// The AVX2 kernels gather the eight corners and fuse multiply-adds; the portable ones do not.
// They agree to float rounding, for both gradient sources and spectral transmittance.
TEST(RaycastKernels, Avx2AgreesWithPortable) {
  if (availableKernelIsas().back() != KernelIsa::kAvx2) GTEST_SKIP() << "no AVX2 on this CPU";
  const Scene scene = test::phantomScene();
  for (const char* gradients : {"precomputed", "on-the-fly"})
    for (const auto& [model, cv] : phantomClassified()) {
      const nlohmann::json options = {{"raycast", {{"gradients", gradients}}}};
      const Pair p = renderBoth(scene, cv, options, options,
                                RaycastRenderer({.isa = KernelIsa::kPortable}),
                                RaycastRenderer({.isa = KernelIsa::kAvx2}));
      EXPECT_LT(largestDifference(p.a, p.b), 1e-4) << model << " " << gradients;
    }
}

}  // namespace
}  // namespace svr
