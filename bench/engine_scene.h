#pragma once
// The scene every backend bench renders (data/scenes/engine.json), loaded once per binary, so
// the raycast, shear-warp and splat benches time the same volume, transfer function and view.

#include "renderers/core/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/data_dir.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct EngineBenchScene {
  SpectrumLibrary library = SpectrumLibrary::load(defaultDataDir(), WavelengthGrid::standard());
  Observer observer = Observer::cie1931(defaultDataDir(), WavelengthGrid::standard());
  Scene scene = loadScene(defaultDataDir() + "/scenes/engine.json", library);
};

inline const EngineBenchScene& engineBenchScene() {
  static const EngineBenchScene s;
  return s;
}

}  // namespace svr
