#include "harness/comparison.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "harness/compare_command.h"
#include "harness/sweep_command.h"
#include "renderers/registry.h"
#include "spectral/componentwise_model.h"
#include "spectral/image_difference.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

bool registered(const std::string& name) {
  const auto names = rendererNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

TEST(CompareRelit, IdenticalImagesDifferByZero) {
  const auto model = makeSpectralModel(test::rendererObserver(), 6);
  LightIndependentImage img(8, 8, 6, 1);
  for (int p = 0; p < 6; ++p)
    for (int i = 0; i < 64; ++i) img.setSample(p, i % 8, i / 8, 0.1f + 0.01f * p);
  for (int i = 0; i < 64; ++i) img.setSample(6, i % 8, i / 8, 0.2f);
  const Spectrum d65 = test::rendererObserver().unitLuminance(test::rendererLibrary().get("D65"));
  const auto d = compareRelit(img, *model, img, *model, d65, test::rendererObserver().xyz(d65));
  EXPECT_EQ(d.covered, 64u);
  EXPECT_EQ(d.stats.mean, 0.0);
  EXPECT_EQ(d.stats.max, 0.0);
}

TEST(CompareRelit, AKnownPerturbationGivesTheExpectedDeltaE) {
  // Scaling S by 0.8 scales XYZ by 0.8: ΔE2000 is that of the two Lab colours, every pixel.
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  LightIndependentImage a(4, 4, 81, 1), b(4, 4, 81, 1);
  const Spectrum refl = test::rendererLibrary().get("ColorChecker/orange");
  for (int c = 0; c < 81; ++c)
    for (int i = 0; i < 16; ++i) {
      a.setSample(c, i % 4, i / 4, static_cast<float>(refl[c]));
      b.setSample(c, i % 4, i / 4, static_cast<float>(0.8 * refl[c]));
    }
  for (int i = 0; i < 16; ++i) a.setSample(81, i % 4, i / 4, 0.0f), b.setSample(81, i % 4, i / 4, 0.0f);
  const Spectrum d65 = test::rendererObserver().unitLuminance(test::rendererLibrary().get("D65"));
  const Xyz white = test::rendererObserver().xyz(d65);
  const Xyz xyz = test::rendererObserver().xyz(d65 * refl);
  const double expected = deltaE2000(xyzToLab(xyz, white), xyzToLab(0.8 * xyz, white));
  const auto d = compareRelit(a, *model, b, *model, d65, white);
  EXPECT_NEAR(d.stats.mean, expected, 1e-3);
  EXPECT_NEAR(d.stats.max, expected, 1e-3);
  EXPECT_GT(expected, 3.0);
}

TEST(Tolerances, DefaultsAndSceneOverrides) {
  auto find = [](const std::vector<Tolerance>& t, const std::string& m) {
    for (const auto& x : t)
      if (x.metric == m) return x.limit;
    return -1.0;
  };
  EXPECT_EQ(find(tolerancesFor("raycast", {}), "de_vs_raycast_mean"), -1.0);
  EXPECT_EQ(find(tolerancesFor("shearwarp", {}), "de_vs_raycast_mean"), 3.0);
  const nlohmann::json scene = {{"de_mean", 5.0}, {"splat", {{"de_vs_raycast_mean", 4.5}}}};
  EXPECT_EQ(find(tolerancesFor("splat", scene), "de_mean"), 5.0);
  EXPECT_EQ(find(tolerancesFor("splat", scene), "de_vs_raycast_mean"), 4.5);
  EXPECT_EQ(find(tolerancesFor("raycast", scene), "de_mean"), 5.0);
  // Per algorithm: gl's ray casting is the raycaster's algorithm, its splats the splats'.
  EXPECT_EQ(find(tolerancesFor("gl", {}), "de_vs_raycast_mean"), 0.1);
  EXPECT_EQ(find(tolerancesFor("gl", {}, {{"mode", "raycast"}}), "de_vs_raycast_p95"), 0.3);
  EXPECT_EQ(find(tolerancesFor("gl", {}, {{"mode", "splat"}}), "de_vs_raycast_mean"),
            find(tolerancesFor("splat", {}), "de_vs_raycast_mean"));
  EXPECT_EQ(find(tolerancesFor("gl", {}, {{"mode", "splat"}}), "de_vs_raycast_p95"),
            find(tolerancesFor("splat", {}), "de_vs_raycast_p95"));
  // A backend's key in the scene covers its modes.
  EXPECT_EQ(find(tolerancesFor("gl", {{"gl", {{"de_vs_raycast_mean", 0.5}}}}, {{"mode", "splat"}}),
                 "de_vs_raycast_mean"),
            0.5);
  // The run's options over the scene's, for its own backend only.
  const RunSpec spec{"gl", "rgb", {{"gl", {{"mode", "splat"}}}, {"splat", {{"sigma", 1}}}}};
  EXPECT_EQ(runBackendOptions(spec, {{"gl", {{"mode", "raycast"}, {"sheet", 2}}}}),
            nlohmann::json({{"mode", "splat"}, {"sheet", 2}}));
  EXPECT_EQ(runBackendOptions({"gl", "rgb", {}}, {{"gl", {{"mode", "splat"}}}}),
            nlohmann::json({{"mode", "splat"}}));
}

TEST(Comparison, RaycastAgainstItselfAndATightToleranceFails) {
  Scene scene = test::phantomScene();
  scene.width = scene.height = 32;
  ComparisonSession session(scene, test::rendererDataDir());
  // At the finest reference step and no early termination, spectral:81 is the reference itself.
  scene.step_voxels = ReferenceStep().finest_voxels;
  scene.termination = 0.0;
  ComparisonSession fine(scene, test::rendererDataDir());
  ASSERT_EQ(fine.referenceStep().step_voxels, scene.step_voxels);
  const RunResult exact = fine.run({"raycast", "spectral:81", nlohmann::json::object()});
  for (const auto& l : exact.lights) EXPECT_EQ(l.vs_reference.max, 0.0) << l.light;
  const RunResult rgb = session.run({"raycast", "rgb", nlohmann::json::object()});
  ASSERT_EQ(rgb.lights.size(), 4u);  // three lights and one mix
  EXPECT_GT(rgb.lights[0].vs_reference.mean, 0.0);
  const auto misses = checkTolerances(rgb, {{"de_mean", 1e-4}});
  ASSERT_FALSE(misses.empty());
  EXPECT_NE(misses[0].str().find("run 'raycast rgb' light 'D65': de_mean = "), std::string::npos)
      << misses[0].str();
  EXPECT_NE(misses[0].str().find("exceeds the tolerance 0.0001"), std::string::npos);
  EXPECT_TRUE(checkTolerances(rgb, {}).empty());
}

// The total error splits into the model's (against spectral:81 at the run's own sampling) and
// the sampling's (that image against the reference): where the run samples as the reference
// does, the whole error is the model's; spectral:81's whole error is the sampling's.
TEST(Comparison, ModelAndSamplingErrorsApart) {
  Scene scene = test::phantomScene();
  scene.width = scene.height = 32;
  ComparisonSession session(scene, test::rendererDataDir());
  const RunResult exact = session.run({"raycast", "spectral:81", nlohmann::json::object()});
  const RunResult rgb = session.run({"raycast", "rgb", nlohmann::json::object()});
  scene.step_voxels = ReferenceStep().finest_voxels;
  scene.termination = 0.0;
  ComparisonSession fine(scene, test::rendererDataDir());
  const RunResult rgb_fine = fine.run({"raycast", "rgb", nlohmann::json::object()});
  for (std::size_t i = 0; i < rgb.lights.size(); ++i) {
    SCOPED_TRACE(rgb.lights[i].light);
    EXPECT_EQ(exact.lights[i].model_error.max, 0.0);
    EXPECT_EQ(exact.lights[i].sampling_error.mean, exact.lights[i].vs_reference.mean);
    EXPECT_GT(exact.lights[i].sampling_error.mean, 0.0);  // step 0.5 with early termination
    // rgb's exact twin is that same spectral:81 image.
    EXPECT_EQ(rgb.lights[i].sampling_error.mean, exact.lights[i].sampling_error.mean);
    EXPECT_GT(rgb.lights[i].model_error.mean, 0.0);
    EXPECT_EQ(rgb_fine.lights[i].sampling_error.max, 0.0);
    EXPECT_EQ(rgb_fine.lights[i].model_error.mean, rgb_fine.lights[i].vs_reference.mean);
  }
}

// The reference's step: halved from the start until halving it again changes the probe image
// by at most the target; a target nothing meets ends at the finest step, not converged.
TEST(Comparison, ReferenceStepHalvesUntilConverged) {
  Scene scene = test::phantomScene();
  scene.width = scene.height = 32;
  const Observer& observer = test::rendererObserver();
  const ReferenceStep loose = convergedReferenceStep(scene, observer, 0.25, 1e9);
  EXPECT_EQ(loose.step_voxels, 0.25);
  EXPECT_TRUE(loose.converged);
  EXPECT_GT(loose.halving_de2000, 0.0);
  const ReferenceStep never = convergedReferenceStep(scene, observer, 0.25, 0.0);
  EXPECT_EQ(never.step_voxels, never.finest_voxels);
  EXPECT_FALSE(never.converged);
  // Halving the step shrinks the change: each halving's figure is below the one before.
  EXPECT_LT(never.halving_de2000, loose.halving_de2000);
  const ReferenceStep chosen = convergedReferenceStep(scene, observer, 0.25);
  EXPECT_LE(chosen.halving_de2000, kReferenceStepTarget);
  EXPECT_TRUE(chosen.converged);
  // A start already finer than the finest step is kept, never coarsened.
  EXPECT_EQ(convergedReferenceStep(scene, observer, 0.05, 0.0).step_voxels, 0.05);
}

// A depth sweep of the phantom (its box absorbs spectrally): six channels hold at every depth,
// and never lose to three. (A trained factor:3 used to break down here, at more than twice
// factor:6's error at depth 16; chosen on the scene's render, factor:3 is now rgb, which does
// not, issue 40.)
TEST(Sweep, SixChannelsHoldUnderDeepAbsorptionAndNeverLoseToThree) {
  const std::string out = (std::filesystem::temp_directory_path() / "svr_sweep_depth").string();
  SweepOptions o;
  o.data_dir = test::rendererDataDir();
  o.scene = test::rendererDataDir() + "/scenes/phantom.json";
  o.param = "depth=1:16:15";
  o.renderers = {"raycast"};
  o.width = o.height = 32;
  o.charts = false;
  o.quiet = true;
  o.out_dir = out;
  o.model = "factor:3";
  const SweepResult k3 = runSweepStudy(o);
  o.model = "factor:6";
  const SweepResult k6 = runSweepStudy(o);
  ASSERT_EQ(k3.values, (std::vector<double>{1, 16}));
  for (size_t i = 0; i < k3.values.size(); ++i) {
    const double e3 = k3.curves[0].de_mean[i], e6 = k6.curves[0].de_mean[i];
    EXPECT_TRUE(std::isfinite(e3) && std::isfinite(e6));
    EXPECT_LE(e6, 1.0) << "depth " << k3.values[i];
    EXPECT_LE(e6, e3 + 0.05) << "depth " << k3.values[i] << ": factor:3 " << e3;
  }
  EXPECT_TRUE(std::filesystem::exists(out + "/sweep.json"));
}

// Shear-warp composites slices of the principal axis; at an azimuth of 45° (elevation 0) the
// rays cross the slices at the steepest angle, samples lie √2 voxels apart and the principal
// axis switches. Measured on the phantom at 64²: shear-warp 2.24–2.31 from 30° to 60° but 2.73
// at 45°, while the raycaster stays at 1.40–1.41 throughout.
TEST(Sweep, ShearWarpErrorPeaksAtTheAxisSwitch) {
  if (!registered("shearwarp")) GTEST_SKIP() << "shearwarp is not registered in this build";
  const auto dir = std::filesystem::temp_directory_path() / "svr_sweep_azimuth";
  std::filesystem::create_directories(dir);
  nlohmann::json scene;
  std::ifstream(test::rendererDataDir() + "/scenes/phantom.json") >> scene;
  scene["camera"]["elevation"] = 0;
  std::ofstream((dir / "phantom_level.json").string()) << scene.dump();
  SweepOptions o;
  o.data_dir = test::rendererDataDir();
  o.scene = (dir / "phantom_level.json").string();
  o.param = "azimuth=35:55:5";
  o.renderers = {"shearwarp"};
  o.width = o.height = 64;
  o.charts = false;
  o.quiet = true;
  o.out_dir = (dir / "out").string();
  const SweepResult r = runSweepStudy(o);
  ASSERT_EQ(r.values.size(), 5u);
  const auto& de = r.curves.at(0).de_mean;
  for (double v : de) EXPECT_TRUE(std::isfinite(v));
  for (std::size_t i : {0u, 1u, 3u, 4u}) EXPECT_GT(de[2], 1.1 * de[i]) << "azimuth " << r.values[i];
}

// Direct mode composites whole splats in the order of their centres; sheets slice the kernels
// and keep overlapping ones in order. With the default kernel (σ 0.55 voxel, truncated at 2)
// kernels overlap so little in depth that the two agree: measured 0.03 ΔE2000 apart on the
// engine and 0.01 on the frog (512², azimuth 30°), and with σ 1.2 direct mode was even 0.2
// closer to the reference than sheets on this phantom — the bleeding direct mode is known for
// needs wider kernels than a voxel grid calls for. What must hold: the two stay within 0.3 and
// both within the splat tolerance of the reference.
TEST(Sweep, SplatDirectAndSheetModesAgreeAtTheDefaultKernel) {
  if (!registered("splat")) GTEST_SKIP() << "splat is not registered in this build";
  Scene scene = test::phantomScene();
  scene.width = scene.height = 48;
  ComparisonSession session(scene, test::rendererDataDir());
  auto mean = [](const RunResult& r) {
    double m = 0;
    for (const auto& l : r.lights) m += l.vs_reference.mean / r.lights.size();
    return m;
  };
  const double sheet = mean(session.run({"splat", "rgb", {{"splat", {{"mode", "sheet"}}}}}));
  const double direct = mean(session.run({"splat", "rgb", {{"splat", {{"mode", "direct"}}}}}));
  EXPECT_NEAR(direct, sheet, 0.3);
  double tolerance = 0;
  for (const Tolerance& t : tolerancesFor("splat", nlohmann::json::object()))
    if (t.metric == "de_mean") tolerance = t.limit;
  EXPECT_LT(sheet, tolerance);
  EXPECT_LT(direct, tolerance);
}

}  // namespace
}  // namespace svr
