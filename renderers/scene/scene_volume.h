#pragma once
// The "volume" entry of a scene: a file (NRRD, MetaImage, or headerless raw with its layout)
// or a procedural volume with a closed form.
//   {"file": "../volumes/engine.nhdr"}
//   {"file": "ct.raw", "raw": {"dims": [x, y, z], "type": "uint16", "endian": "big",
//                              "spacing": [1, 1, 2], "header_bytes": 0}}
//   {"procedural": "marschner_lobb", "size": 41}
//   {"procedural": "slab", "size": 64, "thickness": 0.5}      (fraction of the z extent)
//   {"procedural": "sphere", "size": 64, "radius": 0.8}       (fraction of the half extent)
//   {"procedural": "shells", "size": 64, "shells": 3}
//   {"procedural": "phantom"}                                  (labels 0..4, 64³)

#include <filesystem>
#include <string>

#include "renderers/volume/volume.h"
#include "renderers/volume/volume_io.h"
#include "base/json_reader.h"

namespace svr {

struct SceneVolume {
  Volume volume;
  std::string source;  // the resolved path, or the procedural description
};

SceneVolume loadSceneVolume(const JsonReader& spec, const std::filesystem::path& base_dir,
                            const VolumeLoadOptions& options);

}  // namespace svr
