#include "icobrdf/core/fit/lanczos.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {

// Below this many steps the Ritz pair is checked after every step; beyond it every kLanczosCheckEvery steps
// (the tridiagonal eigenproblem costs O(j^3), which at a few hundred steps rivals one application of A).
constexpr int kLanczosCheckAlways = 64;
constexpr int kLanczosCheckEvery = 8;

// The largest eigenvalue of the leading j x j part of T (diagonal a, off-diagonal b) and the last entry of its
// unit eigenvector.
void ritz(const std::vector<double>& a, const std::vector<double>& b, int j, double& theta, double& last) {
  Eigen::VectorXd d(j), e(std::max(j - 1, 0));
  for (int i = 0; i < j; ++i) d[i] = a[static_cast<size_t>(i)];
  for (int i = 0; i + 1 < j; ++i) e[i] = b[static_cast<size_t>(i)];
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
  es.computeFromTridiagonal(d, e, Eigen::ComputeEigenvectors);
  theta = es.eigenvalues()[j - 1];  // ascending
  last = es.eigenvectors()(j - 1, j - 1);
}

}  // namespace

LanczosEstimate lanczos_largest_eigenvalue(const SymmetricOperator& apply, const Eigen::VectorXd& start,
                                           double relative_tolerance, int max_steps) {
  const Eigen::Index n = start.size();
  if (!(relative_tolerance > 0.0 && relative_tolerance < 1.0))
    throw ArgumentError("lanczos: relative tolerance must be in (0, 1), got " + std::to_string(relative_tolerance));
  if (max_steps < 1) throw ArgumentError("lanczos: max_steps must be >= 1, got " + std::to_string(max_steps));
  LanczosEstimate out;
  if (n == 0) {
    out.converged = true;
    return out;
  }
  const double start_norm = start.norm();
  if (!(start_norm > 0.0) || !std::isfinite(start_norm))
    throw ArgumentError("lanczos: the start vector must be finite and not zero, norm " + std::to_string(start_norm));
  const int steps = static_cast<int>(std::min<Eigen::Index>(n, max_steps));
  Eigen::MatrixXd v(n, steps + 1);
  v.col(0) = start / start_norm;
  std::vector<double> alpha, beta;
  Eigen::VectorXd w(n);
  for (int j = 0; j < steps; ++j) {
    apply(v.col(j), w);
    if (w.size() != n) throw ArgumentError("lanczos: the operator returned " + std::to_string(w.size()) + " values, expected " + std::to_string(n));
    alpha.push_back(0.0);  // v_j^T A v_j: the v_j parts of the two projections below
    // Full reorthogonalization, twice ("twice is enough", Parlett): V_j stays orthonormal to rounding, so T_j
    // holds no spurious copies of converged eigenvalues.
    for (int pass = 0; pass < 2; ++pass) {
      const Eigen::VectorXd h = v.leftCols(j + 1).transpose() * w;
      w.noalias() -= v.leftCols(j + 1) * h;
      alpha.back() += h[j];
    }
    const double b = w.norm();
    beta.push_back(b);
    out.steps = j + 1;
    const bool last_step = j + 1 == steps;
    const bool invariant = !(b > 0.0);
    if (invariant || last_step || j < kLanczosCheckAlways || (j + 1) % kLanczosCheckEvery == 0) {
      double theta = 0.0, s_last = 0.0;
      ritz(alpha, beta, j + 1, theta, s_last);
      out.value = theta;
      out.residual = invariant ? 0.0 : b * std::abs(s_last);
      if (invariant || out.residual <= relative_tolerance * std::abs(theta) || j + 1 == n) {  // n steps: T_n holds A's spectrum
        out.converged = true;
        return out;
      }
    }
    if (invariant) break;
    v.col(j + 1) = w / b;
  }
  return out;
}

}  // namespace icobrdf
