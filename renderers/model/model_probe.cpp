#include "renderers/model/model_probe.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "renderers/registry.h"
#include "renderers/render/scene_render.h"
#include "spectral/componentwise_model.h"
#include "spectral/image_difference.h"

namespace svr {

Scene ModelProbe::sized(Scene scene, int longer_side) {
  const double scale = std::min(1.0, double(longer_side) / std::max(scene.width, scene.height));
  scene.width = std::max(1, static_cast<int>(std::lround(scene.width * scale)));
  scene.height = std::max(1, static_cast<int>(std::lround(scene.height * scale)));
  return scene;
}

ModelProbe::ModelProbe(const Scene& scene, const Observer& observer, int longer_side)
    : scene_(sized(scene, longer_side)), observer_(observer) {
  lights_ = sceneIlluminations(scene, observer);
  reference_model_ = makeSpectralModel(observer, observer.grid().count);
  classified_ = classifyScene(scene_, *reference_model_);
  reference_ = render(*reference_model_);
}

double ModelProbe::error(const ColourModel& model) const {
  const std::vector<double> each = errors(model);
  return *std::max_element(each.begin(), each.end());
}

double ModelProbe::meanError(const ColourModel& model) const {
  const std::vector<double> each = errors(model);
  return std::accumulate(each.begin(), each.end(), 0.0) / double(each.size());
}

std::vector<double> ModelProbe::errors(const ColourModel& model) const {
  const LightIndependentImage image = render(model);
  std::vector<double> each;
  for (const auto& light : lights_) {
    const ImageDifference d = compareRelit(image, model, reference_, *reference_model_, light,
                                           observer_.xyz(light), 0.98, scene_.background);
    each.push_back(d.stats.finite ? d.stats.mean : INFINITY);
  }
  return each;
}

std::string ModelProbe::size() const { return fmt::format("{}×{}", scene_.width, scene_.height); }

LightIndependentImage ModelProbe::render(const ColourModel& model) const {
  setModel(classified_, scene_.transfer_function, model, classificationOptions(scene_));
  // The harness's reference backend, as the registry names it.
  return makeRenderer(referenceRendererName())->render(sceneRequest(scene_, classified_), nullptr);
}

}  // namespace svr
