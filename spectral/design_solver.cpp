#include "spectral/design_solver.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "spectral/bounded_least_squares.h"
#include "spectral/error.h"

namespace svr {

Xyz relativeXyz(const CmfMatrix& cmf, const Eigen::VectorXd& light,
                const Eigen::VectorXd& reflectance, Xyz* white) {
  const Xyz w = cmf.transpose() * light;
  const double y = w.y() > 0 ? w.y() : 1.0;  // a black light has no white; keep numbers finite
  if (white) *white = w / y;
  return cmf.transpose() * light.cwiseProduct(reflectance) / y;
}

namespace {

// Orthonormal basis of the first k principal directions of every light × material signal;
// CMFᵀ (I − Q Qᵀ) is what projection onto it loses in XYZ.
Eigen::MatrixXd projectionLoss(const CmfMatrix& cmf, const DesignState& s, int k) {
  const int n = static_cast<int>(cmf.rows());
  Eigen::MatrixXd moment = Eigen::MatrixXd::Zero(n, n);
  for (const auto& l : s.lights)
    for (const auto& r : s.materials) {
      const Eigen::VectorXd signal = l.cwiseProduct(r);
      moment.noalias() += signal * signal.transpose();
    }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(moment);
  const Eigen::MatrixXd q = eig.eigenvectors().rightCols(std::min(k, n));
  return cmf.transpose() * (Eigen::MatrixXd::Identity(n, n) - q * q.transpose());
}

bool bilinear(const DesignPalette& p) {
  bool light = false, material = false;
  for (const auto& l : p.lights) light = light || l.free;
  for (const auto& m : p.materials) material = material || m.free;
  return light && material;
}

}  // namespace

// The alternation stops when a round lowers the objective by less than a fraction of it, or of
// the starting objective: bilinear block descent crawls near its optimum (hundreds of rounds
// for the last 1e-6 of a colour), where the colours no longer change visibly.
constexpr double kRelativeDecrease = 1e-3;
constexpr double kStartDecrease = 1e-8;

DesignResult designPalette(const DesignPalette& palette, const Observer& observer) {
  const CmfMatrix cmf = normalisedCmf(observer);
  const DesignOptions& opt = palette.options;
  DesignState state = initialState(palette, cmf);
  DesignResult result;

  std::vector<DesignBlock> blocks;
  for (const auto& m : palette.materials)
    if (m.free) {
      blocks.push_back(DesignBlock::kMaterials);
      break;
    }
  for (const auto& l : palette.lights)
    if (l.free) {
      blocks.push_back(DesignBlock::kLights);
      break;
    }
  const bool physical = opt.bounds == DesignBounds::kPhysical;
  const int max_rounds = bilinear(palette) ? opt.max_iterations : 1;
  // The projection subspace depends on the spectra being designed: refresh it a few times
  // (each refresh changes the objective, so the alternation restarts its descent).
  const int subspace_rounds = opt.projection_k > 0 ? 8 : 1;
  bool first_solve = true;
  for (int sub = 0; sub < subspace_rounds; ++sub) {
    if (opt.projection_k > 0) state.projection_loss = projectionLoss(cmf, state, opt.projection_k);
    double previous = designObjective(palette, cmf, state);
    const double start = previous;
    result.history.push_back(previous);
    result.converged = false;
    for (int round = 0; round < max_rounds; ++round) {
      ++result.iterations;
      for (DesignBlock block : blocks) {
        const auto& spectra = block == DesignBlock::kLights ? palette.lights : palette.materials;
        // Joint: one solve per block. Split: one per free spectrum, much cheaper per solve but
        // slow to converge where metamer colours couple the materials.
        const int parts = opt.split_blocks ? static_cast<int>(spectra.size()) : 1;
        for (int only = 0; only < parts; ++only) {
          if (opt.split_blocks && !spectra[only].free) continue;
          const DesignSystem sys =
              buildDesignSystem(palette, cmf, state, block, opt.split_blocks ? only : -1);
          Eigen::VectorXd x = solveLeastSquares(sys.a, sys.b);
          if (first_solve) result.unconstrained_objective = (sys.a * x - sys.b).squaredNorm();
          first_solve = false;
          if (physical) {
            BoundedLsReport rep;
            x = solveBoundedLeastSquares(sys.a, sys.b, sys.lower, sys.upper, &rep);
            if (!rep.unconstrained) ++result.bounded_solves;
          }
          // Keep the held state when rounding would make the step worse: block descent must
          // never increase the objective.
          const double before = (sys.a * currentUnknowns(sys, state) - sys.b).squaredNorm();
          const double after = (sys.a * x - sys.b).squaredNorm();
          if (x.allFinite() && after <= before) applyUnknowns(sys, x, &state);
          result.history.push_back(std::min(after, before));
        }
      }
      const double now = result.history.back();
      if (previous - now <= kRelativeDecrease * previous + kStartDecrease * start + 1e-14) {
        result.converged = true;
        break;
      }
      previous = now;
    }
  }
  result.objective = result.history.back();

  // Fix every free light's luminance exactly; relative colours do not depend on the scale.
  for (std::size_t j = 0; j < palette.lights.size(); ++j) {
    const double y = cmf.col(1).dot(state.lights[j]);
    if (palette.lights[j].free && y > 0) state.lights[j] *= opt.light_luminance / y;
  }
  const WavelengthGrid grid = observer.grid();
  for (std::size_t j = 0; j < palette.lights.size(); ++j)
    result.lights.push_back({palette.lights[j].name, Spectrum(grid, state.lights[j])});
  for (std::size_t m = 0; m < palette.materials.size(); ++m)
    result.materials.push_back({palette.materials[m].name, Spectrum(grid, state.materials[m])});

  auto report = [&](int m, int j, CellKind kind, const Xyz& target, double weight) {
    CellReport c;
    c.material = palette.materials[m].name;
    c.light = palette.lights[j].name;
    c.kind = kind;
    Xyz white;
    c.achieved = relativeXyz(cmf, state.lights[j], state.materials[m], &white);
    c.target = target;
    c.de2000 = deltaE2000(xyzToLab(c.achieved, white), xyzToLab(target, white));
    c.residual = weight * (c.achieved - target).norm();
    c.miss = kind == CellKind::kBlack ? c.achieved.y() > opt.black_y : c.de2000 > opt.miss_de2000;
    if (!c.achieved.allFinite() || !std::isfinite(c.de2000))
      throw Error(fmt::format("design: cell {} × {} is not finite", c.material, c.light));
    if (c.miss)
      result.misses.push_back(
          kind == CellKind::kBlack
              ? fmt::format("{} under {}: black cell has Y = {:.4f} > {}", c.material, c.light,
                            c.achieved.y(), opt.black_y)
              : fmt::format("{} under {}: {} cell misses by ΔE2000 {:.2f} (> {})", c.material,
                            c.light, toString(kind), c.de2000, opt.miss_de2000));
    result.cells.push_back(c);
  };
  for (const auto& c : palette.cells) report(c.material, c.light, c.kind, c.target, c.weight);
  for (const auto& g : palette.metamers) {
    // The shared colour reported is the members' mean: each member's ΔE is its distance from it.
    Xyz mean = Xyz::Zero();
    for (int m : g.materials) mean += relativeXyz(cmf, state.lights[g.light], state.materials[m]);
    mean /= static_cast<double>(g.materials.size());
    for (int m : g.materials) report(m, g.light, CellKind::kMetamer, mean, g.weight);
  }
  return result;
}

}  // namespace svr
