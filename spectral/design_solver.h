#pragma once
// Designing a palette's free spectra (TOG 2009 §3): the stacked least-squares system solved
// without bounds first (complete orthogonal decomposition), then with them (BVLS); where a cell
// has both its light and its material free the problem is bilinear, and the solver alternates
// (materials with lights held, lights with materials held) until the objective stops falling.
// With a projection term the model subspace is the PCA subspace of the current colour signals
// (a factor:k model's span does not depend on its sharpening) and each signal's rows are scaled
// by CIELAB's slope at its luminance; both are refreshed until every signal projects within
// options.projection_de2000 or options.projection_rounds is spent.

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

// A light × material signal against its projection onto the colour model's subspace.
struct ProjectionReport {
  std::string material, light;
  double de2000 = 0.0;
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
  // With a projection model: every light × material (not only the constrained cells).
  std::vector<ProjectionReport> projection;
  int projection_rounds = 0;             // refreshes of the model subspace
};

DesignResult designPalette(const DesignPalette& palette, const Observer& observer);

// ΔE2000 between the colour of every light × material signal and of its projection onto the
// span of the factor:k model trained on these spectra (the span of principalBasis; what a
// scene's factor:k keeps of each signal).
std::vector<ProjectionReport> projectionErrors(const std::vector<NamedSpectrum>& lights,
                                               const std::vector<NamedSpectrum>& materials,
                                               const Observer& observer, int k);

// XYZ of light ⊙ reflectance relative to the light's white (Y = 1), with that white.
Xyz relativeXyz(const CmfMatrix& cmf, const Eigen::VectorXd& light,
                const Eigen::VectorXd& reflectance, Xyz* white = nullptr);

}  // namespace svr
