#pragma once
// `svr render SCENE --out DIR`: load, classify, render once, relight under every scene light and
// light mix. Writes the light-independent EXR and its model JSON, one sRGB PNG per light and
// mix, and render.json with the settings and timings.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace svr {

class RenderDistribution;

struct RenderOptions {
  std::string data_dir;
  std::string scene;
  std::string renderer = "raycast";
  std::string model;  // overrides the scene's
  std::string out_dir;
  std::optional<int> width, height;
  bool half = false;  // store the EXR as half floats
  bool html = false;  // also write view.html (harness/view/standalone_page.h)
  std::vector<std::string> options;  // "backend.key=value", over the scene's render.options
  std::optional<std::uint64_t> memory_budget;
  bool quiet = false;
  bool steady = false;  // render the view again and report that frame's time too
  // A distributed render (svr-mpi): this process's part in it; null for svr render.
  RenderDistribution* distribution = nullptr;
  // How its kd-split shares the volume out: "work" (estimated, render/work_estimate.h, for
  // backends that pass the transmittance in front on) or "voxels".
  std::string balance = "work";
};

int runRender(const RenderOptions& options);

}  // namespace svr
