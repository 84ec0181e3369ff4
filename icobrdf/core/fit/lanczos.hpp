#pragma once
// The largest eigenvalue of a symmetric positive semi-definite operator known only by its action, by the
// Lanczos process with full reorthogonalization (Golub & Van Loan, Matrix Computations, 4th ed., 10.1).
//
// The operator is n x n and given by apply(v, out): out = A v (v and out are vectors of length n, out is
// resized by the caller's callback if needed). After j steps the Krylov basis V_j is orthonormal (every new
// vector is orthogonalized against all earlier ones, twice), T_j = V_j^T A V_j is tridiagonal, and its largest
// eigenvalue theta (the Ritz value) never exceeds lambda_max(A) and rises to it with j. The Ritz pair's
// residual is r = beta_j |s_j| (s_j: last entry of the Ritz vector); some eigenvalue of A lies in
// [theta - r, theta + r] (Golub & Van Loan, Theorem 10.1.4 with Theorem 8.1.15's residual bound), and for the
// extreme Ritz value that eigenvalue is lambda_max in practice (Kaniel-Paige: the extremes converge first).
// The process stops when r <= relative_tolerance * theta, when beta_j vanishes (V_j spans an invariant
// subspace, theta is exact), after n steps, or after max_steps steps (converged = false; theta is then
// still a lower bound of lambda_max).
//
// Cost per step: one application of A plus O(n j) for the reorthogonalization; memory n x (steps + 1)
// doubles. Convergence of the extreme Ritz value goes with the square root of the relative gap (Chebyshev),
// against the gap itself for the power method: tens of steps where power iteration needs hundreds.
// Deterministic: the start vector is fixed by the caller, and the arithmetic does not depend on threads.
#include <Eigen/Core>

#include <functional>

namespace icobrdf {

struct LanczosEstimate {
  double value = 0.0;     // theta: the largest Ritz value (0 for a zero operator or n = 0)
  double residual = 0.0;  // r = beta_j |s_j| at the last step
  int steps = 0;          // applications of A
  bool converged = false; // r <= relative_tolerance * theta, an invariant subspace, or n steps
};

using SymmetricOperator = std::function<void(const Eigen::VectorXd& v, Eigen::VectorXd& out)>;

// start: the first Lanczos vector up to scale (length n, not zero, any direction with a component along the
// top eigenvector). ArgumentError for a start of the wrong length or zero norm, relative_tolerance outside
// (0, 1), or max_steps < 1.
LanczosEstimate lanczos_largest_eigenvalue(const SymmetricOperator& apply, const Eigen::VectorXd& start,
                                           double relative_tolerance, int max_steps);

}  // namespace icobrdf
