#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>

#include "renderers/core/classification.h"
#include "renderers/core/procedural_volume.h"
#include "renderers/scene_model.h"
#include "renderers/raycast/raycast_renderer.h"
#include "renderers/core/splat_footprint.h"
#include "renderers/core/splat_settings.h"
#include "renderers/splat/splat_renderer.h"
#include "spectral/error.h"
#include "spectral/image_difference.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

LightIndependentImage renderScene(const Scene& scene, const ColourModel& model,
                                  const Renderer& renderer, const nlohmann::json& options) {
  return test::render(renderer, scene, model, options);
}

nlohmann::json splatOptions(const std::string& mode) { return {{"splat", {{"mode", mode}}}}; }

// The footprint's line integrals, summed over the pixels and converted to world area, give the
// kernel's integral: the voxel's volume (the truncated Gaussian is renormalised).
TEST(SplatFootprint, IntegratesToTheKernelIntegral) {
  const splat::KernelShape kernel{0.7, 2.0, 0.3};
  const splat::FootprintTable table(kernel.cutoff());
  const glm::dvec3 spacing(1.0, 1.5, 2.0);
  const double volume = spacing.x * spacing.y * spacing.z;
  for (double fov : {0.0, 40.0}) {
    const Camera camera = Camera::orbit(30.0, 20.0, 60.0, fov, 20.0);
    const int size = 256;
    const splat::Projector projector(camera, size, size, spacing, kernel);
    for (const glm::dvec3 world : {glm::dvec3(0.0), glm::dvec3(3.3, -2.1, 1.7)}) {
      SCOPED_TRACE(fov);
      const glm::dvec3 pos = projector.project(world);
      const splat::Footprint fp = projector.footprint(world);
      ASSERT_GT(fp.half_w, 4.f);  // well resolved, so the pixel sum approximates the integral
      double sum = 0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const double dx = x + 0.5 - pos.x, dy = y + 0.5 - pos.y;
          const double q = fp.a * dx * dx + 2 * fp.b * dx * dy + fp.c * dy * dy;
          if (q < table.cutoffSquared()) sum += fp.norm * table.gaussian(static_cast<float>(q));
        }
      // Pixel area in world units at the voxel's depth.
      const double half_h = fov > 0 ? std::tan(fov * M_PI / 360.0) * pos.z : 10.0;
      const double pixel = 2.0 * half_h / size;
      EXPECT_NEAR(sum * pixel * pixel, volume, 5e-3 * volume);
    }
  }
}

