#pragma once
// What `svr render` writes into its folder, given a rendered light-independent image: the EXR
// and its model, one sRGB PNG per scene light and mix, view.html when asked, and render.json
// with the settings and timings. svr render, svr-mpi and the Python module's Image.save share it.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/render_command.h"
#include "renderers/render/renderer.h"
#include "renderers/scene/scene.h"
#include "renderers/model/scene_model.h"
#include "spectral/colorimetry.h"
#include "spectral/light_independent_image.h"

namespace svr {

// render: the classification's first frame, which builds what the backend keeps per
// classification (encodings, gradients, uploads); steady: the same view again (--steady).
struct Timings {
  double load = 0, classify = 0, render = 0, relight = 0;
  std::optional<double> steady;
};

// Relights the image under every scene light and mix and writes the folder (o.out_dir; o.scene,
// o.half, o.html and o.quiet are read too). `distributed`: one entry per process of a
// distributed render, or null.
void writeRenderOutputs(const RenderOptions& o, const Scene& scene, const Renderer& renderer,
                        const SceneModel& chosen, const Observer& observer,
                        const LightIndependentImage& image, Timings t,
                        const std::vector<std::string>& notes,
                        const nlohmann::json& distributed = nullptr);

}  // namespace svr
