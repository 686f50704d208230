#include "base/data_dir.h"

#include <dlfcn.h>
#include <link.h>

#include <cstdlib>
#include <filesystem>

namespace svr {

namespace fs = std::filesystem;

namespace {

// The file that holds this function's code: libsvr.so when it is linked from one, else the
// executable. The object's own link map says which: the executable's name there is empty
// (dladdr's dli_fname would give argv[0] instead, which a bare `svr` from PATH resolves against
// the working folder), a shared library's is the path it was loaded from.
fs::path codeFile() {
  static const int anchor = 0;
  Dl_info info{};
  link_map* map = nullptr;
  if (::dladdr1(&anchor, &info, reinterpret_cast<void**>(&map), RTLD_DL_LINKMAP) != 0 && map &&
      map->l_name && *map->l_name) {
    std::error_code ec;
    const fs::path p = fs::canonical(map->l_name, ec);
    if (!ec) return p;
  }
  std::error_code ec;
  return fs::read_symlink("/proc/self/exe", ec);
}

}  // namespace

std::optional<std::string> installedShareDir() {
  static const std::optional<std::string> dir = []() -> std::optional<std::string> {
    const fs::path code = codeFile();
    if (code.empty()) return std::nullopt;
    // bin/svr or lib/<multiarch>/libsvr.so.N or lib/libsvr.so.N: look up to three levels up.
    fs::path up = code.parent_path();
    for (int level = 0; level < 3 && up.has_parent_path() && up != up.root_path(); ++level) {
      up = up.parent_path();
      const fs::path share = up / "share" / "svr";
      std::error_code ec;
      if (fs::is_directory(share / "spectra", ec)) return share.string();
    }
    return std::nullopt;
  }();
  return dir;
}

std::string defaultDataDir() {
  if (const auto share = installedShareDir()) return *share;
  if (const char* env = std::getenv("SVR_DATA_DIR"); env && *env) return env;
  return SVR_DEFAULT_DATA_DIR;
}

std::string scriptDir() {
  if (const auto share = installedShareDir()) return *share + "/scripts";
  return SVR_SOURCE_SCRIPT_DIR;
}

}  // namespace svr