TEST(SplatFootprint, SheetSharesOfAKernelSumToOne) {
  const splat::FootprintTable table(2.0 / 0.7);
  for (double offset : {0.0, 0.13, 0.5}) {
    double sum = 0;
    for (double t = -4.0 + offset; t < 4.0; t += 0.37)
      sum += table.cdf(static_cast<float>(t + 0.37)) - table.cdf(static_cast<float>(t));
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
  EXPECT_NEAR(table.cdf(0.f), 0.5, 1e-4);
}

// The slab of linear extinction seen along z: T = exp(−σ Σ values), in both modes, over the
// whole slab (no holes between splats). Tolerance: the ripple of the kernel lattice — the sum
// of the default kernels (σ 0.55, truncated at 2 voxels) varies by 1.9% peak to peak across a
// voxel, so T = 0.55 at τ = 0.6 varies by ±0.55·0.6·0.0095 = ±0.0031 — plus table lookups.
TEST(Splat, SlabTransmittanceIsExpMinusSigmaD) {
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const Scene scene = test::slabScene(0.05, "", 0.5);
  const double expected = std::exp(-0.05 * test::slabVoxels(scene));
  for (const std::string mode : {"sheet", "direct"}) {
    const auto img = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    for (int y = 4; y < 28; y += 3)
      for (int x = 4; x < 28; x += 3)
        EXPECT_NEAR(img.transmittance(0, x, y), expected, 4e-3) << mode << " " << x << " " << y;
  }
}

TEST(Splat, SpectralSlabTransmittancePerChannel) {
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  const Scene scene = test::slabScene(0.05, "ColorChecker/cyan", 0.5);
  const double d = test::slabVoxels(scene);
  const auto img = renderScene(scene, *model, SplatRenderer(), splatOptions("sheet"));
  ASSERT_EQ(img.transmittanceChannels(), 81);
  const Eigen::VectorXd a = test::rendererLibrary().get("ColorChecker/cyan").values();
  const Eigen::VectorXd shape = a / a.mean();
  for (int c = 0; c < 81; c += 10)
    EXPECT_NEAR(img.transmittance(c, 16, 16), std::exp(-0.05 * d * shape[c]), 4e-3) << c;
}

// A ball of radius R: optical depth σ·2√(R² − b²) at impact parameter b. A binary ball is a
// voxelised edge, so the chord is known to about a voxel: tolerance 1 voxel of chord for
// b ≤ 0.8 R (the raycaster meets the same bound).
TEST(Splat, SphereChordsMatchTheAnalyticLength) {
  const nlohmann::json j = {
      {"volume", {{"procedural", "sphere"}, {"size", 48}, {"radius", 0.8}}},
      {"materials",
       {{"ball", {{"reflectance", "ColorChecker/white 9.5 (.05 D)"}, {"opacity", 0.05}}}}},
      {"transfer_function", {{"points", {{0, "ball"}}}, {"opacity", {{0, 0}, {1, 1}}}}},
      {"lights", {"D65"}},
      {"camera", {{"azimuth", 30}, {"elevation", 20}, {"zoom", 1}}},
      {"image", {{"width", 48}, {"height", 48}}},
      {"render", {{"step", 0.5}, {"early_termination", 0}}},
  };
  const Scene scene =
      parseScene(j, test::rendererDataDir() + "/scenes/sphere.json", test::rendererLibrary());
  const double radius = 0.8 * 0.5 * 47;
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const RayGenerator rays(scene.camera, scene.width, scene.height);
  for (const std::string mode : {"sheet", "direct"}) {
    const auto img = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    int checked = 0;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 48; ++x) {
        const Ray ray = rays.ray(x + 0.5, y + 0.5);
        const double b = glm::length(glm::cross(ray.origin, ray.direction));
        if (b > 0.8 * radius) continue;
        const double depth = -std::log(img.transmittance(0, x, y)) / 0.05;
        EXPECT_NEAR(depth, sphereChordLength(radius, b), 1.0) << mode << " " << x << " " << y;
        ++checked;
      }
    EXPECT_GT(checked, 200);
  }
}

// Sheet mode against the raycaster at a generic view (azimuth 30°, elevation 20°): mean ΔE2000
// over covered pixels under D65, 96×96, rgb (both images share the model, so only the backends
// differ). Measured with the defaults: engine mean 2.32 / p95 8.1, frog 1.72 / 5.4 (at 512²:
// 2.42 / 8.2 and 1.74 / 5.5, so not a matter of resolution). The frog meets the goal of 2; the
// engine misses it by the difference between pre-classified kernels and the raycaster's
// post-classified samples at its sharp opacity steps (the error sits on material boundaries).
// Until 2026-11 the frog measured 7.16: the raycaster blended label colours without opacity
// weighting, darkening every boundary, and splats were shaded at their centre only.
TEST(Splat, SheetModeAgreesWithTheRaycaster) {
  for (const auto& [name, bound] : {std::pair{"engine", 2.6}, {"frog", 2.0}}) {
    SCOPED_TRACE(name);
    Scene scene =
        loadScene(test::rendererDataDir() + "/scenes/" + name + ".json", test::rendererLibrary());
    scene.width = scene.height = 96;
    scene.camera = Camera::orbit(30.0, 20.0, glm::length(scene.camera.eye),
                                 scene.camera.fov_degrees, scene.camera.ortho_height);
    const SceneModel model = makeSceneModel("rgb", scene, test::rendererObserver());
    const auto splat = renderScene(scene, *model.model, SplatRenderer(), splatOptions("sheet"));
    const auto ray = renderScene(scene, *model.model, RaycastRenderer(), {});
    const Spectrum d65 = test::rendererObserver().unitLuminance(test::rendererLibrary().get("D65"));
    const auto diff = compareRelit(splat, *model.model, ray, *model.model, d65,
                                   test::rendererObserver().xyz(d65));
    std::printf("[ measured ] %s sheet vs raycast: mean ΔE2000 %.3f, p95 %.3f, covered %zu\n", name,
                diff.stats.mean, diff.stats.p95, diff.covered);
    EXPECT_GT(diff.covered, 1000u);
    EXPECT_LT(diff.stats.mean, bound);
  }
}

