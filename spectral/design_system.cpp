#include "spectral/design_system.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "base/error.h"

namespace svr {

CmfMatrix normalisedCmf(const Observer& observer) {
  const CmfMatrix& w = observer.weightedCmf();
  return w / w.col(1).sum();
}

DesignState initialState(const DesignPalette& palette, const CmfMatrix& cmf) {
  DesignState s;
  const double y = palette.options.light_luminance;
  for (const auto& l : palette.lights) {
    const double ly = cmf.col(1).dot(l.spectrum.values());
    if (!(ly > 0)) throw Error(fmt::format("light '{}' has luminance Y = {}", l.name, ly));
    s.lights.push_back(l.spectrum.values() * (y / ly));
  }
  for (const auto& m : palette.materials) s.materials.push_back(m.spectrum.values());
  s.metamer_colours.assign(palette.metamers.size(), Eigen::Vector3d::Zero());
  // Start each shared colour at the mean of its members under the starting spectra.
  for (std::size_t g = 0; g < palette.metamers.size(); ++g) {
    const auto& group = palette.metamers[g];
    for (int m : group.materials)
      s.metamer_colours[g] += cmf.transpose() * s.lights[group.light].cwiseProduct(s.materials[m]);
    s.metamer_colours[g] /= static_cast<double>(group.materials.size());
  }
  return s;
}

namespace {

// Rows accumulate as a dense matrix: the systems are small (hundreds of unknowns).
class RowStack {
 public:
  explicit RowStack(int unknowns) : unknowns_(unknowns) {}
  // Appends `count` rows; returns the block to fill (A) and the right-hand side block.
  int add(int count) {
    const int first = rows_;
    rows_ += count;
    if (rows_ > a_.rows()) {
      const int cap = std::max<int>(rows_, 2 * static_cast<int>(a_.rows()) + 64);
      a_.conservativeResize(cap, unknowns_);
      b_.conservativeResize(cap);
      a_.bottomRows(cap - first).setZero();
      b_.tail(cap - first).setZero();
    }
    return first;
  }
  Eigen::MatrixXd& a() { return a_; }
  Eigen::VectorXd& b() { return b_; }
  void finish(DesignSystem* s) {
    s->a = a_.topRows(rows_);
    s->b = b_.head(rows_);
  }

