#pragma once
// Where svr's shipped files live (issue 50). An installed svr (`cmake --install`) keeps them in
// <prefix>/share/svr/: spectra/, scenes/, palettes/, volumes/, and scripts/ (the chart scripts
// the harness runs). The prefix is the folder above the one holding the code that asks — the
// svr binary, or libsvr.so for a program linked to it — so a prefix may be moved as a whole.
//
// The data folder is the first of: <prefix>/share/svr, when it holds spectra/; $SVR_DATA_DIR;
// the source tree's data/ (baked in at configure time, so that a build runs from anywhere).
// The installed data comes first so that an installed svr never reads another version's tables
// through a variable left set for a build tree; `svr --data DIR` overrides all three.

#include <optional>
#include <string>

namespace svr {

std::string defaultDataDir();
// The folder of the harness's Python scripts (report.py, plot_spectra.py): <prefix>/share/svr/
// scripts when installed, else the source tree's harness/.
std::string scriptDir();
// <prefix>/share/svr, when this code runs from an installed prefix that has it.
std::optional<std::string> installedShareDir();

}  // namespace svr
