// Issue 49's view corpus (bench/backends/view_corpus.h, seed 40): corpus scenes from any side,
// zoomed 1–3×, orthographic or perspective, at 96–128². On the first thirty views, with rgb and
// factor:6, what holds today and must keep holding: every backend renders every view it takes
// (no failure; shear-warp skips perspective cameras and only those), every figure is finite, and
// gl ray casting agrees with the CPU raycaster within 0.1 mean ΔE2000 (issue 49, goal 4) under
// every light; and shear-warp's median over the views it takes is within goal 4's 0.8 for both
// models. svr_backend_bench measures the whole corpus and prints the shares; shear-warp's p95
// target (2.0: 2.01 and 2.06 over 200 views) and the splats' are not met yet
// (docs/backends.md), so they are not asserted here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "bench/backends/backend_agreement.h"
#include "bench/backends/view_corpus.h"
#include "renderers/registry.h"

namespace svr {
namespace {

constexpr int kViewsPerCase = 5;

struct Corpus {
  std::shared_ptr<const SessionSpectra> spectra = std::make_shared<SessionSpectra>(SVR_TEST_DATA_DIR);
  SceneCorpus scenes{SVR_TEST_DATA_DIR, spectra->library, SceneCorpus::kDefaultSeed, 96};
  ViewCorpus views{scenes, spectra->library, SceneCorpus::kDefaultSeed};
};

const Corpus& corpus() {
  static const Corpus c;
  return c;
}

class ViewCorpusTest : public testing::TestWithParam<int> {};

TEST_P(ViewCorpusTest, EveryBackendRendersItsViewsAndGlAgreesWithTheRaycaster) {
  const Corpus& c = corpus();
  for (int i = GetParam(); i < GetParam() + kViewsPerCase; ++i) {
    SCOPED_TRACE(fmt::format("{} ({})", c.views.name(i), c.views.describe(i)));
    const Scene scene = c.views.scene(i);
    for (const std::string model : {"rgb", "factor:6"}) {
      SCOPED_TRACE(model);
      const BackendFrame raycast =
          renderBackendFrame(c.spectra, scene, referenceRendererName(), model);
      for (const auto& renderer : rendererNames()) {
        if (renderer == referenceRendererName()) continue;
        SCOPED_TRACE(renderer);
        const Agreement a = agreementWithRaycast(c.spectra, scene, raycast, renderer, model);
        const bool takes_view =
            backendEntry(renderer).info.supports.perspective || scene.camera.orthographic();
        ASSERT_NE(a.status, Agreement::Status::kFailed) << a.note;
        EXPECT_EQ(a.status == Agreement::Status::kSkipped, !takes_view) << a.note;
        if (a.status != Agreement::Status::kRendered) continue;
        EXPECT_TRUE(std::isfinite(a.vs_raycast) && std::isfinite(a.vs_raycast_p95));
        if (renderer == "gl") EXPECT_LE(a.vs_raycast, 0.1);
      }
    }
  }
}

// Shear-warp at its defaults (samples between slices for the render step, an intermediate image
// as fine as the screen) against the raycaster: the median over the first thirty views' orthographic
// ones (measured 0.41 for rgb and 0.40 for factor:6, 23 views; 1.24 with one sample a slice at
// volume resolution, rgb).
TEST(ViewCorpus, ShearWarpsMedianIsWithinItsTarget) {
  const Corpus& c = corpus();
  for (const std::string model : {"rgb", "factor:6"}) {
    std::vector<double> figures;
    for (int i = 0; i < 30; ++i) {
      const Scene scene = c.views.scene(i);
      if (!scene.camera.orthographic()) continue;
      const BackendFrame raycast =
          renderBackendFrame(c.spectra, scene, referenceRendererName(), model);
      const Agreement a = agreementWithRaycast(c.spectra, scene, raycast, "shearwarp", model);
      ASSERT_EQ(a.status, Agreement::Status::kRendered) << c.views.name(i) << ": " << a.note;
      figures.push_back(a.vs_raycast);
    }
    ASSERT_GE(figures.size(), 15u);
    std::sort(figures.begin(), figures.end());
    const double median = figures[(figures.size() - 1) / 2];  // nearest rank, the lower middle
    std::printf("shearwarp %s: median %.3f over %zu views\n", model.c_str(), median,
                figures.size());
    EXPECT_LE(median, 0.8) << model;
  }
}

INSTANTIATE_TEST_SUITE_P(FirstThirtyViews, ViewCorpusTest, testing::Range(0, 30, kViewsPerCase),
                         [](const testing::TestParamInfo<int>& info) {
                           return fmt::format("views_{}_to_{}", info.param,
                                              info.param + kViewsPerCase - 1);
                         });

}  // namespace
}  // namespace svr
