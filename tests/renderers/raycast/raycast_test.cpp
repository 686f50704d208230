#include "renderers/raycast/raycast_renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "renderers/classification/classification.h"
#include "renderers/model/scene_model.h"
#include "renderers/registry.h"
#include "spectral/componentwise_model.h"
#include "base/error.h"
#include "spectral/linear_model.h"
#include "spectral/post_illumination.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

LightIndependentImage renderScene(const Scene& scene, const ColourModel& model,
                                  const Renderer& renderer,
                                  std::optional<Eigen::VectorXd> baked = std::nullopt,
                                  bool skipping = true) {
  ClassificationOptions options = classificationOptions(scene);
  options.baked_light = baked;
  const ClassifiedVolume cv = classify(scene.volume, scene.transfer_function, model, options);
  RenderRequest request = sceneRequest(scene, cv);
  request.empty_space_skipping = skipping;
  return renderer.render(request);
}

TEST(Raycast, SlabTransmittanceIsExpMinusSigmaD) {
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  const RaycastRenderer renderer;
  const double sigma = 0.05;
  std::vector<double> errors;
  for (double step : {2.0, 1.0, 0.5, 0.25, 0.125}) {
    Scene scene = test::slabScene(sigma, "", step);
    // A (nearly) step-shaped opacity: σ switches on where the field crosses 0.5, i.e. halfway
    // between the last voxel inside and the first outside, so the slab is exactly as thick as
    // its voxels, and the sampling error depends on the step.
    scene.transfer_function.opacity = {{0.0, 0.0}, {0.49, 0.0}, {0.51, 1.0}, {1.0, 1.0}};
    // A slanted view, so the samples do not line up with the voxels: the chord is d / sin 60°.
    scene.camera = Camera::orbit(20.0, 60.0, 200.0, 0.0, 20.0);
    const double d = test::slabVoxels(scene) * scene.volume.spacing().z / std::sin(M_PI / 3);
    ASSERT_GT(d, 5.0);
    const auto img = renderScene(scene, *model, renderer);
    ASSERT_EQ(img.transmittanceChannels(), 1);  // achromatic: scalar transmittance
    errors.push_back(std::abs(img.transmittance(0, 16, 16) - std::exp(-sigma * d)));
  }
  EXPECT_LT(errors.back(), 1e-3);
  EXPECT_LT(errors.back(), 0.5 * errors.front());  // falls as the step shrinks
  for (size_t i = 1; i < errors.size(); ++i) EXPECT_LE(errors[i], errors[i - 1] + 1e-6) << i;
}

TEST(Raycast, SlabWithLinearOpacityIsExactAtAnyStep) {
  // Extinction linear in the value: the midpoint rule integrates the trilinear field exactly.
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  for (double step : {1.0, 0.25}) {
    const Scene scene = test::slabScene(0.05, "", step);
    const auto img = renderScene(scene, *model, RaycastRenderer());
    EXPECT_NEAR(img.transmittance(0, 16, 16), std::exp(-0.05 * test::slabVoxels(scene)), 1e-5);
  }
}

TEST(Raycast, SpectralSlabTransmittancePerChannel) {
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  const Scene scene = test::slabScene(0.05, "ColorChecker/cyan", 0.125);
  const double d = test::slabVoxels(scene);
  const auto img = renderScene(scene, *model, RaycastRenderer());
  ASSERT_EQ(img.transmittanceChannels(), 81);
  const Eigen::VectorXd a = test::rendererLibrary().get("ColorChecker/cyan").values();
  const Eigen::VectorXd shape = a / a.mean();
  for (int c = 0; c < 81; c += 10)
    EXPECT_NEAR(img.transmittance(c, 16, 16), std::exp(-0.05 * d * shape[c]), 1e-3) << c;
}

