#pragma once
// One way to turn a Scene into a render, used by the harness, the tests and the benches alike:
// the classification options the scene asks for, and the request that renders its classified
// volume with the scene's camera, size, shading, light direction, termination and options.
// Callers change what they vary on the returned values (a bench its image size, the reference
// its termination) instead of writing the request out again.

#include "renderers/classification/classification.h"
#include "renderers/render/renderer.h"
#include "renderers/scene/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/colour_model.h"

namespace svr {

ClassificationOptions classificationOptions(const Scene& scene);
ClassifiedVolume classifyScene(const Scene& scene, const ColourModel& model);

// The request for this scene (options_source names the scene file's render.options).
RenderRequest sceneRequest(const Scene& scene, const ClassifiedVolume& classified);

// What the scene is relit under: each light at unit luminance, then each mix as the weighted
// sum of those (light matrices are linear in the light), in scene.lights then scene.mixes order.
std::vector<Spectrum> sceneIlluminations(const Scene& scene, const Observer& observer);
// Their names, in the same order: the lights', then the mixes'.
std::vector<std::string> sceneIlluminationNames(const Scene& scene);

}  // namespace svr
