#include "harness/demo_command.h"

#include <CLI/CLI.hpp>
#include <memory>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "harness/command.h"
#include "harness/compare_command.h"
#include "renderers/registry.h"
#include "base/atomic_file.h"
#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

int runDemo(const DemoOptions& o) {
  const std::vector<std::string> scenes{"engine", "frog", "phantom"};
  nlohmann::json demo = {{"scenes", scenes}, {"quick", o.quick}};
  std::vector<CompareSummary> summaries;
  for (const auto& name : scenes) {
    CompareOptions c;
    c.data_dir = o.data_dir;
    c.scene = (fs::path(o.data_dir) / "scenes" / (name + ".json")).string();
    c.out_dir = (fs::path(o.out_dir) / name).string();
    c.models = o.quick ? std::vector<std::string>{"rgb", "factor:6"}
                       : std::vector<std::string>{"rgb", "factor:4", "factor:6",
                                                  "factor:6/projected", "factor:8",
                                                  "spectral:31"};
    c.width = c.height = o.quick ? 128 : 256;
    // gl ray casts by default; its splats run beside it, so the report shows both.
    const std::vector<std::string> built = rendererNames();
    // shear-warp post-classifies by default; its pre-classified mode (VolPack's) runs beside it.
    c.variants = {"shearwarp.classification=pre"};
    if (std::ranges::find(built, "gl") != built.end()) c.variants.push_back("gl.mode=splat");
    c.charts = false;  // one combined page below
    c.quiet = o.quiet;
    summaries.push_back(runComparison(c));
  }
  writeTextAtomically((fs::path(o.out_dir) / "demo.json").string(), demo.dump(1) + "\n");
  renderReportCharts(o.out_dir);
  int status = 0;  // the worst scene's: 1 on a tolerance miss, 2 when a run failed
  for (const auto& s : summaries) {
    printSummaryTable(s);
    fmt::print("\n");
    printSummaryNotes(s);
    status = std::max(status, compareExitStatus(s));
  }
  fmt::print("report: {}\n", (fs::path(o.out_dir) / "report.html").string());
  return status;
}

namespace commands {

CommandEntry demo() {
  return {"demo", "compare every backend and model on the default scenes; writes report.html",
          [](CLI::App& sub, CommandContext& context) {
            auto o = std::make_shared<DemoOptions>();
            sub.add_option("--out", o->out_dir, "report folder")->capture_default_str();
            sub.add_flag("--quick", o->quick, "fewer models, smaller images (for CI)");
            sub.add_flag("-q,--quiet", o->quiet, "no progress bars");
            addCacheFlag(sub);
            runOnParse(sub, context, o, &runDemo);
          }};
}

}  // namespace commands

}  // namespace svr
