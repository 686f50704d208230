#include "spectral/product_objective.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace svr {

ProductObjective::ProductObjective(const Observer& observer, const TrainingSet& set,
                                   const Eigen::MatrixXd& b0, const Eigen::MatrixXd& p0,
                                   LightMatrixKind light_matrix)
    : k_(static_cast<int>(b0.cols())),
      depths_(set.depths),
      full_(light_matrix == LightMatrixKind::kFull) {
  const int n_all = static_cast<int>(set.reflectances.size());
  const int n = std::min(n_all, kMaxSamples);
  const int nl = static_cast<int>(set.lights.size());
  const int n_grid = static_cast<int>(b0.rows());
  Eigen::MatrixXd lights(n_grid, nl), refl(n_grid, n), absorb(n_grid, n);
  for (int l = 0; l < nl; ++l) lights.col(l) = set.lights[l].values();
  for (int j = 0; j < n; ++j) {
    const int src = static_cast<int>(static_cast<long>(j) * n_all / n);
    refl.col(j) = set.reflectances[src].values();
    absorb.col(j) = set.absorbers.empty() ? set.reflectances[src].values()
                                          : set.absorbers[src].values();
  }
  if (set.absorbers.empty()) depths_.clear();
  const auto& cmf = observer.weightedCmf();
  al_ = p0 * lights;
  ar_ = p0 * refl;
  at_ = p0 * absorb;
  a1_ = p0 * Eigen::VectorXd::Ones(n_grid);
  cb_ = cmf.transpose() * b0;
  for (int l = 0; l < nl; ++l)
    cb_light_.push_back(cmf.transpose() * lights.col(l).asDiagonal() * b0);
  whites_ = cmf.transpose() * lights;  // Y = 1 for unit-luminance lights
  const int cases = 1 + static_cast<int>(depths_.size());
  for (int c = 0; c < cases; ++c) {
    const Eigen::MatrixXd trans = c == 0 ? Eigen::MatrixXd::Ones(n_grid, n)
                                         : Eigen::MatrixXd(absorb.array().pow(depths_[c - 1]));
    for (int l = 0; l < nl; ++l)
      for (int j = 0; j < n; ++j) {
        const Eigen::VectorXd filtered = lights.col(l).cwiseProduct(trans.col(j));
        const double y = cmf.col(1).dot(filtered);
        if (c > 0 && !(y >= kVisibleDepthY)) continue;
        const double scale = c == 0 ? 1.0 : 1.0 / y;
        const Xyz xyz = cmf.transpose() * filtered.cwiseProduct(refl.col(j)) * scale;
        products_.push_back({c, l, j, scale, xyzToLab(xyz, whites_.col(l))});
      }
  }
  n_ = n;
}

struct ProductObjective::State {
  Eigen::MatrixXd ti;                // T⁻¹
  Eigen::VectorXd w;                 // white coefficients before normalisation: T⁻¹·P0·1
  Eigen::MatrixXd cl, cr, ct_raw;    // P·L, P·R, P·t (k × lights, reflectances, absorbers)
  Eigen::MatrixXd ct;                // P·t clamped to [0, 1]
  std::vector<Eigen::MatrixXd> ctm;  // ct^m per depth
  std::vector<Eigen::MatrixXd> g;    // cb·T: one (projected) or per light (full)
};

bool ProductObjective::makeState(const Eigen::VectorXd& theta, State& s) const {
  const Eigen::Map<const Eigen::MatrixXd> t(theta.data(), k_, k_);
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(t);
  if (!(std::abs(lu.determinant()) > 1e-14)) return false;
  s.ti = lu.inverse();
  s.w = s.ti * a1_;
  if (!s.w.allFinite() || s.w.cwiseAbs().minCoeff() < 1e-9) return false;
  // A T whose colours cancel is as unusable as a singular one (kMaxCancellation).
  if (!(toXyzCancellation(cb_ * t * s.w.asDiagonal()) <= kMaxCancellation)) return false;
  const Eigen::VectorXd inv_w = s.w.cwiseInverse();
  s.cl = inv_w.asDiagonal() * (s.ti * al_);
  s.cr = inv_w.asDiagonal() * (s.ti * ar_);
  s.ct_raw = inv_w.asDiagonal() * (s.ti * at_);
  s.ct = s.ct_raw.cwiseMax(0.0).cwiseMin(1.0);
  s.ctm.clear();
  for (int m : depths_) s.ctm.emplace_back(s.ct.array().pow(m));
  s.g.clear();
  if (full_)
    for (const auto& cbl : cb_light_) s.g.push_back(cbl * t);
  else
    s.g.push_back(cb_ * t);
  return true;
}

