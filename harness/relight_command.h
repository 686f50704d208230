#pragma once
// `svr relight LI.exr --light D65 | --mix A:0.3,F11:0.7 --out x.png`: post-illumination of a
// saved light-independent image, no re-rendering. The colour model is read from the JSON the
// renderer wrote beside the EXR (or --model). --on BACKEND relights on that backend's device (the
// same maths, to one 8-bit code value).

#include <string>

namespace svr {

struct RelightOptions {
  std::string data_dir;
  std::string image;
  std::string model;  // default: the EXR's svr:model_file attribute, beside it
  std::string light;
  std::string mix;    // "A:0.3,F11:0.7"
  std::string background;
  double exposure = 1.0;
  std::string out;
  std::string relighter;  // a backend whose relighter to use (gl: its fragment shader); empty: CPU
};

int runRelight(const RelightOptions& options);

}  // namespace svr
