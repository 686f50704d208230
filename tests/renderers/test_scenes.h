#pragma once
// Scene builders shared by the renderer tests and benches (OSPRay-style): small analytic scenes
// with known answers.

#include <string>

#include <optional>

#include "renderers/classification/classification.h"
#include "renderers/render/renderer.h"
#include "renderers/scene/scene.h"
#include "renderers/render/scene_render.h"
#include "spectral/colorimetry.h"
#include "spectral/spectrum_library.h"

namespace svr::test {

const std::string& rendererDataDir();
const SpectrumLibrary& rendererLibrary();
const Observer& rendererObserver();

// A homogeneous slab of `voxels` ones (along z, centred) in a 48³ grid, one material of
// extinction sigma (absorbing like `absorption`, or achromatic when empty), seen from +z,
// orthographic, 32×32 pixels, early termination off.
Scene slabScene(double sigma, const std::string& absorption, double step_voxels);

// Voxels of the slab's centre column: the line integral of the trilinear field through it.
double slabVoxels(const Scene& scene);

// The procedural phantom with four materials (one spectral absorber, one x-ray), 48×48 pixels.
Scene phantomScene();

// Renders the scene's classified volume through sceneRequest; `options`, when given, replace
// the scene's render.options.
LightIndependentImage render(const Renderer& renderer, const Scene& scene,
                             const ClassifiedVolume& classified,
                             const std::optional<nlohmann::json>& options = std::nullopt);
// The same after classifyScene with this model.
LightIndependentImage render(const Renderer& renderer, const Scene& scene,
                             const ColourModel& model,
                             const std::optional<nlohmann::json>& options = std::nullopt);

// Two classifications hold the same channels, tables and volume part, value for value.
void expectSameClassification(const ClassifiedVolume& a, const ClassifiedVolume& b);

}  // namespace svr::test
