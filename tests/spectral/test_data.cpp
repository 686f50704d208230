#include "tests/spectral/test_data.h"

#include "spectral/model_error.h"

namespace svr::test {

const std::string& dataDir() {
  static const std::string dir = SVR_TEST_DATA_DIR;
  return dir;
}

const SpectrumLibrary& library() {
  static const SpectrumLibrary lib = SpectrumLibrary::load(dataDir(), WavelengthGrid::standard());
  return lib;
}

const Observer& observer() {
  static const Observer obs = Observer::cie1931(dataDir(), WavelengthGrid::standard());
  return obs;
}

const TrainingSet& smallTrainingSet() {
  static const TrainingSet set = [] {
    std::vector<Spectrum> refl;
    const auto& names = library().munsellNames();
    for (size_t i = 0; i < names.size(); i += 7) refl.push_back(library().get(names[i]));
    const auto eval = makeEvaluationSet(
        "small", unitLights(library(), observer(), standardLightNames()), refl, 1);
    return TrainingSet{eval.lights, eval.reflectances, eval.absorbers, {16, 64, 256}};
  }();
  return set;
}

}  // namespace svr::test
