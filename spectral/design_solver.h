#pragma once
// Designing a palette's free spectra (TOG 2009 §3): the stacked least-squares system solved
// without bounds first (complete orthogonal decomposition), then with them (BVLS); where a cell
// has both its light and its material free the problem is bilinear, and the solver alternates
// (materials with lights held, lights with materials held) until the objective stops falling.
// With a projection term the model subspace is the PCA subspace of the current colour signals
// (a factor:k model's span does not depend on its sharpening), refreshed between rounds.

#include <string>
#include <vector>

#include "spectral/design_palette.h"
#include "spectral/design_system.h"
#include "spectral/palette.h"

namespace svr {

struct CellReport {
  std::string material, light;
  CellKind kind = CellKind::kColour;
  Xyz target = Xyz::Zero();    // relative to the white under the light (Y = 1)
  Xyz achieved = Xyz::Zero();
  double de2000 = 0.0;         // Lab against the white of that light
  double residual = 0.0;       // weight · ‖achieved − target‖ (XYZ)
  bool miss = false;           // beyond options.miss_de2000, or (black) Y > options.black_y
};

struct DesignResult {
  std::vector<NamedSpectrum> lights;     // designed and given, each at the palette luminance
  std::vector<NamedSpectrum> materials;
  std::vector<CellReport> cells;         // one per constrained cell (metamers: one per member)
  double unconstrained_objective = 0.0;  // first solve without bounds (bounded palettes)
  double objective = 0.0;
  int iterations = 0;                    // alternation rounds (1 when not bilinear)
  std::vector<double> history;           // objective after every block solve
  int bounded_solves = 0;                // block solves where the bounds were active
  bool converged = false;                // objective stopped falling before the round cap
  std::vector<std::string> misses;       // human-readable, one per missed cell
};

DesignResult designPalette(const DesignPalette& palette, const Observer& observer);

// XYZ of light ⊙ reflectance relative to the light's white (Y = 1), with that white.
Xyz relativeXyz(const CmfMatrix& cmf, const Eigen::VectorXd& light,
                const Eigen::VectorXd& reflectance, Xyz* white = nullptr);

}  // namespace svr