// With v = T⁻¹ e_a and u = T⁻¹ x, ∂u/∂T_ab = −v·u_b; the normalised coefficients c = u / w then
// move by −w_b (v / w) ⊙ (c_b − c), and M = cb·T·diag(w) by w_b (cb_a e_bᵀ − cb·T·diag(v)).
// Collecting the product rule over q = cl ⊙ cr ⊙ ct^m, with X = cr ⊙ ct^m, Y = cl ⊙ ct^m,
// D = m·ct^(m−1) ⊙ cl ⊙ cr where ct is not clamped, and Z = q + ct ⊙ D (full: no cl, Z = ct ⊙ D):
//   ∂pred/∂T_ab = w_b [cb_a q_b − G·diag(v)(cl_b X + cr_b Y + ct_b D − Z)],  G = cb·T,
// so all k columns of one b come from four 3×k products G·diag(·)·T⁻¹.
void ProductObjective::productJacobian(const State& s, const Product& p, const Eigen::VectorXd& q,
                                       const Xyz& xyz, Eigen::Ref<Eigen::MatrixXd> rows) const {
  const int k = k_;
  const bool deep = p.c > 0;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(k);
  const Eigen::VectorXd cl = full_ ? ones : Eigen::VectorXd(s.cl.col(p.l));
  const Eigen::VectorXd cr = s.cr.col(p.j);
  const Eigen::VectorXd ctm = deep ? Eigen::VectorXd(s.ctm[p.c - 1].col(p.j)) : ones;
  Eigen::VectorXd d = Eigen::VectorXd::Zero(k);
  if (deep) {
    const int m = depths_[p.c - 1];
    for (int i = 0; i < k; ++i) {
      const double t = s.ct_raw(i, p.j);
      if (t > 0.0 && t < 1.0) d[i] = m * ctm[i] / t * cl[i] * cr[i];
    }
  }
  const Eigen::VectorXd z =
      (full_ ? Eigen::VectorXd::Zero(k) : q) + s.ct_raw.col(p.j).cwiseProduct(d);
  const Eigen::MatrixXd& g = s.g[full_ ? p.l : 0];
  const Eigen::MatrixXd& cb = full_ ? cb_light_[p.l] : cb_;
  const Eigen::Matrix3d a = labJacobian(xyz, whites_.col(p.l)) * p.scale;
  const Eigen::MatrixXd ag = a * g;
  const Eigen::MatrixXd a_cb = a * cb;
  auto through = [&](const Eigen::VectorXd& x) {
    return Eigen::MatrixXd(ag * x.asDiagonal() * s.ti);
  };
  const Eigen::MatrixXd px = full_ ? Eigen::MatrixXd() : through(cr.cwiseProduct(ctm));
  const Eigen::MatrixXd py = through(cl.cwiseProduct(ctm));
  const Eigen::MatrixXd pd = deep ? through(d) : Eigen::MatrixXd();
  const Eigen::MatrixXd pz = through(z);
  for (int b = 0; b < k; ++b) {
    auto block = rows.middleCols(b * k, k);
    block = q[b] * a_cb - cr[b] * py + pz;
    if (!full_) block -= cl[b] * px;
    if (deep) block -= s.ct_raw(b, p.j) * pd;
    block *= s.w[b];
  }
}

bool ProductObjective::evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& r,
                                Eigen::MatrixXd* jacobian) const {
  State s;
  if (!makeState(theta, s)) return false;
  r.resize(residuals());
  if (jacobian) jacobian->setZero(residuals(), parameters());
  const int count = static_cast<int>(products_.size());
  // Rows are independent, so the result is the same for any thread count.
#pragma omp parallel for schedule(static) if (jacobian)
  for (int i = 0; i < count; ++i) {
    const Product& p = products_[i];
    Eigen::VectorXd q = s.cr.col(p.j);
    if (!full_) q = q.cwiseProduct(s.cl.col(p.l));
    if (p.c > 0) q = q.cwiseProduct(s.ctm[p.c - 1].col(p.j));
    const Eigen::MatrixXd& g = s.g[full_ ? p.l : 0];
    const Xyz xyz = g * s.w.cwiseProduct(q) * p.scale;
    r.segment<3>(3 * i) = xyzToLab(xyz, whites_.col(p.l)) - p.exact;
    if (jacobian) productJacobian(s, p, q, xyz, jacobian->middleRows(3 * i, 3));
  }
  // The hinge on reflectance coefficients: ∂c_i/∂T_ab = −w_b (T⁻¹_ia / w_i)(c_b − c_i).
  int row = 3 * count;
  for (int j = 0; j < s.cr.cols(); ++j)
    for (int i = 0; i < k_; ++i, ++row) {
      const double c = s.cr(i, j);
      const double excess = c < kCoeffLo ? c - kCoeffLo : (c > kCoeffHi ? c - kCoeffHi : 0.0);
      r[row] = kBoundWeight * std::abs(excess);
      if (!jacobian || excess == 0.0) continue;
      const double sign = excess < 0.0 ? -1.0 : 1.0;
      for (int b = 0; b < k_; ++b)
        for (int a = 0; a < k_; ++a)
          (*jacobian)(row, a + b * k_) =
              -kBoundWeight * sign * s.w[b] * s.ti(i, a) / s.w[i] * (s.cr(b, j) - c);
    }
  return r.allFinite() && (!jacobian || jacobian->allFinite());
}

double ProductObjective::cost(const Eigen::VectorXd& r) const {
  constexpr double c2 = kRobustScale * kRobustScale;
  const int count = static_cast<int>(products_.size());
  double sum = 0.0;
  for (int i = 0; i < count; ++i)
    sum += 2.0 * c2 * (std::sqrt(1.0 + r.segment<3>(3 * i).squaredNorm() / c2) - 1.0);
  return sum + r.tail(r.size() - 3 * count).squaredNorm();
}

void ProductObjective::reweigh(Eigen::VectorXd& r, Eigen::MatrixXd& jacobian) const {
  constexpr double c2 = kRobustScale * kRobustScale;
  for (int i = 0; i < static_cast<int>(products_.size()); ++i) {
    const double root = std::pow(1.0 + r.segment<3>(3 * i).squaredNorm() / c2, -0.25);
    r.segment<3>(3 * i) *= root;
    jacobian.middleRows(3 * i, 3) *= root;
  }
}

double ProductObjective::value(const Eigen::MatrixXd& t) const {
  const Eigen::VectorXd theta = Eigen::Map<const Eigen::VectorXd>(t.data(), t.size());
  Eigen::VectorXd r;
  return evaluate(theta, r) ? cost(r) : std::numeric_limits<double>::infinity();
}

}  // namespace svr
