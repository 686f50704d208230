#include "harness/reference_step.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "renderers/model/scene_model.h"
#include "renderers/render/scene_render.h"
#include "renderers/registry.h"
#include "base/elapsed.h"
#include "spectral/componentwise_model.h"
#include "spectral/image_difference.h"

namespace svr {

nlohmann::json ReferenceStep::toJson() const {
  return {{"step_voxels", step_voxels},
          {"halving_de2000", halving_de2000},
          {"converged", converged},
          {"target_de2000", target},
          {"finest_step_voxels", finest_voxels},
          {"probe", probe_size},
          {"probe_ms", probe_ms}};
}

ReferenceStep convergedReferenceStep(const Scene& scene, const Observer& observer,
                                     double start_voxels, double target, double finest_voxels) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene probe = ModelProbe::sized(scene);
  probe.termination = 0.0;
  const std::unique_ptr<ColourModel> exact = makeSpectralModel(observer, observer.grid().count);
  const std::unique_ptr<Renderer> renderer = makeRenderer(referenceRendererName());
  const auto render = [&](double step) {
    probe.step_voxels = step;
    return renderer->render(sceneRequest(probe, classifyScene(probe, *exact)), nullptr);
  };
  const std::vector<Spectrum> lights = sceneIlluminations(scene, observer);
  const auto difference = [&](const LightIndependentImage& a, const LightIndependentImage& b) {
    double worst = 0.0;
    for (const Spectrum& light : lights) {
      const ErrorStats d = compareRelit(a, *exact, b, *exact, light, observer.xyz(light), 0.98,
                                        scene.background)
                               .stats;
      worst = std::max(worst, d.finite ? d.mean : INFINITY);
    }
    return worst;
  };

  ReferenceStep out;
  out.target = target;
  out.finest_voxels = finest_voxels;
  out.probe_size = fmt::format("{}×{}", probe.width, probe.height);
  // Never coarser than the start: a scene already finer than finest_voxels keeps its step.
  out.step_voxels = start_voxels;
  LightIndependentImage coarse = render(out.step_voxels);
  for (;;) {
    const double half = out.step_voxels / 2;
    LightIndependentImage fine = render(half);
    out.halving_de2000 = difference(coarse, fine);
    out.converged = out.halving_de2000 <= target;
    if (out.converged || half < finest_voxels) break;
    out.step_voxels = half;
    coarse = std::move(fine);
  }
  out.probe_ms = msSince(t0);
  return out;
}

}  // namespace svr
