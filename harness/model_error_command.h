#pragma once
// `svr model-error`: how far each colour model is from the exact spectral product, on the
// standard sets (design.md §4) or on a scene's own palette.

#include <string>
#include <vector>

namespace svr {

struct ModelErrorOptions {
  std::string data_dir;
  std::vector<std::string> lights;        // library names; empty = the standard six
  std::vector<std::string> reflectances;  // library names, or "munsell" / "colorchecker"
  std::string palette;                    // palette JSON: train on its own lights × materials
  std::string json_path;
  int k_min = 3, k_max = 10;
  bool contrast = false;  // also the closed-form sharpening, to show its instability
  bool quiet = false;
};

int runModelError(const ModelErrorOptions& options);

}  // namespace svr
