#include "spectral/bounded_least_squares.h"

#include <fmt/format.h>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <vector>

#include "base/error.h"

namespace svr {

Eigen::VectorXd solveLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  if (a.cols() == 0) return Eigen::VectorXd();
  return a.completeOrthogonalDecomposition().solve(b);
}

namespace {

enum class State { kFree, kLower, kUpper };

void checkInputs(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                 const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  const Eigen::Index n = a.cols();
  if (a.rows() != b.size() || lower.size() != n || upper.size() != n)
    throw Error(fmt::format("bounded least squares: A is {}×{}, b has {}, bounds have {} and {}",
                            a.rows(), n, b.size(), lower.size(), upper.size()));
  if (!a.allFinite() || !b.allFinite())
    throw Error("bounded least squares: A or b holds a non-finite value");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(lower[i] <= upper[i]) || std::isnan(lower[i]) || std::isnan(upper[i]))
      throw Error(fmt::format("bounded least squares: bounds of x[{}] are [{}, {}]", i, lower[i],
                              upper[i]));
}

}  // namespace

Eigen::VectorXd solveBoundedLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                         const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper,
                                         BoundedLsReport* report) {
  const Eigen::Index n = a.cols();
  checkInputs(a, b, lower, upper);
  if (a.rows() > n + 1) {
    // ‖A x − b‖² = ‖R x − c‖² + const with [A b] = Q [R c]: every later free-set solve then
    // works on n + 1 rows instead of all of them.
    Eigen::MatrixXd ab(a.rows(), n + 1);
    ab << a, b;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(ab);
    const Eigen::MatrixXd r =
        qr.matrixQR().topRows(n + 1).triangularView<Eigen::Upper>().toDenseMatrix();
    return solveBoundedLeastSquares(r.leftCols(n), r.col(n), lower, upper, report);
  }
  BoundedLsReport local;
  BoundedLsReport& rep = report ? *report : local;
  rep = {};

  // Start from the unconstrained minimiser clipped to the box: often it is already feasible,
  // and otherwise it is a good first free set.
  Eigen::VectorXd x = solveLeastSquares(a, b);
  std::vector<State> state(n, State::kFree);
  bool feasible = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (x[i] <= lower[i]) {
      feasible = feasible && x[i] == lower[i];
      x[i] = lower[i], state[i] = State::kLower;
    } else if (x[i] >= upper[i]) {
      feasible = feasible && x[i] == upper[i];
      x[i] = upper[i], state[i] = State::kUpper;
    }
  }
  if (feasible) {
    rep.unconstrained = rep.converged = true;
    return x;
  }

  const int max_iterations = static_cast<int>(10 * n + 50);
  Eigen::Index blocked = -1;  // a variable just freed that rounding sent the wrong way
  bool need_inner = true;     // the clipped start is not yet optimal over its free set
  for (rep.iterations = 0; rep.iterations < max_iterations; ++rep.iterations) {
    if (!need_inner) {
      // Kuhn–Tucker test: w = Aᵀ(b − A x) is minus half the gradient. A variable at its lower
      // bound with w > 0 (or at its upper with w < 0) would lower the objective if freed.
      const Eigen::VectorXd w = a.transpose() * (b - a * x);
      const double scale = (a.transpose() * b).cwiseAbs().maxCoeff() + 1e-300;
      Eigen::Index best = -1;
      double best_w = 1e-12 * scale;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (state[i] == State::kFree || i == blocked || lower[i] == upper[i]) continue;
        const double gain = state[i] == State::kLower ? w[i] : -w[i];
        if (gain > best_w) best_w = gain, best = i;
      }
      if (best < 0) {
        rep.converged = true;
        return x;
      }
      state[best] = State::kFree;
      blocked = best;  // kept only if the first inner step moves it the wrong way
    }
    need_inner = false;
    // Inner loop: solve over the free set with the bound variables held; step back to the box
    // when the solution leaves it, binding the variables that hit their bounds.
    for (bool first = true;; first = false) {
      std::vector<Eigen::Index> free;
      for (Eigen::Index i = 0; i < n; ++i)
        if (state[i] == State::kFree) free.push_back(i);
      if (free.empty()) break;
      Eigen::VectorXd rhs = b;
      for (Eigen::Index i = 0; i < n; ++i)
        if (state[i] != State::kFree) rhs -= a.col(i) * x[i];
      Eigen::MatrixXd af(a.rows(), static_cast<Eigen::Index>(free.size()));
      for (std::size_t f = 0; f < free.size(); ++f) af.col(f) = a.col(free[f]);
      const Eigen::VectorXd z = solveLeastSquares(af, rhs);
      double alpha = 1.0;
      Eigen::Index hit = -1;
      for (std::size_t f = 0; f < free.size(); ++f) {
        const Eigen::Index i = free[f];
        if (z[f] < lower[i] || z[f] > upper[i]) {
          const double bound = z[f] < lower[i] ? lower[i] : upper[i];
          const double t = (bound - x[i]) / (z[f] - x[i]);
          if (t < alpha) alpha = t, hit = i;
        }
      }
      if (hit < 0) {  // z is feasible: accept it
        for (std::size_t f = 0; f < free.size(); ++f) x[free[f]] = z[f];
        if (blocked >= 0 && state[blocked] == State::kFree) blocked = -1;
        break;
      }
      if (first && hit == blocked && alpha <= 0) {
        // Rounding made the newly freed variable want to leave through its own bound: put it
        // back and exclude it from the next Kuhn–Tucker pick (Stark & Parker, step 5).
        state[blocked] = x[blocked] <= lower[blocked] ? State::kLower : State::kUpper;
        break;
      }
      alpha = std::max(alpha, 0.0);
      for (std::size_t f = 0; f < free.size(); ++f) {
        const Eigen::Index i = free[f];
        x[i] += alpha * (z[f] - x[i]);
        const double eps = 1e-13 * (1.0 + std::abs(x[i]));
        if (i == hit || x[i] <= lower[i] + eps || x[i] >= upper[i] - eps) {
          if (x[i] - lower[i] <= upper[i] - x[i])
            x[i] = lower[i], state[i] = State::kLower;
          else
            x[i] = upper[i], state[i] = State::kUpper;
        }
      }
    }
  }
  return x;  // iteration cap: the best feasible point so far; report.converged says so
}

}  // namespace svr
