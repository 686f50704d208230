#include "bench/backends/backend_agreement.h"

#include <cmath>

#include "harness/comparison.h"
#include "renderers/registry.h"
#include "spectral/image_difference.h"

namespace svr {

BackendFrame renderBackendFrame(const std::shared_ptr<const SessionSpectra>& spectra,
                                const Scene& scene, const std::string& renderer,
                                const std::string& model,
                                const std::vector<std::string>& options) {
  FrameSettings settings;
  settings.renderer = renderer;
  settings.model = model;
  settings.options = options;
  RenderSession session(spectra, scene, settings, "view corpus");
  session.render();                    // the first frame builds what the backend keeps
  const double ms = session.render();  // a steady frame
  std::vector<Spectrum> lights;
  for (const auto& name : session.lightNames()) lights.push_back(session.light(name));
  return {session.takeModel(), session.takeImage(), ms, std::move(lights)};
}

Agreement agreementWithRaycast(const std::shared_ptr<const SessionSpectra>& spectra,
                               const Scene& scene, const BackendFrame& raycast,
                               const std::string& renderer, const std::string& model,
                               const std::vector<std::string>& options) {
  Agreement out;
  if (const auto why = unsupportedBy(backendEntry(renderer).info, scene.camera, 1, 1)) {
    out.status = Agreement::Status::kSkipped;
    out.note = *why;
    return out;
  }
  try {
    const BackendFrame frame = renderBackendFrame(spectra, scene, renderer, model, options);
    double mean_limit = INFINITY, p95_limit = INFINITY;
    nlohmann::json run_options = nlohmann::json::object();
    for (const auto& o : options) applyOptionAssignment(run_options, o, "--option");
    const RunSpec spec{renderer, model, run_options};
    for (const auto& t : tolerancesFor(renderer, scene.tolerances,
                                       runBackendOptions(spec, scene.renderer_options))) {
      if (t.metric == "de_vs_raycast_mean") mean_limit = t.limit;
      if (t.metric == "de_vs_raycast_p95") p95_limit = t.limit;
    }
    out.vs_raycast = out.vs_raycast_p95 = 0.0;
    out.within_tolerance = true;
    const auto& lights = raycast.lights;
    for (const auto& light : lights) {
      const ErrorStats e =
          compareRelit(frame.image, *frame.model.model, raycast.image, *raycast.model.model, light,
                       spectra->observer.xyz(light), 0.98, scene.background)
              .stats;
      out.vs_raycast += e.mean / double(lights.size());
      out.vs_raycast_p95 += e.p95 / double(lights.size());
      out.within_tolerance = out.within_tolerance && e.mean <= mean_limit && e.p95 <= p95_limit;
    }
    out.ms = frame.ms;
  } catch (const Cancelled&) {
    throw;
  } catch (const std::exception& e) {
    out.status = Agreement::Status::kFailed;
    out.note = e.what();
  }
  return out;
}

}  // namespace svr
