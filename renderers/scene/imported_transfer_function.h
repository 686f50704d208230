#pragma once
// A colour map from another tool (colour_map.h) turned into svr's own transfer function: each
// colour becomes a reflectance spectrum through svr's design solver (paper §4: smooth, bounded
// spectra that reproduce a target colour under a chosen light), and each α a share of one
// extinction σ. The result is ordinary svr materials, so models, relighting and the viewer work
// on them as on any scene.
//
// Colours: the map is sampled densely in its own colour space; the fewest knots are kept such
// that blending the knots' colours linearly (what svr's material blend does to the colour
// under a light) stays within `blend_de2000` of every sample; one reflectance is designed per knot.
// Opacity: α per unit distance d is the extinction σ = −ln(1 − α) / d (α capped at 0.999, so
// σ ≤ 6.9 / d); the materials carry the largest σ and the opacity curve the share of it.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "renderers/scene/colour_map.h"
#include "renderers/scene/transfer_function.h"
#include "spectral/colorimetry.h"
#include "spectral/spectrum_library.h"

namespace svr {

struct ImportOptions {
  double unit_distance = 1.0;  // world length over which a map's α is the opacity
  std::string light = "D65";   // the light under which the spectra show the map's colours
  double specular = 0.0;       // of every material made
  double blend_de2000 = 0.5;   // knots: the blend stays this close to the map
};

struct ImportedKnot {
  double x;
  Eigen::Vector3d srgb;   // the map's colour there
  double de2000 = 0.0;    // the designed reflectance under the light against it
};

struct ImportedTransferFunction {
  TransferFunction tf;
  std::vector<ImportedKnot> knots;
  // At every control point of the map: the colour the transfer function shows there under the
  // light against the map's, ΔE2000.
  std::vector<double> control_point_de2000;
  double sigma = 0.0;  // the materials' extinction per unit world length
};

// Throws svr::Error for a light the library does not know or a unit distance ≤ 0.
ImportedTransferFunction importTransferFunction(const ColourMap& map,
                                                const SpectrumLibrary& library,
                                                const Observer& observer,
                                                const ImportOptions& options = {});

// The colour the transfer function's material blend at x shows under `light` (Y of white = 1),
// as CIELAB against that white: what a view lit only by ambient light shows of an opaque slab.
Lab transferFunctionLab(const TransferFunction& tf, double x, const Spectrum& light,
                        const Observer& observer);

}  // namespace svr
