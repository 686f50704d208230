#pragma once
// The stacked linear least-squares system of a design palette (TOG 2009 §3): every criterion as
// weighted rows in the free spectra — colour rows of each target, black and metamer cell, the
// projection-error rows (the colour of each colour signal minus that of its projection onto
// the colour model's subspace), the second-difference smoothness rows, the light-luminance rows
// and a tiny ridge. A cell's colour, light ⊙ reflectance seen through the CMFs, is bilinear,
// so the system is linear in one block at a time: the free materials (lights held) or the
// free lights (materials held). Metamer colours are unknowns in both blocks.
//
// Units: the CMFs are scaled so that the flat light E = 1 has Y = 1; a light at Y = 1 gives
// XYZ relative to its white directly.

#include <Eigen/Core>
#include <vector>

#include "spectral/design_palette.h"

namespace svr {

using CmfMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3>;

// The current values of every spectrum and unknown metamer colour.
struct DesignState {
  std::vector<Eigen::VectorXd> lights;
  std::vector<Eigen::VectorXd> materials;
  std::vector<Eigen::Vector3d> metamer_colours;
  // 3×n: XYZ of what the projection onto the model subspace loses, CMFᵀ (I − Q Qᵀ); empty
  // when the palette has no projection term.
  Eigen::MatrixXd projection_loss;
  // lights × materials: each signal's projection rows are scaled by this (the CIELAB slope at
  // the signal's current luminance, so that equal weighted XYZ losses are equal ΔE).
  Eigen::MatrixXd projection_cell_weight;
};

enum class DesignBlock { kMaterials, kLights };

struct DesignSystem {
  DesignBlock block = DesignBlock::kMaterials;
  Eigen::MatrixXd a;  // rows × unknowns
  Eigen::VectorXd b;
  Eigen::VectorXd lower, upper;
  std::vector<int> spectrum_offset;  // per light or material (by block): column, or −1 if given
  int metamer_offset = 0;            // first of 3 columns per metamer group
};

// CMFs scaled so a flat unit spectrum has Y = 1.
CmfMatrix normalisedCmf(const Observer& observer);

DesignState initialState(const DesignPalette& palette, const CmfMatrix& cmf);

// `only` ≥ 0 restricts the unknowns to that one light or material (and the metamer colours):
// smaller solves, and block descent over finer blocks still never increases the objective.
DesignSystem buildDesignSystem(const DesignPalette& palette, const CmfMatrix& cmf,
                               const DesignState& state, DesignBlock block, int only = -1);
Eigen::VectorXd currentUnknowns(const DesignSystem& system, const DesignState& state);
void applyUnknowns(const DesignSystem& system, const Eigen::VectorXd& x, DesignState* state);

// The objective ‖A x − b‖², the same function of the state whichever block builds it.
double designObjective(const DesignPalette& palette, const CmfMatrix& cmf,
                       const DesignState& state);

}  // namespace svr
