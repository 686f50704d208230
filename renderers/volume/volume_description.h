#pragma once
// What `svr info` prints about a volume: its header (layout, encoding, spacing), the world box
// it fills, its values and what it costs in memory, with a histogram to judge a transfer
// function's domain at a glance.

#include <string>

#include "renderers/volume/volume.h"
#include "renderers/volume/volume_io.h"

namespace svr {

// Multi-line, plain text, fits 100 columns. `header` and `volume` describe the same file.
std::string describeVolume(const VolumeHeader& header, const Volume& volume);

}  // namespace svr
