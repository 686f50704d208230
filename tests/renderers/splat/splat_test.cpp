#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>

#include "renderers/classification/classification.h"
#include "renderers/volume/procedural_volume.h"
#include "renderers/model/scene_model.h"
#include "renderers/raycast/raycast_renderer.h"
#include "renderers/classification/classified_sample.h"
#include "renderers/render/scene_render.h"
#include "renderers/kernels/splat_footprint.h"
#include "renderers/kernels/splat_settings.h"
#include "renderers/kernels/splat_projection.h"
#include "renderers/splat/splat_coverage.h"
#include "renderers/splat/splat_list.h"
#include "renderers/splat/splat_renderer.h"
#include "base/error.h"
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

// Mean ΔE2000 under D65 of `splat` against the raycaster's image of the same scene and model
// (so only the backends differ).
double meanAgainstRaycast(const Scene& scene, const ColourModel& model,
                          const LightIndependentImage& splat) {
  const auto ray = renderScene(scene, model, RaycastRenderer(), {});
  const Spectrum d65 = test::rendererObserver().unitLuminance(test::rendererLibrary().get("D65"));
  const auto diff = compareRelit(splat, model, ray, model, d65, test::rendererObserver().xyz(d65),
                                 0.98, scene.background);
  EXPECT_GT(diff.covered, 1000u);
  return diff.stats.mean;
}

Scene shippedScene(const std::string& name, int size) {
  Scene scene =
      loadScene(test::rendererDataDir() + "/scenes/" + name + ".json", test::rendererLibrary());
  scene.width = scene.height = size;
  return scene;
}

// Sheet mode against the raycaster at a generic view (azimuth 30°, elevation 20°): mean ΔE2000
// over covered pixels under D65, 96×96, rgb. Measured with the defaults: engine 1.34 (post-
// classified; pre-classified it was 2.32, the error on material boundaries), frog 1.72 (a label
// map: classified at the voxels). Until 2026-11 the frog measured 7.16: the raycaster blended
// label colours without opacity weighting, darkening every boundary, and splats were shaded at
// their centre only.
TEST(Splat, SheetModeAgreesWithTheRaycaster) {
  for (const std::string name : {"engine", "frog"}) {
    SCOPED_TRACE(name);
    Scene scene = shippedScene(name, 96);
    scene.camera = Camera::orbit(30.0, 20.0, glm::length(scene.camera.eye),
                                 scene.camera.fov_degrees, scene.camera.ortho_height);
    const SceneModel model = makeSceneModel("rgb", scene, test::rendererObserver());
    const double mean = meanAgainstRaycast(
        scene, *model.model, renderScene(scene, *model.model, SplatRenderer(), splatOptions("sheet")));
    std::printf("[ measured ] %s sheet vs raycast: mean ΔE2000 %.3f\n", name.c_str(), mean);
    EXPECT_LT(mean, 2.0);
  }
}

// The 16-bit CT scenes where pre-classified splats missed the raycaster by 2.4–3.0 (issue 17):
// an x-ray material (cthead) and a spectral absorber over a backdrop (headsq), magnified and
// minified. Post-classified sheets reconstruct the value the raycaster classifies and stay
// within 2; pre-classified ones still miss where the raycaster's interpolated value crosses a
// thin opacity ramp. 128², rgb; the scene's own zoom × 0.5 and × 2.
TEST(Splat, PostClassifiedSheetsAgreeWithTheRaycasterOnZoomedCt) {
  for (const std::string name : {"cthead_xray_zoom", "headsq_blood_backdrop"})
    for (const double zoom : {0.5, 2.0}) {
      SCOPED_TRACE(name + " zoom × " + std::to_string(zoom));
      Scene scene = shippedScene(name, 128);
      scene.camera.ortho_height /= zoom;
      const SceneModel model = makeSceneModel("rgb", scene, test::rendererObserver());
      const nlohmann::json post = {{"splat", {{"classification", "post"}}}};
      const double mean = meanAgainstRaycast(
          scene, *model.model, renderScene(scene, *model.model, SplatRenderer(), post));
      std::printf("[ measured ] %s × %.1f post-classified sheets vs raycast: mean ΔE2000 %.3f\n",
                  name.c_str(), zoom, mean);
      EXPECT_LT(mean, 2.0);
    }
}

