#pragma once
// Reading a whole input text file (scene, palette, colour model, spectrum table) with the checks
// a path from outside needs: a device or FIFO (/dev/zero, /dev/stdin) would otherwise be read
// forever, and a huge file named by mistake would be read into memory whole.

#include <cstdint>
#include <string>

namespace svr {

// Input text files are small (the largest shipped table is a few MiB).
inline constexpr std::uint64_t kMaxTextFileBytes = std::uint64_t{64} << 20;

// The file's bytes. Throws svr::Error naming `path` when it is missing, not a regular file,
// larger than kMaxTextFileBytes, or unreadable; `what` says what it should be ("spectrum table").
std::string readTextFile(const std::string& path, const std::string& what);

}  // namespace svr
