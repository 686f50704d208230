#pragma once
// `svr import-tf MAP --volume VOLUME --out SCENE.json`: a colour and opacity map from ParaView
// (an exported JSON preset) or 3D Slicer (a .vp volume property) made into an editable svr
// scene: one designed reflectance per colour knot (renderers/scene/imported_transfer_function.h),
// written as explicit spectra, the opacity as svr's extinction and opacity curve, the light the
// colours were matched under, and the volume. Prints, per control point of the map, how far the
// scene's colour there (under that light) is from the map's.

#include <optional>
#include <string>
#include <utility>

namespace svr {

struct ImportTfOptions {
  std::string data_dir;
  std::string map;     // .json (ParaView) or .vp (Slicer)
  std::string preset;  // ParaView: which preset of several
  std::string volume;  // the scene's volume file
  std::string out;     // the scene file to write
  std::string range;   // "" (as stored), "data" or "LO,HI"
  double unit_distance = 1.0;
  std::string light = "D65";
  double specular = 0.0;
  bool quiet = false;
};

int runImportTf(const ImportTfOptions& options);

}  // namespace svr
