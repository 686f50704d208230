#include "base/text_file.h"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.h"

namespace svr {
namespace fs = std::filesystem;

std::string readTextFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw Error(fmt::format("{}: cannot open {}: no such file", path, what));
  if (!fs::is_regular_file(status))
    throw Error(fmt::format("{}: cannot open {}: not a regular file", path, what));
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxTextFileBytes)
    throw Error(fmt::format("{}: {} bytes is too large for a {} (at most {} bytes)", path, size,
                            what, kMaxTextFileBytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(fmt::format("{}: cannot open {}", path, what));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(fmt::format("{}: cannot read {}", path, what));
  return text.str();
}

}  // namespace svr
