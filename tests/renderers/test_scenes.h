#pragma once
// Scene builders shared by the renderer tests and benches (OSPRay-style): small analytic scenes
// with known answers.

#include <string>

#include "renderers/core/scene.h"
#include "spectral/colorimetry.h"
#include "spectral/spectrum_library.h"

namespace svr::test {

const std::string& rendererDataDir();
const SpectrumLibrary& rendererLibrary();
const Observer& rendererObserver();

// A homogeneous slab of `voxels` ones (along z, centred) in a 48³ grid, one material of
// extinction sigma (absorbing like `absorption`, or achromatic when empty), seen from +z,
// orthographic, 32×32 pixels, early termination off.
Scene slabScene(double sigma, const std::string& absorption, double step_voxels);

// The procedural phantom with four materials (one spectral absorber, one x-ray), 48×48 pixels.
Scene phantomScene();

}  // namespace svr::test
