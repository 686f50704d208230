#include "spectral/data_dir.h"

#include <cstdlib>

namespace svr {

std::string defaultDataDir() {
  if (const char* env = std::getenv("SVR_DATA_DIR"); env && *env) return env;
  return SVR_DEFAULT_DATA_DIR;
}

}  // namespace svr
