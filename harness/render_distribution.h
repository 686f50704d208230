#pragma once
// What a distributed render changes in `svr render` (design.md §5b): each process reads, classifies
// and renders one brick, the processes agree on the whole volume's ranges and on failures, and
// one of them composites and writes. harness/mpi/ implements it over MPI for svr-mpi; `svr
// render` runs without one. The rest of the command — scene, model, relighting, the files it
// writes — is the same code either way.

#include <exception>
#include <memory>
#include <nlohmann/json.hpp>
#include <utility>

#include "renderers/volume/brick_box.h"
#include "renderers/scene/camera.h"
#include "renderers/render/front_transmittance.h"
#include "spectral/light_independent_image.h"

namespace svr {

class RenderDistribution {
 public:
  virtual ~RenderDistribution() = default;

  // Collective, before brick(): the writer's estimate of where the render's work lies (null:
  // none), which brick() then shares out instead of voxels.
  virtual void balance(const WorkGrid* on_writer) = 0;
  // The brick of a volume of these dims that this process reads.
  virtual VolumeBrick brick(const Dims& whole) = 0;
  // Collectives: every process's range of its own voxels → the whole volume's.
  virtual std::pair<double, double> wholeRange(std::pair<double, double> local) = 0;
  virtual FieldRange wholeField(const FieldRange& local) = 0;
  // For one frame of a backend that takes it (BackendCapabilities::front_transmittance): the
  // transmittance of the bricks in front of this process's, block by block; null when nothing
  // can lie in front (one process). Collective.
  virtual std::unique_ptr<FrontTransmittance> frontTransmittance(const Camera& camera, int width,
                                                                 int height, int t_channels,
                                                                 const glm::dvec3& spacing) = 0;
  // The bricks' images composited front to back for the camera: the whole image on the writer,
  // an empty image elsewhere. `spacing` places the kd planes in world space.
  virtual LightIndependentImage composite(const LightIndependentImage& local,
                                          const Camera& camera, const glm::dvec3& spacing) = 0;
  // Every process's facts (its brick, times, memory) as one array, on the writer.
  virtual nlohmann::json gather(const nlohmann::json& local) = 0;
  // How many processes share the render.
  virtual int processes() const = 0;
  // Whether this process writes the outputs and shows progress.
  virtual bool writes() const = 0;
  // Every process calls this at the end of each phase with that phase's failure (null: none).
  // When any process failed, it throws on every process an svr::Error with the message of the
  // first process that failed, naming it; otherwise it returns.
  virtual void agree(const std::exception_ptr& failure) = 0;
};

}  // namespace svr