// A binary ball (values 0 and 1) whose transfer function is opaque only near 0.5: no voxel
// holds such a value, so pre-classified splats have nothing to draw, while the raycaster's
// interpolated field crosses 0.5 on a shell around the ball. Post-classified sheets reconstruct
// that field and draw the shell too.
Scene shellScene() {
  const nlohmann::json j = {
      {"volume", {{"procedural", "sphere"}, {"size", 32}, {"radius", 0.7}}},
      {"materials",
       {{"shell", {{"reflectance", "ColorChecker/white 9.5 (.05 D)"}, {"opacity", 2.0}}}}},
      {"transfer_function",
       {{"points", {{0, "shell"}}},
        {"opacity", {{0, 0}, {0.3, 0}, {0.5, 1}, {0.7, 0}, {1, 0}}}}},
      {"lights", {"D65"}},
      {"camera", {{"azimuth", 30}, {"elevation", 20}, {"zoom", 1}}},
      {"image", {{"width", 40}, {"height", 40}}},
      {"render", {{"step", 0.5}, {"early_termination", 0}}},
  };
  return parseScene(j, test::rendererDataDir() + "/scenes/shell.json", test::rendererLibrary());
}

TEST(Splat, PostClassifiedSheetsFindAValueRangeNoVoxelHolds) {
  const Scene scene = shellScene();
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const auto ray = renderScene(scene, *model, RaycastRenderer(), {});
  const auto post = renderScene(scene, *model, SplatRenderer(),
                                {{"splat", {{"classification", "post"}}}});
  const auto pre = renderScene(scene, *model, SplatRenderer(),
                               {{"splat", {{"classification", "pre"}}}});
  // The ball's voxels are binary, so the shell follows their staircase, which the Gaussian and
  // the trilinear field trace differently by a fraction of a voxel: pixel by pixel the two
  // differ, but the splats must draw about as much of the shell as the raycaster does (measured:
  // 206 against 210 px). Its thickness differs by the kernel: across the step the Gaussian's
  // normalised sum rises with slope 1/(σ√(2π)) = 0.73 per voxel at σ 0.55, the trilinear field
  // with slope 1, so the 0.3–0.7 band is 1/0.73 = 1.38× as thick (measured: 1.41× the optical
  // depth).
  int seen_ray = 0, seen_post = 0;
  double depth_ray = 0, depth_post = 0;
  for (int y = 0; y < scene.height; ++y)
    for (int x = 0; x < scene.width; ++x) {
      EXPECT_EQ(pre.transmittance(0, x, y), 1.f) << x << " " << y;
      seen_ray += ray.transmittance(0, x, y) < 0.9f;
      seen_post += post.transmittance(0, x, y) < 0.9f;
      depth_ray -= std::log(ray.transmittance(0, x, y));
      depth_post -= std::log(post.transmittance(0, x, y));
    }
  std::printf("[ measured ] shell: T < 0.9 at %d px (raycaster) and %d px (post-classified "
              "splats); optical depth summed over the image %.1f and %.1f\n",
              seen_ray, seen_post, depth_ray, depth_post);
  EXPECT_GT(seen_ray, 150);
  EXPECT_NEAR(static_cast<double>(seen_post) / seen_ray, 1.0, 0.1);
  EXPECT_NEAR(depth_post / depth_ray, 0.55 * std::sqrt(2.0 * M_PI), 0.1);
}

