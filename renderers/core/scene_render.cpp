#include "renderers/core/scene_render.h"

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

}  // namespace svr
