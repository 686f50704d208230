#include "tests/renderers/test_scenes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace svr::test {

const std::string& rendererDataDir() {
  static const std::string dir = SVR_TEST_DATA_DIR;
  return dir;
}

const SpectrumLibrary& rendererLibrary() {
  static const SpectrumLibrary lib =
      SpectrumLibrary::load(rendererDataDir(), WavelengthGrid::standard());
  return lib;
}

const Observer& rendererObserver() {
  static const Observer obs = Observer::cie1931(rendererDataDir(), WavelengthGrid::standard());
  return obs;
}

Scene slabScene(double sigma, const std::string& absorption, double step_voxels) {
  nlohmann::json material = {{"reflectance", "ColorChecker/white 9.5 (.05 D)"}, {"opacity", sigma}};
  if (!absorption.empty()) material["absorption"] = absorption;
  const nlohmann::json j = {
      {"volume", {{"procedural", "slab"}, {"size", 48}, {"thickness", 0.25}}},
      {"materials", {{"slab", material}}},
      // Extinction linear in the value: the trilinear field's line integral is then exact.
      {"transfer_function", {{"points", {{0, "slab"}}}, {"opacity", {{0, 0}, {1, 1}}}}},
      {"lights", {"D65", "A"}},
      {"camera", {{"azimuth", 0}, {"elevation", 90}, {"zoom", 2}}},
      {"image", {{"width", 32}, {"height", 32}}},
      {"render", {{"step", step_voxels}, {"early_termination", 0}, {"bins", 4096}}},
  };
  return parseScene(j, rendererDataDir() + "/scenes/slab.json", rendererLibrary());
}

double slabVoxels(const Scene& scene) {
  const auto& d = scene.volume.dims();
  double n = 0;
  for (int z = 0; z < d[2]; ++z) n += scene.volume.value(d[0] / 2, d[1] / 2, z);
  return n;
}

Scene phantomScene() {
  Scene s = loadScene(rendererDataDir() + "/scenes/phantom.json", rendererLibrary());
  s.width = s.height = 48;
  s.light_direction = glm::dvec3(0.0, -0.6, 0.8);
  return s;
}

LightIndependentImage render(const Renderer& renderer, const Scene& scene,
                             const ClassifiedVolume& classified,
                             const std::optional<nlohmann::json>& options) {
  RenderRequest request = sceneRequest(scene, classified);
  if (options) request.options = *options;
  return renderer.render(request);
}

LightIndependentImage render(const Renderer& renderer, const Scene& scene,
                             const ColourModel& model,
                             const std::optional<nlohmann::json>& options) {
  return render(renderer, scene, classifyScene(scene, model), options);
}

void expectSameClassification(const ClassifiedVolume& a, const ClassifiedVolume& b) {
  EXPECT_EQ(a.k, b.k);
  EXPECT_EQ(a.t_channels, b.t_channels);
  EXPECT_EQ(a.entries, b.entries);
  EXPECT_EQ(a.alpha, b.alpha);
  EXPECT_EQ(a.reflectance, b.reflectance);
  EXPECT_EQ(a.specular, b.specular);
  EXPECT_EQ(a.transmission, b.transmission);
  EXPECT_EQ(a.white, b.white);
  EXPECT_EQ(a.values, b.values);
  EXPECT_EQ(a.label, b.label);
  EXPECT_EQ(a.shading_field, b.shading_field);
  EXPECT_EQ(a.block_occupied, b.block_occupied);
}

}  // namespace svr::test
