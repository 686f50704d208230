#include "renderers/core/scene.h"

#include <gtest/gtest.h>

#include "renderers/core/classification.h"
#include "renderers/scene_model.h"

#include <fmt/format.h>
#include "spectral/componentwise_model.h"
#include "spectral/error.h"
#include "tests/renderers/test_scenes.h"

namespace svr {
namespace {

nlohmann::json minimalScene() {
  return {{"volume", {{"procedural", "sphere"}, {"size", 16}}},
          {"materials", {{"m", {{"reflectance", "ColorChecker/red"}, {"opacity", 0.5}}}}},
          {"transfer_function", {{"points", {{0, "m"}}}}},
          {"lights", {"D65"}}};
}

std::string errorOf(const nlohmann::json& j) {
  try {
    parseScene(j, "s.json", test::rendererLibrary());
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Scene, DefaultScenesLoad) {
  for (const char* name : {"engine", "frog", "phantom"}) {
    const Scene s =
        loadScene(test::rendererDataDir() + "/scenes/" + name + ".json", test::rendererLibrary());
    EXPECT_GE(s.lights.size(), 2u) << name;
    EXPECT_FALSE(s.transfer_function.materials.empty()) << name;
  }
}

TEST(Scene, DefaultsAndOverrides) {
  auto j = minimalScene();
  Scene s = parseScene(j, "s.json", test::rendererLibrary());
  EXPECT_EQ(s.width, 512);
  EXPECT_EQ(s.model, "factor:6");
  EXPECT_TRUE(s.camera.orthographic());
  j["image"] = {{"width", 100}, {"height", 50}};
  j["render"] = {{"step", 0.25}};
  j["model"] = "spectral:31";
  s = parseScene(j, "s.json", test::rendererLibrary());
  EXPECT_EQ(s.width, 100);
  EXPECT_DOUBLE_EQ(s.stepWorld(), 0.25);
  EXPECT_EQ(s.model, "spectral:31");
}

TEST(Scene, ErrorsNameFileKeyPathAndValue) {
  auto j = minimalScene();
  j["camrea"] = {{"azimuth", 10}};
  EXPECT_EQ(errorOf(j), "s.json: unknown key 'camrea'");
  j = minimalScene();
  j["camera"] = {{"azimuth", "east"}};
  EXPECT_EQ(errorOf(j), "s.json: camera.azimuth: expected a number, got \"east\"");
  j = minimalScene();
  j["image"] = {{"width", -5}};
  EXPECT_EQ(errorOf(j), "s.json: image.width: value -5 is outside 1..16384");
  j = minimalScene();
  j["image"] = {{"width", 100000}};
  EXPECT_EQ(errorOf(j), "s.json: image.width: value 100000 is outside 1..16384");
  j = minimalScene();
  j["transfer_function"] = {{"points", {{0, "steel"}}}};
  EXPECT_EQ(errorOf(j),
            "s.json: transfer_function.points[0][1]: no material named 'steel' "
            "(materials: m)");
  j = minimalScene();
  j["lights"] = {"D56"};
  EXPECT_NE(errorOf(j).find("s.json: lights[0]: unknown spectrum 'D56'"), std::string::npos);
  j = minimalScene();
  j["model"] = "factor:0";
  EXPECT_NE(errorOf(j).find("s.json: model: colour model 'factor:0'"), std::string::npos);
  j = minimalScene();
  j["model"] = "factor:100";
  EXPECT_NE(errorOf(j).find("outside 3..16"), std::string::npos);
  j = minimalScene();
  j["light_mixes"] = {{"x", {{"A", 1.0}}}};
  EXPECT_EQ(errorOf(j), "s.json: light_mixes.x: no light named 'A'");
  j = minimalScene();
  j["materials"]["m"]["opacity"] = -1;
  EXPECT_EQ(errorOf(j), "s.json: materials.m.opacity: value -1 is outside 0..1000000");
  j = minimalScene();
  j["volume"] = {{"file", "missing.nhdr"}};
  EXPECT_NE(errorOf(j).find("missing.nhdr"), std::string::npos);
  j = minimalScene();
  j["transfer_function"] = {{"points", {{10, "m"}, {5, "m"}}}};
  EXPECT_EQ(errorOf(j), "s.json: transfer_function.points[1]: values must increase: 5 follows 10");
  j = minimalScene();
  j["render"] = {{"step", 0}};
  EXPECT_EQ(errorOf(j), "s.json: render.step: value 0 is outside 0.001..64");
}

TEST(SceneModel, AutoPicksTheSmallestKWithinTheTarget) {
  Scene s = test::phantomScene();
  s.auto_target = 2.0;
  const SceneModel chosen = makeSceneModel("auto", s, test::rendererObserver());
  EXPECT_EQ(chosen.model->kind(), ModelKind::kFactor);
  EXPECT_NE(chosen.description.find("the smallest k within 2"), std::string::npos)
      << chosen.description;
  // One k lower misses the target (or k is already the smallest).
  const int k = chosen.model->channels();
  if (k > 3) {
    const SceneModel lower = makeSceneModel(fmt::format("factor:{}", k - 1), s,
                                            test::rendererObserver());
    const auto pos = lower.description.find("mean ΔE2000 ");
    ASSERT_NE(pos, std::string::npos);
    EXPECT_GT(std::stod(lower.description.substr(pos + std::string("mean ΔE2000 ").size())), 2.0);
  }
  EXPECT_THROW(makeSceneModel("linear:4", s, test::rendererObserver()), Error);
}

TEST(Classification, TablesFollowTheTransferFunction) {
  auto j = minimalScene();
  j["materials"]["n"] = {{"reflectance", "ColorChecker/blue"}, {"opacity", 1.0}, {"specular", 0.5}};
  j["transfer_function"] = {{"points", {{0.0, "m"}, {1.0, "n"}}},
                            {"opacity", {{0.0, 0.0}, {0.5, 1.0}}}};
  const Scene s = parseScene(j, "s.json", test::rendererLibrary());
  const auto model = makeSpectralModel(test::rendererObserver(), 81);
  ClassificationOptions o;
  o.step_world = 0.5;
  o.bins = 3;  // values 0, 0.5, 1 (the sphere's range)
  const ClassifiedVolume cv = classify(s.volume, s.transfer_function, *model, o);
  ASSERT_EQ(cv.entries, 3);
  EXPECT_EQ(cv.t_channels, 1);
  EXPECT_FLOAT_EQ(cv.alpha[0], 0.0f);  // opacity factor 0 at value 0
  // At 0.5: half m (σ 0.5), half n (σ 1), opacity factor 1 → σ = 0.75.
  EXPECT_NEAR(cv.alpha[1], 1 - std::exp(-0.5 * 0.75), 1e-6);
  EXPECT_NEAR(cv.transmission[1], std::exp(-0.5 * 0.75), 1e-6);
  EXPECT_NEAR(cv.specular[1], 0.25, 1e-6);
  const double red = test::rendererLibrary().get("ColorChecker/red")[40];
  const double blue = test::rendererLibrary().get("ColorChecker/blue")[40];
  EXPECT_NEAR(cv.reflectance[1 * 81 + 40], 0.5 * red + 0.5 * blue, 1e-6);
  EXPECT_NEAR(cv.alpha[2], 1 - std::exp(-0.5 * 1.0), 1e-6);
}

TEST(Classification, XrayMaterialsScatterButDoNotOcclude) {
  auto j = minimalScene();
  j["materials"]["m"]["xray"] = true;
  const Scene s = parseScene(j, "s.json", test::rendererLibrary());
  const auto model = makeSpectralModel(test::rendererObserver(), 4);
  const ClassifiedVolume cv = classify(s.volume, s.transfer_function, *model, {});
  EXPECT_GT(cv.alpha.back(), 0.0f);
  EXPECT_FLOAT_EQ(cv.transmission.back(), 1.0f);
}

}  // namespace
}  // namespace svr
