#include "renderers/volume/memory_budget.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "base/error.h"

namespace svr {

std::uint64_t defaultMemoryBudget() {
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream fields(line);
    std::string key, unit;
    std::uint64_t kib = 0;
    if (fields >> key >> kib >> unit && key == "MemAvailable:" && unit == "kB") return kib * 1024;
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES);
  const long page_size = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page_size > 0)
    return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page_size);
  // Nothing can tell how much is free; refusing every volume would be worse than no limit.
  return std::numeric_limits<std::uint64_t>::max();
}

void checkMemoryBudget(std::uint64_t bytes, std::uint64_t budget, const std::string& what) {
  if (bytes <= budget) return;
  throw Error(
      fmt::format("{} needs {}, over the memory budget of {} (set --memory-budget to raise it)",
                  what, formatBytes(bytes), formatBytes(budget)));
}

std::uint64_t volumeBytes(const HeaderDims& dims, ScalarType type, const std::string& source) {
  for (int a = 0; a < 3; ++a) {
    if (dims[a] < 1)
      throw Error(fmt::format("{}: dimension {} is {}; every dimension must be ≥ 1", source,
                              "xyz"[a], dims[a]));
    if (dims[a] > INT_MAX)
      throw Error(fmt::format("{}: dimension {} is {}, above the largest supported ({})", source,
                              "xyz"[a], dims[a], INT_MAX));
  }
  std::uint64_t bytes = bytesPerVoxel(type);
  for (int a = 0; a < 3; ++a) {
    const auto d = static_cast<std::uint64_t>(dims[a]);
    if (bytes > std::numeric_limits<std::uint64_t>::max() / d)
      throw Error(fmt::format("{}: {} does not fit in 64 bits of bytes", source,
                              describeShape(dims, type)));
    bytes *= d;
  }
  return bytes;
}

std::string formatBytes(std::uint64_t bytes) {
  static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (bytes < 1024) return fmt::format("{} B", bytes);
  double value = static_cast<double>(bytes) / 1024.0;
  int unit = 0;
  while (value >= 1024.0 && unit < 5) {
    value /= 1024.0;
    ++unit;
  }
  return fmt::format("{:.1f} {}", value, kUnits[unit]);
}

std::uint64_t parseByteSize(const std::string& text, const std::string& what) {
  const auto fail = [&] {
    return Error(
        fmt::format("{}: '{}' is not a size; expected bytes, or a number with K, M, G "
                    "or T (binary units), e.g. 512M or 2G",
                    what, text));
  };
  double number = 0;
  const char* const begin = text.data();
  const char* const end = begin + text.size();
  const auto [rest, ec] = std::from_chars(begin, end, number);
  if (ec != std::errc() || !std::isfinite(number) || number <= 0) throw fail();
  std::string suffix;
  for (const char* p = rest; p != end; ++p)
    suffix += static_cast<char>(std::toupper(static_cast<unsigned char>(*p)));
  double scale = 1;
  if (!suffix.empty() && suffix != "B") {
    const std::string units = "KMGT";
    const auto power = units.find(suffix[0]);
    const std::string tail = suffix.substr(1);
    if (power == std::string::npos || !(tail.empty() || tail == "B" || tail == "IB")) throw fail();
    scale = std::pow(1024.0, static_cast<double>(power + 1));
  }
  const double bytes = std::round(number * scale);
  // 2^64 is exactly representable; anything at or above it does not fit.
  if (bytes < 1 || bytes >= 18446744073709551616.0)
    throw Error(fmt::format("{}: '{}' is out of range (1 byte to 16 EiB)", what, text));
  return static_cast<std::uint64_t>(bytes);
}

std::string describeShape(const HeaderDims& dims, ScalarType type) {
  return fmt::format("{}×{}×{} {}", dims[0], dims[1], dims[2], toString(type));
}

std::string describeShape(const Dims& dims, ScalarType type) {
  return describeShape(HeaderDims{dims[0], dims[1], dims[2]}, type);
}

}  // namespace svr
