#include "spectral/design_solver.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "spectral/bounded_least_squares.h"
#include "base/error.h"

namespace svr {

Xyz relativeXyz(const CmfMatrix& cmf, const Eigen::VectorXd& light,
                const Eigen::VectorXd& reflectance, Xyz* white) {
  const Xyz w = cmf.transpose() * light;
  const double y = w.y() > 0 ? w.y() : 1.0;  // a black light has no white; keep numbers finite
  if (white) *white = w / y;
  return cmf.transpose() * light.cwiseProduct(reflectance) / y;
}

namespace {

// The span of the factor:k model a scene trains on these spectra: the first k principal
// directions of every light × material signal with the lights at equal luminance
// (principalBasis's span; sharpening only changes the basis within the span, not the span).
// Not principalBasis itself: its different summation order moves the design to another local
// optimum (see the boost note below).
Eigen::MatrixXd modelSubspace(const CmfMatrix& cmf, const DesignState& s, int k) {
  const int n = static_cast<int>(cmf.rows());
  Eigen::MatrixXd moment = Eigen::MatrixXd::Zero(n, n);
  for (const auto& l : s.lights) {
    const double y = cmf.col(1).dot(l);
    for (const auto& r : s.materials) {
      const Eigen::VectorXd signal = l.cwiseProduct(r) / (y > 0 ? y : 1.0);
      moment.noalias() += signal * signal.transpose();
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(moment);
  return eig.eigenvectors().rightCols(std::min(k, n));
}

// CIELAB's lightness slope dL*/dY relative to its value at Y = 1: ΔE of an XYZ loss grows as
// a colour darkens (23× at black), so a metameric black needs its projection loss ~23× smaller
// than a white does for the same ΔE.
double labSlope(double y) { return std::pow(std::max(y, 216.0 / 24389.0), -2.0 / 3.0); }

// ΔE2000 (lights × materials) between each signal's colour and that of its projection onto the
// model subspace q (orthonormal columns), against the light's white.
Eigen::MatrixXd projectionDe2000(const CmfMatrix& cmf, const DesignState& s,
                                 const Eigen::MatrixXd& q) {
  Eigen::MatrixXd de(static_cast<Eigen::Index>(s.lights.size()),
                     static_cast<Eigen::Index>(s.materials.size()));
  for (std::size_t j = 0; j < s.lights.size(); ++j)
    for (std::size_t m = 0; m < s.materials.size(); ++m) {
      Xyz white;
      const Xyz full = relativeXyz(cmf, s.lights[j], s.materials[m], &white);
      const Eigen::VectorXd signal = s.lights[j].cwiseProduct(s.materials[m]);
      const double y = cmf.col(1).dot(s.lights[j]);
      const Xyz lost = cmf.transpose() * (signal - q * (q.transpose() * signal)) / (y > 0 ? y : 1.0);
      de(j, m) = deltaE2000(xyzToLab(full, white), xyzToLab(full - lost, white));
    }
  return de;
}

// Loss rows for the subspace q; each signal weighted by CIELAB's slope at its luminance
// times its boost (grown for signals that stay beyond the target, a penalty method).
void refreshProjectionTerm(const CmfMatrix& cmf, const Eigen::MatrixXd& q,
                           const Eigen::MatrixXd& boost, DesignState* s) {
  const int n = static_cast<int>(cmf.rows());
  s->projection_loss = cmf.transpose() * (Eigen::MatrixXd::Identity(n, n) - q * q.transpose());
  s->projection_cell_weight = boost;
  for (std::size_t j = 0; j < s->lights.size(); ++j)
    for (std::size_t m = 0; m < s->materials.size(); ++m)
      s->projection_cell_weight(j, m) *=
          labSlope(relativeXyz(cmf, s->lights[j], s->materials[m]).y());
}

}  // namespace

std::vector<ProjectionReport> projectionErrors(const std::vector<NamedSpectrum>& lights,
                                               const std::vector<NamedSpectrum>& materials,
                                               const Observer& observer, int k) {
  DesignState s;
  for (const auto& l : lights) s.lights.push_back(l.spectrum.values());
  for (const auto& m : materials) s.materials.push_back(m.spectrum.values());
  const CmfMatrix cmf = normalisedCmf(observer);
  const Eigen::MatrixXd de = projectionDe2000(cmf, s, modelSubspace(cmf, s, k));
  std::vector<ProjectionReport> out;
  for (std::size_t j = 0; j < lights.size(); ++j)
    for (std::size_t m = 0; m < materials.size(); ++m)
      out.push_back({materials[m].name, lights[j].name, de(j, m)});
  return out;
}

namespace {

bool bilinear(const DesignPalette& p) {
  bool light = false, material = false;
  for (const auto& l : p.lights) light = light || l.free;
  for (const auto& m : p.materials) material = material || m.free;
  return light && material;
}

}  // namespace

// Every constrained cell's target, achieved colour and ΔE2000 (metamers against their
// members' mean), and a line for each that misses.
void reportCells(const DesignPalette& palette, const CmfMatrix& cmf, const DesignState& state,
                 DesignResult* out) {
  const DesignOptions& opt = palette.options;
  DesignResult& result = *out;
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
}

// The alternation stops when a round lowers the objective by less than a fraction of it, or of
// the starting objective: bilinear block descent crawls near its optimum (hundreds of rounds
// for the last 1e-6 of a colour), where the colours no longer change visibly.
constexpr double kRelativeDecrease = 1e-3;
constexpr double kStartDecrease = 1e-8;

DesignResult designPalette(const DesignPalette& palette, const Observer& observer) {
  const CmfMatrix cmf = normalisedCmf(observer);
  const WavelengthGrid grid = observer.grid();
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
  // The projection subspace and the cells' CIELAB slopes depend on the spectra being designed:
  // refresh them until every signal projects within the target (each refresh changes the
  // objective, so the alternation restarts its descent).
  const int subspace_rounds = opt.projection_k > 0 ? opt.projection_rounds : 1;
  bool first_solve = true;
  Eigen::MatrixXd boost = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(palette.lights.size()),
                                                 static_cast<Eigen::Index>(palette.materials.size()));
  for (int sub = 0; sub < subspace_rounds; ++sub) {
    if (opt.projection_k > 0) {
      const Eigen::MatrixXd q = modelSubspace(cmf, state, opt.projection_k);
      if (sub > 0) {
        const Eigen::MatrixXd de = projectionDe2000(cmf, state, q);
        if (de.maxCoeff() <= opt.projection_de2000) break;
        // A signal k× beyond the target gets up to k× the weight (at most 4× a round). The
        // boosts are unbounded, and the outcome is sensitive: summing the subspace's moment
        // in another order (principalBasis) sent the engine to an objective of 1e14 (issue 8's
        // note).
        boost = boost.cwiseProduct(
            (de / std::max(opt.projection_de2000, 1e-3)).cwiseMax(1.0).cwiseMin(4.0));
      }
      refreshProjectionTerm(cmf, q, boost, &state);
      ++result.projection_rounds;
    }
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
  for (std::size_t j = 0; j < palette.lights.size(); ++j)
    result.lights.push_back({palette.lights[j].name, Spectrum(grid, state.lights[j])});
  for (std::size_t m = 0; m < palette.materials.size(); ++m)
    result.materials.push_back({palette.materials[m].name, Spectrum(grid, state.materials[m])});
  if (opt.projection_k > 0)
    result.projection = projectionErrors(result.lights, result.materials, observer, opt.projection_k);

  reportCells(palette, cmf, state, &result);
  return result;
}

}  // namespace svr
