#pragma once
// What this build of svr is: its version and the options it was built with (`svr --version`).

#include <string>

namespace svr {

// Several lines: version, build type and compiler, the gl backend's platforms, svr view,
// svr-mpi, the Python module, the relight kernel this CPU runs, and the data folder.
std::string buildDescription(const std::string& data_dir);

}  // namespace svr