TEST(Splat, IdenticalBytesForOneAndTwoThreads) {
  const Scene scene = test::phantomScene();
  const auto model = makeSpectralModel(test::rendererObserver(), 6);
  for (const std::string mode : {"sheet", "direct"}) {
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const auto one = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    omp_set_num_threads(2);
    const auto two = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    omp_set_num_threads(threads);
    for (int p = 0; p < one.planes(); ++p)
      ASSERT_EQ(std::memcmp(one.planeFloat(p).data(), two.planeFloat(p).data(),
                            one.pixels() * sizeof(float)),
                0)
          << mode << " plane " << p;
  }
}

// Principal-axis and 45° views (where direct mode's order and the sheets' orientation switch):
// finite everywhere, and no gaps: wherever the raycaster sees the phantom (T < 0.5), so does the
// splatter (T < 0.9).
TEST(Splat, PrincipalAxisAnd45DegreeViewsHaveNoGaps) {
  Scene scene = test::phantomScene();
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const double distance = glm::length(scene.camera.eye);
  for (const auto& [az, el] :
       {std::pair{0.0, 0.0}, {90.0, 0.0}, {0.0, 90.0}, {45.0, 0.0}, {45.0, 45.0}, {-45.0, 35.26}}) {
    scene.camera = Camera::orbit(az, el, distance, 0.0, scene.camera.ortho_height);
    const auto ray = renderScene(scene, *model, RaycastRenderer(), {});
    for (const std::string mode : {"sheet", "direct"}) {
      SCOPED_TRACE(mode + " " + std::to_string(az) + " " + std::to_string(el));
      const auto img = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
      int seen = 0;
      for (int p = 0; p < img.planes(); ++p)
        for (float v : img.planeFloat(p)) ASSERT_TRUE(std::isfinite(v));
      for (int y = 0; y < scene.height; ++y)
        for (int x = 0; x < scene.width; ++x) {
          if (ray.transmittance(0, x, y) >= 0.5f) continue;
          ++seen;
          EXPECT_LT(img.transmittance(0, x, y), 0.9f) << x << " " << y;
        }
      EXPECT_GT(seen, 100);
    }
  }
}

TEST(Splat, BadOptionsNameTheKeyAndValue) {
  const auto settingsOf = [](const nlohmann::json& options) {
    return splat::splatSettings(readBackendOptions(splat::splatOptionSpecs(), options, "splat"));
  };
  const auto expectError = [&](const nlohmann::json& options, const std::string& part) {
    try {
      settingsOf(options);
      FAIL() << options.dump();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError({{"splat", {{"mode", "blend"}}}}, "splat.mode: 'blend' is not one of sheet, direct");
  expectError({{"splat", {{"radius", -1}}}}, "splat.radius");
  expectError({{"splat", {{"sigmma", 0.7}}}}, "sigmma");
  // Other backends' options are theirs to check.
  EXPECT_NO_THROW(settingsOf({{"raycast", {{"anything", 1}}}}));
  EXPECT_EQ(settingsOf({{"splat", {{"mode", "direct"}}}}).mode,
            splat::SplatSettings::Mode::kDirect);
}

}  // namespace
}  // namespace svr
