#include "harness/brick_steps.h"

#include <fmt/format.h>
#include <sys/resource.h>

#include <ctime>
#include <optional>

#include "harness/render_session.h"
#include "renderers/registry.h"
#include "renderers/render/scene_render.h"
#include "renderers/render/work_estimate.h"

namespace svr {
namespace {

// The render's work over a coarse lattice of the volume, for backends whose bricks pass the
// transmittance in front on; the others' bricks each work as if alone, and voxels share that
// out best (nullopt).
std::optional<WorkGrid> estimateRenderWork(const SessionSpectra& spectra,
                                           const std::string& scene_file,
                                           const FrameSettings& settings,
                                           const VolumeLoadOptions& volume_options) {
  if (!backendEntry(settings.renderer).info.supports.front_transmittance) return std::nullopt;
  VolumeLoadOptions coarse = volume_options;
  coarse.brick = nullptr;
  coarse.lattice = Dims{kWorkLatticeSamples, kWorkLatticeSamples, kWorkLatticeSamples};
  const Scene scene = loadScene(scene_file, spectra.library, coarse);
  const SceneModel model = makeSceneModel("rgb", scene, spectra.observer);
  return estimateWork(classifyScene(scene, *model.model), scene.camera,
                      settings.width.value_or(scene.width), settings.height.value_or(scene.height),
                      scene.termination);
}

nlohmann::json boxJson(const VoxelBox& box) {
  return {{"lo", box.lo}, {"hi", box.hi}};
}

// Peak resident memory of this process so far.
std::uint64_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;
}

}  // namespace

std::string splitIntoBricks(const SessionSpectra& spectra, const std::string& scene_file,
                            const FrameSettings& settings, VolumeLoadOptions& volume_options) {
  RenderDistribution* const dist = settings.distribution;
  std::string failure;
  std::optional<WorkGrid> work;
  if (dist->writes() && dist->processes() > 1 && settings.balance == "work") try {
      work = estimateRenderWork(spectra, scene_file, settings, volume_options);
    } catch (const std::exception& e) {
      failure = e.what();
    }
  dist->balance(work ? &*work : nullptr);
  volume_options.brick = [dist](const Dims& whole) { return dist->brick(whole); };
  return failure;
}

SceneModel agreeOnAutoModel(RenderDistribution& dist, SceneModel chosen, const Scene& scene,
                            const Observer& observer) {
  const int k = chosen.model->channels();
  const int agreed = static_cast<int>(dist.wholeRange({k, k}).second);
  if (agreed == k) return chosen;
  std::optional<SceneModel> wider;
  phase(&dist, [&] {
    wider = makeSceneModel(
        agreed > 16 ? fmt::format("spectral:{}", agreed) : fmt::format("factor:{}", agreed),
        scene, observer);
    wider->description = fmt::format("auto: {} — the most channels any brick's probe asked "
                                     "for (this brick's: {})",
                                     wider->description, chosen.model->name());
    wider->asked = "auto";
    wider->target = scene.auto_target;
  });
  return std::move(*wider);
}

nlohmann::json BrickFacts::json(const Volume& volume) const {
  const VolumeBrick& brick = *volume.brick();
  return {{"own", boxJson(brick.own)},
          {"stored", boxJson(brick.stored)},
          {"volume_bytes", volume.bytes()},
          {"render_ms", render_ms},
          {"composite_ms", composite_ms},
          {"render_cpu_ms", render_cpu_ms},
          {"front_wait_ms", front_wait_ms},
          {"peak_resident_bytes", peakResidentBytes()}};
}

double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

}  // namespace svr
