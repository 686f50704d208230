#pragma once
// How much memory a volume may take, checked before anything is allocated: a header that claims
// 4096³ float64 must give a clear error, not an out-of-memory kill or a half-read file. Sizes
// are computed with overflow checks because header values are untrusted input.

#include <array>
#include <cstdint>
#include <string>

#include "renderers/volume/volume.h"

namespace svr {

// Dimensions as a header states them, before they are known to be valid Dims.
using HeaderDims = std::array<std::int64_t, 3>;

// MemAvailable from /proc/meminfo (what the kernel says can be allocated without swapping);
// sysconf's available physical pages where /proc is missing; no limit if neither answers.
std::uint64_t defaultMemoryBudget();

// Throws svr::Error "WHAT needs 512.0 MiB, over the memory budget of 100.0 MiB (set
// --memory-budget to raise it)" when bytes > budget. `what` names the file and the volume,
// e.g. "head.nhdr: 512×512×512 float32".
void checkMemoryBudget(std::uint64_t bytes, std::uint64_t budget, const std::string& what);

// Bytes of a dims[0]×dims[1]×dims[2] grid of `type` voxels. Throws svr::Error naming `source`
// when a dimension is < 1 or above INT_MAX (Volume keeps int dims), or when the product does not
// fit in 64 bits.
std::uint64_t volumeBytes(const HeaderDims& dims, ScalarType type, const std::string& source);

// "512.0 MiB", "100 B", "2.0 GiB": binary units, one decimal.
std::string formatBytes(std::uint64_t bytes);

// "1073741824", "512M", "2G", "1.5GiB", "64k" → bytes (K, M, G, T are binary: 1K = 1024; an
// optional "B" or "iB" may follow). Throws svr::Error naming `what` (e.g. "--memory-budget")
// and the text when it is not a positive size or does not fit in 64 bits.
std::uint64_t parseByteSize(const std::string& text, const std::string& what);

// "256×256×128 uint8": how messages name a volume's shape.
std::string describeShape(const HeaderDims& dims, ScalarType type);
std::string describeShape(const Dims& dims, ScalarType type);

}  // namespace svr
