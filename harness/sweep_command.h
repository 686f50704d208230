#pragma once
// `svr sweep SCENE --param NAME=FROM:TO:STEP`: test stability where methods fail (design.md §6).
// At every value the reference and each renderer render again; the ΔE2000 curve against the
// reference and the time are written to sweep.json with flags for jumps, NaN/Inf and blow-ups,
// and drawn as sweep_<param>.png. Parameters: azimuth, elevation (degrees), zoom, step (voxels),
// k (factor model size), depth (scale of every material's opacity, i.e. absorption depth), or
// BACKEND.KEY for a backend option (e.g. splat.radius).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace svr {

struct SweepOptions {
  std::string data_dir;
  std::string scene;
  std::string param;  // NAME=FROM:TO:STEP
  std::vector<std::string> renderers;  // empty = every registered backend
  std::string model = "factor:6";
  std::string out_dir;
  int width = 96, height = 96;
  bool charts = true;
  bool quiet = false;
};

struct SweepCurve {
  std::string renderer;
  std::vector<double> de_mean, ms;  // NaN where the run failed
  std::vector<std::string> errors;  // per value: why its run failed; empty where it worked
  std::vector<std::string> flags;   // "jump at 45", "non-finite at 12", "blow-up at 3",
                                    // "failed at 2: …"
};

struct SweepResult {
  std::string param;
  std::vector<double> values;
  std::vector<SweepCurve> curves;
};

SweepResult runSweepStudy(const SweepOptions& options);  // also writes sweep.json (+ chart)
// The command: a line per curve and flag; 0, or 2 when a run failed (the others are reported).
int runSweep(const SweepOptions& options);

}  // namespace svr