// The phantom is a label map (classified at the voxels); the shell's sheets are post-classified.
// Every plane of b equals a's, byte for byte.
void expectSameBytes(const LightIndependentImage& a, const LightIndependentImage& b,
                     const std::string& what) {
  ASSERT_EQ(a.planes(), b.planes()) << what;
  for (int p = 0; p < a.planes(); ++p)
    ASSERT_EQ(std::memcmp(a.planeFloat(p).data(), b.planeFloat(p).data(),
                          a.pixels() * sizeof(float)),
              0)
        << what << " plane " << p;
}

// The engine at 256², about a pixel a voxel: footprints large enough to be factored
// (footprint_factors.h), where the small test scenes' are evaluated splat by splat.
Scene engineAt256() {
  Scene engine = loadScene(test::rendererDataDir() + "/scenes/engine.json", test::rendererLibrary());
  engine.width = engine.height = 256;
  return engine;
}

TEST(Splat, IdenticalBytesForOneAndTwoThreads) {
  const auto model = makeSpectralModel(test::rendererObserver(), 6);
  const Scene engine = engineAt256();
  for (const auto& [scene, mode] : {std::pair{test::phantomScene(), std::string("sheet")},
                                    {test::phantomScene(), "direct"},
                                    {shellScene(), "sheet"},
                                    {engine, "direct"},
                                    {engine, "sheet"}}) {
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const auto one = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    omp_set_num_threads(2);
    const auto two = renderScene(scene, *model, SplatRenderer(), splatOptions(mode));
    omp_set_num_threads(threads);
    expectSameBytes(one, two, mode);
  }
}

// A renderer keeps a frame's arrays for its next (reuse_pool.h): a second frame of another
// view, and a third of the first view again, on reused memory, give what fresh renderers give.
TEST(Splat, FramesOnReusedMemoryEqualFreshOnes) {
  const auto model = makeSpectralModel(test::rendererObserver(), 3);
  Scene engine = engineAt256();
  Scene turned = engine;
  turned.camera = orbitCamera(engine.camera, {.azimuth = 20, .elevation = 10, .zoom = 1.3});
  {  // the scene takes the factored footprints
    const ClassifiedVolume cv = classifyScene(engine, *model);
    const RenderRequest req = sceneRequest(engine, cv);
    const splat::KernelShape kernel =
        splat::splatSettings(readBackendOptions(splat::splatOptionSpecs(), {}, "splat")).kernel;
    const splat::FootprintTable table(kernel.cutoff());
    splat::SplatListMemory memory;
    const splat::SplatList list(cv, req,
                                splat::Projector(req.camera, req.width, req.height, cv.spacing,
                                                 kernel),
                                splat::SplatVoxels::Set::kVisible, memory);
    ASSERT_NE(splat::SplatCoverage(list, table, req.width, req.height).factors(), nullptr);
  }
  for (const std::string mode : {"direct", "sheet"}) {
    const SplatRenderer reused;
    for (const Scene* scene : {&engine, &turned, &engine}) {
      const auto again = renderScene(*scene, *model, reused, splatOptions(mode));
      const auto fresh = renderScene(*scene, *model, SplatRenderer(), splatOptions(mode));
      expectSameBytes(fresh, again, mode);
    }
  }
}

// A frame's splat arrays count against the memory budget (about 100 bytes a listed voxel: some
// 140 MiB for the engine's 1.4 M at any image size), as the output image does: a budget with
// room for the image alone is refused, naming the backend; one with room for both renders.
TEST(Splat, WorkingArraysCountAgainstTheMemoryBudget) {
  const auto model = makeSpectralModel(test::rendererObserver(), 3);
  const Scene engine = engineAt256();
  const ClassifiedVolume cv = classifyScene(engine, *model);
  RenderRequest request = sceneRequest(engine, cv);
  const std::uint64_t image =
      LightIndependentImage::bytesFor(request.width, request.height, cv.k, cv.t_channels);
  for (const std::string mode : {"direct", "sheet"}) {
    request.options = splatOptions(mode);
    request.memory_budget = image + (std::uint64_t{16} << 20);  // room for the image and 16 MiB
    try {
      SplatRenderer().render(request);
      FAIL() << mode << ": a budget with room for the image alone was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("splat"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("over the memory budget"), std::string::npos)
          << e.what();
    }
    request.memory_budget = image + (std::uint64_t{512} << 20);
    EXPECT_NO_THROW(SplatRenderer().render(request)) << mode;
  }
}