 private:
  int unknowns_, rows_ = 0;
  Eigen::MatrixXd a_{0, 0};
  Eigen::VectorXd b_;
};

Eigen::MatrixXd secondDifference(int n) {
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(std::max(n - 2, 0), n);
  for (int i = 0; i + 2 < n; ++i) d(i, i) = 1, d(i, i + 1) = -2, d(i, i + 2) = 1;
  return d;
}

}  // namespace

DesignSystem buildDesignSystem(const DesignPalette& palette, const CmfMatrix& cmf,
                               const DesignState& state, DesignBlock block, int only) {
  const int n = static_cast<int>(cmf.rows());
  const DesignOptions& opt = palette.options;
  const bool lights_block = block == DesignBlock::kLights;
  const auto& block_spectra = lights_block ? palette.lights : palette.materials;
  DesignSystem sys;
  sys.block = block;
  int unknowns = 0;
  for (std::size_t i = 0; i < block_spectra.size(); ++i) {
    const bool active = block_spectra[i].free && (only < 0 || static_cast<int>(i) == only);
    sys.spectrum_offset.push_back(active ? unknowns : -1);
    if (active) unknowns += n;
  }
  sys.metamer_offset = unknowns;
  unknowns += 3 * static_cast<int>(palette.metamers.size());
  const double inf = std::numeric_limits<double>::infinity();
  const bool physical = opt.bounds == DesignBounds::kPhysical;
  sys.lower = Eigen::VectorXd::Constant(unknowns, -inf);
  sys.upper = Eigen::VectorXd::Constant(unknowns, inf);
  if (physical)
    for (int off : sys.spectrum_offset)
      if (off >= 0) {
        sys.lower.segment(off, n).setZero();
        if (!lights_block) sys.upper.segment(off, n).setOnes();
      }

  RowStack rows(unknowns);
  auto offsetOf = [&](bool is_light, int index) {
    return is_light == lights_block ? sys.spectrum_offset[index] : -1;
  };
  // Adds w · (M3×n · (l ⊙ r)) − w · target as 3 rows: linear in whichever factor is unknown.
  // `metamer` ≥ 0 subtracts that group's unknown colour instead of a fixed target.
  auto addColourRows = [&](const Eigen::MatrixXd& m, int light, int material, double w,
                           const Eigen::Vector3d& target, int metamer) {
    const int r = rows.add(3);
    const Eigen::VectorXd& l = state.lights[light];
    const Eigen::VectorXd& refl = state.materials[material];
    const int lo = offsetOf(true, light), mo = offsetOf(false, material);
    if (lo >= 0)
      rows.a().block(r, lo, 3, n) = w * (m * refl.asDiagonal());
    else if (mo >= 0)
      rows.a().block(r, mo, 3, n) = w * (m * l.asDiagonal());
    else
      rows.b().segment(r, 3) -= w * (m * l.cwiseProduct(refl));
    if (metamer >= 0)
      rows.a().block(r, sys.metamer_offset + 3 * metamer, 3, 3) =
          -w * Eigen::Matrix3d::Identity();
    else
      rows.b().segment(r, 3) += w * target;
  };
  const Eigen::MatrixXd cmf_t = cmf.transpose();
  for (const auto& c : palette.cells)
    addColourRows(cmf_t, c.light, c.material, c.weight, c.target, -1);
  for (std::size_t g = 0; g < palette.metamers.size(); ++g)
    for (int m : palette.metamers[g].materials)
      addColourRows(cmf_t, palette.metamers[g].light, m, palette.metamers[g].weight,
                    Eigen::Vector3d::Zero(), static_cast<int>(g));
  if (state.projection_loss.size() > 0 && opt.projection_weight > 0)
    for (std::size_t j = 0; j < palette.lights.size(); ++j)
      for (std::size_t m = 0; m < palette.materials.size(); ++m)
        addColourRows(state.projection_loss, static_cast<int>(j), static_cast<int>(m),
                      opt.projection_weight * state.projection_cell_weight(j, m),
                      Eigen::Vector3d::Zero(), -1);

  // Per free spectrum: smoothness, ridge, and (lights) luminance. Spectra outside the block
  // contribute constant rows so that the objective is the same whichever block is solved.
  const Eigen::MatrixXd d2 = secondDifference(n);
  for (int kind = 0; kind < 2; ++kind) {
    const bool is_light = kind == 0;
    const auto& list = is_light ? palette.lights : palette.materials;
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].free) continue;
      const Eigen::VectorXd& s = is_light ? state.lights[i] : state.materials[i];
      const int off = offsetOf(is_light, static_cast<int>(i));  // −1: held, constant rows
      auto addLinear = [&](const Eigen::MatrixXd& m, double w, const Eigen::VectorXd& target) {
        if (w <= 0) return;
        const int r = rows.add(static_cast<int>(m.rows()));
        if (off >= 0)
          rows.a().block(r, off, m.rows(), n) = w * m;
        else
          rows.b().segment(r, m.rows()) -= w * (m * s);
        rows.b().segment(r, m.rows()) += w * target;
      };
      addLinear(d2, opt.smoothness, Eigen::VectorXd::Zero(d2.rows()));
      addLinear(Eigen::MatrixXd::Identity(n, n), opt.ridge, Eigen::VectorXd::Zero(n));
      // Luminance: weighted heavily, it fixes each free light's scale (relative colours do
      // not depend on it, so it only removes a degree of freedom).
      if (is_light)
        addLinear(cmf.col(1).transpose(), 10.0, Eigen::VectorXd::Constant(1, opt.light_luminance));
    }
  }
  rows.finish(&sys);
  return sys;
}

Eigen::VectorXd currentUnknowns(const DesignSystem& sys, const DesignState& state) {
  Eigen::VectorXd x(sys.a.cols());
  const auto& spectra = sys.block == DesignBlock::kLights ? state.lights : state.materials;
  for (std::size_t i = 0; i < sys.spectrum_offset.size(); ++i)
    if (sys.spectrum_offset[i] >= 0)
      x.segment(sys.spectrum_offset[i], spectra[i].size()) = spectra[i];
  for (std::size_t g = 0; g < state.metamer_colours.size(); ++g)
    x.segment<3>(sys.metamer_offset + 3 * g) = state.metamer_colours[g];
  return x;
}

void applyUnknowns(const DesignSystem& sys, const Eigen::VectorXd& x, DesignState* state) {
  auto& spectra = sys.block == DesignBlock::kLights ? state->lights : state->materials;
  for (std::size_t i = 0; i < sys.spectrum_offset.size(); ++i)
    if (sys.spectrum_offset[i] >= 0)
      spectra[i] = x.segment(sys.spectrum_offset[i], spectra[i].size());
  for (std::size_t g = 0; g < state->metamer_colours.size(); ++g)
    state->metamer_colours[g] = x.segment<3>(sys.metamer_offset + 3 * g);
}

double designObjective(const DesignPalette& palette, const CmfMatrix& cmf,
                       const DesignState& state) {
  const DesignSystem sys = buildDesignSystem(palette, cmf, state, DesignBlock::kMaterials);
  return (sys.a * currentUnknowns(sys, state) - sys.b).squaredNorm();
}

}  // namespace svr
