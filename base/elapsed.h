#pragma once
// Milliseconds since a steady-clock time point: the one way commands, the harness, the library's
// session and the benches time their stages.

#include <chrono>

namespace svr {

inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace svr
