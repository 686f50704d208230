#pragma once
// `svr design PALETTE.json --out DIR`: designs a palette's free lights and materials (see
// spectral/design_palette.h) and writes into DIR
//   spectra.csv    every light and material of the palette, designed or given, one column each
//   palette.json   a plain palette naming those columns: for scenes ({"csv": …, "column": …})
//                  and for `svr model-error --palette`
//   design.json    {"cells": [{"material", "light", "kind", "target_xyz", "achieved_xyz",
//                  "de2000", "residual", "miss"}, …], "objective", "iterations", …}
//   palette.png    swatches, materials × lights, target (left) beside achieved (right)
//   spectra.png    the designed spectra (matplotlib through Debian's /usr/bin/python3)
// and prints target against achieved for every constrained cell. Misses are printed and listed;
// with --strict they are an error (exit status 2).

#include <string>

namespace svr {

struct DesignCommandOptions {
  std::string data_dir;
  std::string palette;
  std::string out_dir;
  bool plots = true;  // spectra.png needs python3-matplotlib
  bool strict = false;
  bool quiet = false;
};

int runDesign(const DesignCommandOptions& options);

}  // namespace svr
