#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "harness/command.h"
#include "base/disk_cache.h"
#include "base/error.h"

// The list of commands, in the order `svr --help` shows them. Each NAME is defined by
// harness/NAME_command.cpp as svr::commands::NAME().
#define SVR_COMMANDS(X) \
  X(render)             \
  X(relight)            \
  X(view)               \
  X(compare)            \
  X(sweep)              \
  X(demo)               \
  X(design)             \
  X(model_error)        \
  X(info)               \
  X(import_tf)          \
  /* one line per entry, each ending in a backslash */

namespace svr {
namespace commands {
#define SVR_DECLARE(NAME) CommandEntry NAME();
SVR_COMMANDS(SVR_DECLARE)
#undef SVR_DECLARE
}  // namespace commands

const std::vector<CommandEntry>& commandEntries() {
#define SVR_ENTRY(NAME) commands::NAME(),
  static const std::vector<CommandEntry> entries{SVR_COMMANDS(SVR_ENTRY)};
#undef SVR_ENTRY
  return entries;
}

void addCacheFlag(CLI::App& sub) {
  sub.add_flag_callback(
      "--no-cache", [] { DiskCache::disableProcessCache(); },
      fmt::format("train colour models and design palettes afresh, without reading or writing "
                  "the cache ({})",
                  DiskCache::defaultDirectory().empty() ? "none: no HOME"
                                                        : DiskCache::defaultDirectory().string()));
}

void checkImageSize(const std::string& command, const std::string& flag, int value) {
  if (value < 1 || value > 16384)
    throw Error(fmt::format("{}: {} {} is outside 1..16384", command, flag, value));
}

}  // namespace svr
