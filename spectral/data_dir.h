#pragma once
// Where the shipped tables live: $SVR_DATA_DIR if set, else the source tree's data/ (baked in
// at configure time so a fresh build runs from anywhere).

#include <string>

namespace svr {

std::string defaultDataDir();

}  // namespace svr
