#pragma once
// Bounded-variable least squares: minimise ‖A x − b‖² subject to lower ≤ x ≤ upper (bounds
// may be ±infinity). Stark & Parker's BVLS (Computational Statistics 10, 1995), the active-set
// method scipy's lsq_linear(method="bvls") uses: it generalises Lawson–Hanson NNLS to two-sided
// bounds, terminates finitely, and returns the exact constrained minimiser (to rounding), which
// the bilinear design alternation relies on to never increase its objective. A general NLP
// library (NLopt's bounded L-BFGS, MMA) would stop at a tolerance instead. The sub-problems
// are small (a few hundred unknowns), so every free-set solve is a dense complete orthogonal
// decomposition (rank-deficient sets get the minimum-norm solution).

#include <Eigen/Core>

namespace svr {

struct BoundedLsReport {
  int iterations = 0;        // free-set changes
  bool converged = false;    // Kuhn–Tucker conditions met (else the iteration cap was hit)
  bool unconstrained = false;  // the unconstrained minimiser already lay within the bounds
};

// Throws svr::Error for mismatched sizes, lower > upper or non-finite A, b.
Eigen::VectorXd solveBoundedLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                         const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper,
                                         BoundedLsReport* report = nullptr);

// The unconstrained minimum-norm least-squares solution (complete orthogonal decomposition).
Eigen::VectorXd solveLeastSquares(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

}  // namespace svr
