#pragma once
// Shared, lazily loaded data for the colour-core tests: the shipped library and observer on the
// standard grid, and a small training set that trains in well under a second.

#include "spectral/colorimetry.h"
#include "spectral/factor_training.h"
#include "spectral/spectrum_library.h"

namespace svr::test {

const std::string& dataDir();
const SpectrumLibrary& library();
const Observer& observer();
// 6 standard lights × every 7th Munsell chip (~180), paired weak absorbers.
const TrainingSet& smallTrainingSet();

}  // namespace svr::test
