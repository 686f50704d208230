#include "renderers/render/scene_render.h"

namespace svr {

ClassificationOptions classificationOptions(const Scene& scene) {
  ClassificationOptions options;
  options.step_world = scene.stepWorld();
  options.bins = scene.bins;
  return options;
}

ClassifiedVolume classifyScene(const Scene& scene, const ColourModel& model) {
  return classify(scene.volume, scene.transfer_function, model, classificationOptions(scene));
}

RenderRequest sceneRequest(const Scene& scene, const ClassifiedVolume& classified) {
  return RenderRequest{.volume = classified,
                       .camera = scene.camera,
                       .width = scene.width,
                       .height = scene.height,
                       .shading = scene.shading,
                       .light_direction = scene.light_direction,
                       .termination = scene.termination,
                       .empty_space_skipping = true,
                       .options = scene.renderer_options,
                       .options_source = scene.file + ": render.options",
                       .memory_budget = defaultMemoryBudget(),
                       .note = nullptr};
}

std::vector<Spectrum> sceneIlluminations(const Scene& scene, const Observer& observer) {
  std::vector<Spectrum> out;
  for (const auto& l : scene.lights) out.push_back(observer.unitLuminance(l.spectrum));
  for (const auto& mix : scene.mixes) {
    Spectrum s = Spectrum::constant(observer.grid(), 0.0);
    for (const auto& [index, w] : mix.weights) s = s + out[index] * w;
    out.push_back(s);
  }
  return out;
}

std::vector<std::string> sceneIlluminationNames(const Scene& scene) {
  std::vector<std::string> names;
  for (const auto& l : scene.lights) names.push_back(l.name);
  for (const auto& mix : scene.mixes) names.push_back(mix.name);
  return names;
}

}  // namespace svr
