#include "harness/build_info.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

#include "spectral/relight_kernel.h"
#include "svr_build_info.h"

namespace svr {

std::string buildDescription(const std::string& data_dir) {
  std::vector<std::string> isas;
  for (const KernelIsa isa : availableKernelIsas()) isas.push_back(toString(isa));
  return fmt::format(
      "svr {} ({} build, {})\n"
      "gl backend: OSMesa {}, EGL {}\n"
      "svr view: {}\n"
      "svr-mpi: {}\n"
      "Python module: {}\n"
      "relight kernel: {} on this CPU (runnable here: {})\n"
      "data: {}",
      SVR_BUILD_VERSION, SVR_BUILD_TYPE, SVR_BUILD_COMPILER, SVR_BUILD_OSMESA, SVR_BUILD_EGL,
      SVR_BUILD_VIEWER, SVR_BUILD_MPI, SVR_BUILD_PYTHON, isas.back(), fmt::join(isas, ", "),
      data_dir);
}

}  // namespace svr
