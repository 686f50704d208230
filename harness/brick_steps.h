#pragma once
// What a distributed render adds to the steps of a frame (design.md §5b), for RenderSession:
// every step a phase the processes agree on, the kd-split decided before any brick is read,
// auto's model agreed across bricks, and each process's facts for render.json.

#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "harness/render_distribution.h"
#include "renderers/model/scene_model.h"
#include "renderers/volume/volume_io.h"

namespace svr {

struct SessionSpectra;
struct FrameSettings;

// Runs one step. In a distributed render every process then agrees on failures
// (RenderDistribution::agree), so a process that failed never leaves the others waiting in a
// collective. Without one it is the step alone.
template <class Body>
void phase(RenderDistribution* distribution, Body&& body) {
  if (!distribution) return body();
  std::exception_ptr failure;
  try {
    body();
  } catch (...) {
    failure = std::current_exception();
  }
  distribution->agree(failure);
}

// The bricks, decided before any is read: equal time rather than equal voxels where the
// backend allows (balance "work"), estimated on a coarse lattice of the volume. Only an
// optimisation: if the estimate fails, the bricks share voxels and the load that follows
// reports what is wrong with the scene or its volume. Sets volume_options.brick; returns the
// estimate's failure, or "".
std::string splitIntoBricks(const SessionSpectra& spectra, const std::string& scene_file,
                            const FrameSettings& settings, VolumeLoadOptions& volume_options);

// Each brick's auto probe saw its own part of the volume: all take the most channels any asked
// for (a factor:k, or spectral:n past factor:16), so that every brick renders one model.
// Collective.
SceneModel agreeOnAutoModel(RenderDistribution& distribution, SceneModel chosen,
                            const Scene& scene, const Observer& observer);

// This process's facts: its brick, its times, its peak memory.
struct BrickFacts {
  double render_ms = 0, render_cpu_ms = 0, composite_ms = 0, front_wait_ms = 0;
  nlohmann::json json(const Volume& volume) const;
};

// CPU time of this process's threads, in ms: the work a rank did, unlike its wall time not
// stretched by waiting or by sharing a core.
double processCpuMs();

}  // namespace svr
