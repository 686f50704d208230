#pragma once
// A stress corpus of scenes written the way users write them (issue 40): random, with a fixed
// seed, built from the shipped data only —
//   a real volume from data/volumes (CT, MRI, simulation; 8-bit, 16-bit big- and little-endian,
//   float), with transfer-function points and an opacity ramp placed at quantiles of its values;
//   1–8 lights drawn from the whole library (CIE A/D, the F series, the LEDs), sometimes a mix;
//   1–5 materials from Munsell or the ColorChecker, absorbing achromatically or spectrally (Hb,
//   HbO2, or a reflectance's shape), weak to very strong (an optical depth of 0.3–300 across the
//   volume's diagonal), some x-ray, some specular;
//   sometimes a backdrop; a random light direction and view.
// Scene `index` depends only on (seed, index), so any slice of the corpus is reproducible alone.
// The generator is the bench's (bench/models) and the corpus test's, not the product's.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "renderers/scene/scene.h"
#include "spectral/spectrum_library.h"

namespace svr {

class SceneCorpus {
 public:
  static constexpr unsigned kDefaultSeed = 40;  // the seed the bench and the test use
  SceneCorpus(std::string data_dir, const SpectrumLibrary& library, unsigned seed, int size);

  // The scene file corpus scene `index` would be (volume path absolute).
  nlohmann::json sceneJson(int index) const;
  // The scene itself, loaded as `svr render` would load the file.
  Scene scene(int index) const;
  // "corpus/<seed>/<index>"
  std::string name(int index) const;

 private:
  struct VolumeFacts {
    std::string path;
    std::vector<double> quantiles;  // 0%, 1%, …, 100% of the voxel values
    double diagonal = 1.0;          // of the world box
  };
  const VolumeFacts& facts(int which) const;

  std::string data_dir_;
  const SpectrumLibrary& library_;
  unsigned seed_;
  int size_;
  std::vector<std::string> volume_files_;
  mutable std::map<int, VolumeFacts> facts_;
};

}  // namespace svr
