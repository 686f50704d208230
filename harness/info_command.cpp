#include "harness/info_command.h"

#include <fmt/format.h>

#include "renderers/core/volume_description.h"

namespace svr {

int runInfo(const InfoOptions& options) {
  const VolumeLoadOptions load{options.memory_budget, options.raw};
  const VolumeHeader header = readVolumeHeader(options.path, load);
  const Volume volume = loadVolume(options.path, load);
  fmt::print("{}", describeVolume(header, volume));
  return 0;
}

}  // namespace svr
