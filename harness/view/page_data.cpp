#include "harness/view/page_data.h"

#include <algorithm>
#include <cstdlib>

#include "spectral/light_mixer.h"
#include "spectral/post_illumination.h"

namespace svr {

nlohmann::json pageLight(const PageLightContext& context, const std::string& name,
                         const Spectrum& spectrum) {
  const ColourModel& model = context.model;
  PostIlluminator post(model);
  if (context.background) post.setBackground(model.project(*context.background));
  post.setLight(context.observer.unitLuminance(spectrum));
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

SampleChoice chooseSamples(const PageLightContext& context, const Scene& scene,
                           const LightIndependentImage& image) {
  const LightIndependentImage half = image.withStorage(SampleStorage::kHalf);
  const LightIndependentImage full = image.withStorage(SampleStorage::kFloat);
  PostIlluminator post(context.model);
  if (context.background) post.setBackground(context.model.project(*context.background));
  std::vector<std::uint8_t> a(3 * image.pixels()), b(3 * image.pixels());
  SampleChoice choice;
  for (const auto& light : scene.lights) {
    post.setLight(context.observer.unitLuminance(light.spectrum));
    post.relightSrgb8(full, a);
    post.relightSrgb8(half, b);
    for (size_t i = 0; i < a.size(); ++i)
      choice.half_code_error = std::max(choice.half_code_error, std::abs(int(a[i]) - int(b[i])));
  }
  choice.storage = choice.half_code_error <= 1 ? SampleStorage::kHalf : SampleStorage::kFloat;
  return choice;
}

nlohmann::json pageSceneInfo(const PageLightContext& context, const Scene& scene,
                             const SceneModel& chosen, const std::string& renderer,
                             const OrbitView& view, const SampleChoice& samples) {
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
      {"samples", samples.storage == SampleStorage::kHalf ? "half" : "float"},
      {"half_code_error", samples.half_code_error},
  };
}

}  // namespace svr