// Post-illumination equals a render with the light baked into the classification, for every
// registered backend and for rgb, factor:k and spectral:n with projected light matrices (the
// light's coefficients multiply the materials' componentwise, which is what baking means; full
// light matrices take the light's whole spectrum, which no componentwise bake can: their
// relit pixels are checked against the spectral product in PostIllumination tests). Two scenes:
// the phantom, a label map, and a scalar slab with a spectral absorber, whose splat sheets are
// classified per sheet pixel.
TEST(Raycast, RelitEqualsBakedInLight) {
  const Scene phantom = test::phantomScene();
  const Scene slab = test::slabScene(0.05, "ColorChecker/cyan", 0.5);
  std::vector<std::unique_ptr<ColourModel>> models;
  models.push_back(makeRgbModel(test::rendererObserver()));
  models.push_back(makeSceneModel("factor:6/projected", phantom, test::rendererObserver()).model);
  models.push_back(makeSpectralModel(test::rendererObserver(), 31, LightMatrixKind::kProjected));
  for (const Scene* scene_of : {&phantom, &slab}) {
    const Scene& scene = *scene_of;
    for (const std::string& name : rendererNames()) {
      const auto renderer = makeRenderer(name);
      for (const auto& model : models) {
        SCOPED_TRACE((scene_of == &phantom ? "phantom " : "slab ") + name + " " + model->name());
        const Spectrum spectrum =
            test::rendererObserver().unitLuminance(test::rendererLibrary().get("A"));
        const Eigen::VectorXd light = model->project(spectrum);
        const auto independent = renderScene(scene, *model, *renderer);
        const auto baked = renderScene(scene, *model, *renderer, light);
        PostIlluminator post(*model);
        std::vector<float> relit(3 * independent.pixels()), direct(relit.size());
        post.setLight(spectrum);
        post.relightLinear(independent, relit, RelitSpace::kXyz);
        ASSERT_TRUE(model->white().isApprox(Eigen::VectorXd::Ones(model->channels())));
        post.setLight(Spectrum::constant(spectrum.grid(), 1.0));  // coefficients: all ones
        post.relightLinear(baked, direct, RelitSpace::kXyz);
        double peak = 0;
        for (float v : direct) peak = std::max(peak, std::abs(double(v)));
        ASSERT_GT(peak, 0.01);  // the scene is visible
        for (size_t i = 0; i < relit.size(); ++i)
          ASSERT_NEAR(relit[i], direct[i], 1e-5 * peak) << i;
      }
    }
  }
}

TEST(Raycast, FixedWidthKernelsEqualTheDynamicPath) {
  Scene scene = test::phantomScene();
  for (int k : {3, 4, 6, 8}) {
    const auto model = makeSpectralModel(test::rendererObserver(), k);
    const auto fixed = renderScene(scene, *model, RaycastRenderer());
    const auto dynamic = renderScene(scene, *model, RaycastRenderer({.dynamic_width = true, .isa = std::nullopt}));
    ASSERT_EQ(fixed.planes(), dynamic.planes());
    ASSERT_EQ(fixed.transmittanceChannels(), k);  // the phantom has a spectral absorber
    for (int p = 0; p < fixed.planes(); ++p)
      for (size_t i = 0; i < fixed.pixels(); ++i)
        ASSERT_NEAR(fixed.planeFloat(p)[i], dynamic.planeFloat(p)[i], 1e-6) << k << " " << p;
  }
}

TEST(Raycast, EmptySpaceSkippingChangesNothing) {
  const Scene scene = test::phantomScene();
  const auto model = makeSpectralModel(test::rendererObserver(), 6);
  const auto skipped = renderScene(scene, *model, RaycastRenderer(), std::nullopt, true);
  const auto full = renderScene(scene, *model, RaycastRenderer(), std::nullopt, false);
  for (int p = 0; p < skipped.planes(); ++p)
    for (size_t i = 0; i < skipped.pixels(); ++i)
      ASSERT_NEAR(skipped.planeFloat(p)[i], full.planeFloat(p)[i],
                  1e-6 * (1 + std::abs(full.planeFloat(p)[i])));
}

TEST(Raycast, PerspectiveCameraSeesTheSameSlab) {
  Scene scene = test::slabScene(0.05, "", 0.25);
  scene.camera.fov_degrees = 30.0;
  scene.camera.eye = glm::dvec3(0, 0, 200);
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const auto img = renderScene(scene, *model, RaycastRenderer());
  // The centre ray is perpendicular to the slab: the same transmittance as orthographic.
  const double d = test::slabVoxels(scene);
  EXPECT_NEAR(img.transmittance(0, 16, 16), std::exp(-0.05 * d), 2e-3);
}

TEST(Raycast, LinearModelIsRefusedClearly) {
  const Scene scene = test::phantomScene();
  const auto lin = std::make_unique<LinearModel>(
      test::rendererObserver(), Eigen::MatrixXd::Identity(81, 4));
  EXPECT_THROW(renderScene(scene, *lin, RaycastRenderer()), Error);
}

TEST(Registry, NamesEveryBackendAndRejectsUnknownOnes) {
  const auto names = rendererNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "raycast"), names.end());
  try {
    makeRenderer("raytrace");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unknown renderer 'raytrace'; registered: raycast"),
              std::string::npos);
  }
}

// The harness's reference and auto's probe take the backend the registry calls the reference:
// exactly one entry says so, and it is the raycaster.
TEST(Registry, OneReferenceBackendTheRaycaster) {
  int references = 0;
  for (const auto& e : backendEntries()) references += e.info.supports.reference ? 1 : 0;
  EXPECT_EQ(references, 1);
  EXPECT_EQ(referenceRendererName(), "raycast");
}

}  // namespace
}  // namespace svr
