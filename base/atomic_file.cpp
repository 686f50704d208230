#include "base/atomic_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  // Hidden, and unique per process, so two writers of one file never share a temporary.
  const fs::path tmp =
      target.parent_path() / fmt::format(".{}.tmp{}", target.filename().string(), getpid());
  try {
    write(tmp.string());
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw Error(fmt::format("{}: cannot write: {}", path, ec.message()));
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw Error(fmt::format("{}: cannot write", path));
  });
}

}  // namespace svr
