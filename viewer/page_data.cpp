#include "viewer/page_data.h"

#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"

namespace svr {

nlohmann::json pageLight(const PageLightContext& context, const std::string& name,
                         const Spectrum& spectrum) {
  const ColourModel& model = context.model;
  PostIlluminator post(model);
  if (context.background) post.setBackground(model.project(*context.background));
  post.setLight(model.project(context.observer.unitLuminance(spectrum)));
  // The matrix depends on the image only through its plane counts.
  const LightIndependentImage shape(1, 1, model.imageChannels(), context.t_channels);
  const Eigen::MatrixXd m = post.foldedMatrix(shape, RelitSpace::kLinearSrgb);
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return {{"name", name}, {"matrix", rows}};
}

nlohmann::json pageSceneInfo(const PageLightContext& context, const Scene& scene,
                             const SceneModel& chosen, const std::string& renderer,
                             const OrbitView& view) {
  nlohmann::json lights = nlohmann::json::array();
  for (const auto& light : scene.lights) lights.push_back(pageLight(context, light.name, light.spectrum));
  nlohmann::json mixes = nlohmann::json::array();
  for (const auto& mix : scene.mixes) {
    std::vector<double> w(scene.lights.size(), 0.0);
    for (const auto& [index, weight] : mix.weights) w[index] += weight;
    mixes.push_back({{"name", mix.name}, {"weights", w}});
  }
  const ColourModel& model = *chosen.model;
  return {
      {"scene", scene.file},
      {"renderer", renderer},
      {"model", {{"name", model.name()},
                 {"k", model.channels()},
                 {"description", chosen.description},
                 {"choice", chosen.record()}}},
      {"channels", model.imageChannels()},
      {"t_channels", context.t_channels},
      {"width", scene.width},
      {"height", scene.height},
      {"view", {{"azimuth", view.azimuth}, {"elevation", view.elevation}, {"zoom", view.zoom}}},
      {"lights", lights},
      {"mixes", mixes},
      {"mixer_power", LightMixer{}.power},
  };
}

}  // namespace svr