// The depth sort is a stable sort of the keys (−0 with +0), whether the keys span few float
// bit patterns (one sign, within a factor of two: the two-pass case) or many (both signs, tiny
// and huge magnitudes), with ties, at sizes of one chunk and of many, and at 1 and 2 threads.
TEST(SplatProjection, SortByDepthIsAStableSortOfTheKeys) {
  std::uint32_t state = 12345;
  const auto next = [&] { return state = state * 1664525u + 1013904223u; };
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{1000}, std::size_t{300000}})
    for (int kind = 0; kind < 3; ++kind) {
      std::vector<float> key(n + 7);
      for (float& k : key) {
        const float u = static_cast<float>(next() >> 8) / 16777216.f;  // [0, 1)
        k = kind == 0   ? 500.f + 400.f * u                           // one exponent or two
            : kind == 1 ? (u - 0.5f) * std::ldexp(1.f, static_cast<int>(next() % 60) - 30)
                        : static_cast<float>(next() % 5) - 2.f;      // ties, ±0 among them
        if (kind == 2 && k == 0.f && (next() & 1)) k = -0.f;
      }
      std::vector<std::uint32_t> ids;
      for (std::uint32_t i = 0; i < n + 7; ++i)
        if (i % 8 != 3) ids.push_back(i);  // a subset, ascending, as keptIndices gives
      std::vector<std::uint32_t> expected = ids;
      std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
        return (key[a] == 0.f ? 0.f : key[a]) < (key[b] == 0.f ? 0.f : key[b]);
      });
      for (const int threads : {1, 2}) {
        omp_set_num_threads(threads);
        std::vector<std::uint32_t> sorted = ids;
        splat::DepthSortScratch scratch;
        splat::sortByDepth(sorted, key, scratch);
        EXPECT_EQ(sorted, expected) << "n " << n << " kind " << kind << " threads " << threads;
      }
    }
  omp_set_num_threads(omp_get_num_procs());
}

