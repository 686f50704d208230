#pragma once
// An MPI call's error code as an svr::Error naming the call and MPI's own words for it, so that
// the ranks' agreement (MpiDistribution::agree) can report it like any other failure.

#include <fmt/format.h>
#include <mpi.h>

#include <string>

#include "base/error.h"

namespace svr {

inline void checkMpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(fmt::format("MPI: {} failed: {}", what, std::string(text, length)));
}

}  // namespace svr
