#pragma once
// `svr demo`: the main job. Runs compare on the default scenes (engine, frog, phantom) with
// every registered backend, writes one report folder with a section per scene, prints the
// summary table and the path of report.html. `--quick` (CI) uses fewer models and smaller
// images.

#include <string>

namespace svr {

struct DemoOptions {
  std::string data_dir;
  std::string out_dir = "out/demo";
  bool quick = false;
  bool quiet = false;
};

int runDemo(const DemoOptions& options);

}  // namespace svr