// Orthographic footprints in factors (footprint_factors.h) are the footprint itself: on the CT
// head (slices twice as far apart as pixels) seen obliquely and rolled, so that the footprint's
// ellipse is tilted (b ≠ 0), every pixel of every row of a sample of splats gets norm · exp(−q/2)
// to 1e-5 of norm (float rounding of exponents up to ±20; the kernel table's nearest bin, which
// the per-splat evaluation reads, errs by up to 8e-4), the row's [lo, hi] holds exactly the pixels with q < cutoff² (to 1e-3 in q), and
// the three lengths after hi are 0.
TEST(SplatRows, FactoredLengthsAreTheFootprint) {
  Scene scene = loadScene(test::rendererDataDir() + "/scenes/cthead_xray_zoom.json",
                          test::rendererLibrary());
  scene.camera.eye = {-350, -420, 260};  // at the scene's 256², about 2 pixels a voxel
  scene.camera.up = {0.5, 0.2, -1.0};  // rolled, so that the long axis (z) is oblique on screen
  const auto model = makeSpectralModel(test::rendererObserver(), 3);
  const ClassifiedVolume cv = classifyScene(scene, *model);
  const RenderRequest req = sceneRequest(scene, cv);
  const splat::KernelShape kernel =
      splat::splatSettings(readBackendOptions(splat::splatOptionSpecs(), {}, "splat")).kernel;
  const splat::Projector projector(req.camera, req.width, req.height, cv.spacing, kernel);
  splat::SplatListMemory memory;
  const splat::SplatList list(cv, req, projector, splat::SplatVoxels::Set::kVisible, memory);
  const splat::FootprintTable table(kernel.cutoff());
  const splat::SplatCoverage coverage(list, table, req.width, req.height);
  ASSERT_NE(coverage.factors(), nullptr);
  const splat::Footprint& fp = list.footprint(0);
  ASSERT_GT(std::abs(fp.b), 0.05 * fp.a);
  const double cut2 = table.cutoffSquared();
  splat::SplatRows rows(coverage);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < list.splats().size(); i += 97) {
    const splat::Splat& s = list.splats()[i];
    const splat::SplatRows::Box box = rows.start(i);
    for (int y = box.ya; y <= box.yb; ++y) {
      int lo, hi;
      const float* w = rows.row(y, lo, hi);
      for (int x = box.xa; x <= box.xb; ++x) {
        const double dx = x + 0.5 - s.x, dy = y + 0.5 - s.y;
        const double q = fp.a * dx * dx + 2.0 * fp.b * dx * dy + fp.c * dy * dy;
        if (x < lo || x > hi) {
          EXPECT_GT(q, cut2 - 1e-3) << i << " " << x << " " << y;
          continue;
        }
        EXPECT_LT(q, cut2 + 1e-3) << i << " " << x << " " << y;
        if (q < cut2 - 1e-3) {
          EXPECT_NEAR(w[x - lo], fp.norm * std::exp(-0.5 * q), 1e-5 * fp.norm) << i << " " << x;
        }
        ++checked;
      }
      if (lo <= hi) {
        for (int m = 1; m <= 3; ++m) EXPECT_EQ(w[hi - lo + m], 0.f);
      }
    }
  }
  EXPECT_GT(checked, 1000u);
}

// A splat's coefficients come from two rows of its blend table (σ_α, σ_α·s, σ_α·ρ, σ_t): the
// same opacity-weighted blend as blendEntries over the splat's per-unit-length tables, to float
// rounding, at every entry and between entries, for scalar and spectral transmittance and where
// nothing scatters (σ_α = 0: colour 0).
TEST(Splat, BlendTableCoefficientsEqualBlendEntries) {
  Scene engine = loadScene(test::rendererDataDir() + "/scenes/engine.json", test::rendererLibrary());
  engine.width = engine.height = 32;
  const Scene spectral_slab = test::slabScene(0.05, "ColorChecker/cyan", 0.5);
  for (const Scene& scene : {engine, spectral_slab})
    for (const int k : {3, 6}) {
      const auto model = makeSpectralModel(test::rendererObserver(), k);
      const ClassifiedVolume cv = classifyScene(scene, *model);
      const RenderRequest req = sceneRequest(scene, cv);
      const splat::Projector projector(req.camera, req.width, req.height, cv.spacing,
                                       splat::splatSettings(readBackendOptions(
                                           splat::splatOptionSpecs(), {}, "splat")).kernel);
      splat::SplatListMemory memory;
      const splat::SplatList list(cv, req, projector, splat::SplatVoxels::Set::kVisible, memory);
      const auto voxels = splat::SplatVoxels::of(cv, splat::SplatVoxels::Set::kVisible);
      const int kt = cv.t_channels;
      std::vector<float> sigma_t(kt), colour(k), ref_refl(k), ref_t(kt);
      int scattering = 0, clear = 0;
      for (int e = 0; e < cv.entries; ++e)
        for (const float frac : {0.f, 0.25f, 0.5f, 0.875f}) {
          const float shade = 0.3f + 0.7f * frac, highlight = 0.6f - 0.5f * frac;
          splat::SplatCoefficients coef{0.f, sigma_t, colour};
          list.classifyBin(static_cast<float>(e) + frac, shade, highlight, coef);
          int e0, e1;
          float f;
          entriesOfBin(cv, static_cast<float>(e) + frac, e0, e1, f);
          const int entry[2] = {e0, e1};
          const float w[2] = {1.f - f, f};
          float ref_alpha, ref_spec;
          blendEntries(cv, voxels->sigmaAlpha().data(), voxels->sigmaT().data(), entry, w, 2, k,
                       kt, ref_alpha, ref_spec, ref_refl.data(), ref_t.data());
          ASSERT_NEAR(coef.sigma_alpha, ref_alpha, 1e-6f * std::abs(ref_alpha) + 1e-12f) << e;
          for (int c = 0; c < kt; ++c)
            ASSERT_NEAR(sigma_t[c], ref_t[c], 1e-6f * std::abs(ref_t[c]) + 1e-12f) << e << " " << c;
          for (int c = 0; c < k; ++c) {
            const float want = ref_refl[c] * shade + cv.white[c] * highlight * ref_spec;
            ASSERT_NEAR(colour[c], want, 2e-6f * (std::abs(want) + 1.f)) << e << " " << c;
          }
          (ref_alpha > 0.f ? scattering : clear) += 1;
        }
      EXPECT_GT(scattering, 0);  // both branches were taken
      EXPECT_GT(clear, 0);
    }
}

