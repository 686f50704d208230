#pragma once
// `svr info FILE`: what a volume file holds (layout, spacing, world box, value range, memory,
// histogram), to check a file before rendering it.

#include <cstdint>
#include <optional>
#include <string>

#include "renderers/volume/volume_io.h"

namespace svr {

struct InfoOptions {
  std::string path;
  std::optional<RawLayout> raw;  // for headerless files
  std::optional<glm::dvec3> spacing;  // for TIFF stacks
  std::uint64_t memory_budget = defaultMemoryBudget();
};

// Prints describeVolume to stdout; returns the exit code. Throws svr::Error for bad files.
int runInfo(const InfoOptions& options);

}  // namespace svr
