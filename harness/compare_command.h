#pragma once
// `svr compare SCENE`: the reference and every backend × model on one scene; writes the report
// folder (report.json, relit PNGs, ΔE2000 maps, speed_accuracy.png, report.html) and exits
// non-zero when a tolerance is exceeded, naming the run, light, metric, value and tolerance, or
// when a run failed; the runs that worked are reported either way.

#include <string>
#include <vector>

#include "harness/comparison.h"

namespace svr {

struct CompareOptions {
  std::string data_dir;
  std::string scene;
  std::vector<std::string> renderers;  // empty = every registered backend
  std::vector<std::string> models;     // empty = rgb, factor:3, factor:4, factor:6, factor:8, spectral:31
  std::vector<std::string> variants;   // extra runs "BACKEND.KEY=VALUE" (e.g. splat.mode=direct)
  std::string out_dir;
  int width = 0, height = 0;           // 0 = the scene's
  bool charts = true;                  // run harness/report.py (matplotlib) for the PNG charts and HTML
  bool quiet = false;
};

struct CompareSummary {
  std::string scene;
  std::vector<RunResult> runs;
  std::vector<Exceedance> exceedances;
  std::vector<std::string> skipped;  // "shearwarp skipped: … orthographic cameras only …"
  std::vector<FailedRun> failed;     // runs that ended in an error, with it
  double reference_ms = 0.0;
  ReferenceStep reference_step;
  nlohmann::json report;  // what report.json holds
};

// Runs every comparison and writes report.json and the images into out_dir (charts and HTML
// too when options.charts). Throws svr::Error for bad input (an unknown backend or model name,
// an unreadable scene) and when the reference fails; tolerance misses and failed runs are
// returned.
CompareSummary runComparison(const CompareOptions& options);
// The same for a scene already loaded (the Python module's); options.scene names it.
CompareSummary runComparison(Scene scene, const CompareOptions& options);
// The command: runComparison, a table on stdout, one line per exceedance and per failed run, and
// compareExitStatus.
int runCompare(const CompareOptions& options);
// 0; 1 when a tolerance was missed; 2 when a run failed (as for any other error).
int compareExitStatus(const CompareSummary& summary);
// Prints the summary table (backend × model: ms/frame, relight fps, mean ΔE2000, pass; failed
// runs with their error).
void printSummaryTable(const CompareSummary& summary);
// The skipped runs, tolerance misses and failed runs on stderr, one line each.
void printSummaryNotes(const CompareSummary& summary);

// Runs harness/report.py on a report folder (charts, heat maps, report.html).
void renderReportCharts(const std::string& out_dir);

}  // namespace svr