// Direct compositing's loops are compiled for the common channel counts (channel_widths.h)
// and for any k: both give the same bytes, over scalar (the engine) and spectral transmittance
// and a label map, at every compiled width and one that is not.
TEST(Splat, FixedWidthDirectCompositingEqualsDynamicWidth) {
  Scene engine = loadScene(test::rendererDataDir() + "/scenes/engine.json", test::rendererLibrary());
  engine.width = engine.height = 48;
  const Scene spectral_slab = test::slabScene(0.05, "ColorChecker/cyan", 0.5);
  for (const Scene& scene : {engine, test::phantomScene(), spectral_slab})
    for (const int k : {3, 4, 6, 8, 5}) {
      const auto model = makeSpectralModel(test::rendererObserver(), k);
      const auto fixed = renderScene(scene, *model, SplatRenderer(), splatOptions("direct"));
      const auto dynamic = renderScene(scene, *model, SplatRenderer({.dynamic_width = true, .isa = std::nullopt}),
                                       splatOptions("direct"));
      ASSERT_EQ(fixed.planes(), dynamic.planes());
      for (int p = 0; p < fixed.planes(); ++p)
        ASSERT_EQ(std::memcmp(fixed.planeFloat(p).data(), dynamic.planeFloat(p).data(),
                              fixed.pixels() * sizeof(float)),
                  0)
            << "k " << k << " plane " << p;
      float peak_s = 0.f, least_t = 1.f;  // something was drawn: it scatters or absorbs
      for (int c = 0; c < k; ++c)
        for (const float v : fixed.planeFloat(c)) peak_s = std::max(peak_s, v);
      for (const float t : fixed.planeFloat(k)) least_t = std::min(least_t, t);
      EXPECT_TRUE(peak_s > 0.01f || least_t < 0.9f) << "k " << k << ": " << peak_s << " " << least_t;
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

// Post-classification where it cannot apply is an error that says why, not a silent fallback.
TEST(Splat, PostClassificationWhereItCannotApplyNamesTheKey) {
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const auto expectError = [&](const Scene& scene, const nlohmann::json& options,
                               const std::string& part) {
    try {
      renderScene(scene, *model, SplatRenderer(), options);
      FAIL() << options.dump();
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError(test::slabScene(0.05, "", 0.5),
              {{"splat", {{"classification", "post"}, {"mode", "direct"}}}},
              "splat.classification=post needs splat.mode=sheet");
  expectError(test::phantomScene(), {{"splat", {{"classification", "post"}}}},
              "splat.classification=post needs a scalar volume");
  // auto classifies the label map at its voxels, and the slab per sheet pixel.
  EXPECT_NO_THROW(renderScene(test::phantomScene(), *model, SplatRenderer(), {}));
}

}  // namespace
}  // namespace svr
