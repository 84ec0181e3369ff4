// The Lanczos estimate of the largest eigenvalue (icobrdf/core/fit/lanczos.hpp), on operators whose spectrum is
// set by construction (A = Q diag(lambda) Q^T with Q orthogonal), so every expected value is exact.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/fit/lanczos.hpp"
#include "tests/support/random_matrix.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr double kEps = 2.220446049250313e-16;
// Forming Q diag(lambda) Q^T and applying it perturbs the eigenvalues by about n eps lambda_max (Weyl); 1e3 eps
// covers n = 400 with a margin.
constexpr double kConstructionTol = 1e3 * kEps;
// The Lanczos process must beat the power method by far on a spectrum whose top gap is 1%: power iteration
// needs ln(1e-6) / ln(0.99) ~ 1,400 steps for a 1e-6 Rayleigh quotient there; Chebyshev acceleration gives
// a few hundred at most, and one hundred or so in practice.
constexpr int kStepsForOnePercentGap = 250;
// Solving with the Cholesky factor of a matrix of condition 1e8 and size 200 is accurate to cond * n eps
// relative (backward-stable solve, forward error bounded by the condition).
constexpr double kInverseSolveTol = 1e8 * 200 * kEps;
// A 3 x 3 tridiagonal eigenproblem and three orthogonalizations of exact small integers: a few roundings.
constexpr double kSmallExactTol = 10 * kEps;

using test_support::random_matrix;

// Q diag(lambda) Q^T for a random orthogonal Q (the Q factor of a random matrix).
Eigen::MatrixXd with_spectrum(const Eigen::VectorXd& lambda, unsigned seed) {
  const Eigen::Index n = lambda.size();
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(random_matrix(n, n, seed)).householderQ();
  return q * lambda.asDiagonal() * q.transpose();
}

SymmetricOperator times(const Eigen::MatrixXd& a) {
  return [&a](const Eigen::VectorXd& v, Eigen::VectorXd& out) { out.noalias() = a * v; };
}

// lambda_k = 10^(-8 k / (n - 1)): eigenvalues from 1 down to 1e-8, evenly spaced in the logarithm.
Eigen::VectorXd geometric(Eigen::Index n) {
  Eigen::VectorXd l(n);
  for (Eigen::Index k = 0; k < n; ++k) l[k] = std::pow(10.0, -8.0 * static_cast<double>(k) / static_cast<double>(n - 1));
  return l;
}

TEST(Lanczos, LargestEigenvalueWithinTheResidualBound) {
  for (double tol : {1e-4, 1e-8}) {
    const Eigen::MatrixXd a = with_spectrum(geometric(300), 1);
    const LanczosEstimate e = lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::LinSpaced(300, 1.0, 2.0), tol, 300);
    ASSERT_TRUE(e.converged) << "tolerance " << tol << ", " << e.steps << " steps";
    EXPECT_LE(e.residual, tol * e.value);
    // Some eigenvalue lies within the residual of the Ritz value, and the Ritz value never exceeds lambda_max.
    EXPECT_LE(std::abs(e.value - 1.0), e.residual + kConstructionTol) << "tolerance " << tol;
    EXPECT_LE(e.value, 1.0 + kConstructionTol);
  }
}

TEST(Lanczos, SmallestEigenvalueThroughTheInverseAtConditionOneHundredMillion) {
  const Eigen::MatrixXd a = with_spectrum(geometric(200), 2);
  const Eigen::LLT<Eigen::MatrixXd> llt(a);
  ASSERT_EQ(llt.info(), Eigen::Success);
  const SymmetricOperator inverse = [&llt](const Eigen::VectorXd& v, Eigen::VectorXd& out) { out = llt.solve(v); };
  const double tol = 1e-6;
  const LanczosEstimate e = lanczos_largest_eigenvalue(inverse, Eigen::VectorXd::LinSpaced(200, 2.0, 1.0), tol, 200);
  ASSERT_TRUE(e.converged);
  // 1 / lambda_min = 1e8, within the Lanczos tolerance plus the solves' rounding.
  EXPECT_NEAR(1.0 / e.value, 1e-8, 1e-8 * (tol + kInverseSolveTol));
}

TEST(Lanczos, ClusteredTopNeedsFarFewerStepsThanThePowerMethod) {
  // lambda = 1, 0.99, 0.98, ... , 0.01 and a tail: the top gap is 1% of lambda_max.
  Eigen::VectorXd l(400);
  for (Eigen::Index k = 0; k < 400; ++k) l[k] = std::max(1.0 - 0.01 * static_cast<double>(k), 1e-3);
  const Eigen::MatrixXd a = with_spectrum(l, 3);
  const double tol = 1e-6;
  const LanczosEstimate e = lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::LinSpaced(400, 1.0, 2.0), tol, 400);
  ASSERT_TRUE(e.converged);
  EXPECT_LE(e.steps, kStepsForOnePercentGap);
  EXPECT_LE(std::abs(e.value - 1.0), e.residual + kConstructionTol);
}

TEST(Lanczos, InvariantSubspaceGivesTheExactValueAndStops) {
  // diag(5, 3, 2, 0, ..., 0) started in the span of the first three axes: three steps, exact.
  Eigen::VectorXd d = Eigen::VectorXd::Zero(50);
  d.head(3) << 5.0, 3.0, 2.0;
  const Eigen::MatrixXd a = d.asDiagonal();
  Eigen::VectorXd start = Eigen::VectorXd::Zero(50);
  start.head(3) << 1.0, 1.0, 1.0;
  const LanczosEstimate e = lanczos_largest_eigenvalue(times(a), start, 1e-12, 50);
  EXPECT_TRUE(e.converged);
  EXPECT_EQ(e.steps, 3);
  EXPECT_NEAR(e.value, 5.0, kSmallExactTol * 5.0);
  // The zero operator: one step, value 0.
  const Eigen::MatrixXd z = Eigen::MatrixXd::Zero(10, 10);
  const LanczosEstimate ez = lanczos_largest_eigenvalue(times(z), Eigen::VectorXd::Ones(10), 1e-6, 10);
  EXPECT_TRUE(ez.converged);
  EXPECT_EQ(ez.steps, 1);
  EXPECT_EQ(ez.value, 0.0);
}

TEST(Lanczos, StepLimitIsReportedAsNotConverged) {
  const Eigen::MatrixXd a = with_spectrum(geometric(100), 4);
  const LanczosEstimate e = lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::LinSpaced(100, 1.0, 2.0), 1e-12, 2);
  EXPECT_FALSE(e.converged);
  EXPECT_EQ(e.steps, 2);
  EXPECT_LE(e.value, 1.0 + kConstructionTol);  // a Ritz value: inside the spectrum
  EXPECT_GT(e.residual, 1e-12 * e.value);
}

TEST(Lanczos, BadArgumentsAreRefused) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(4, 4);
  EXPECT_THROW(lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::Zero(4), 1e-6, 4), ArgumentError);
  EXPECT_THROW(lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::Ones(4), 0.0, 4), ArgumentError);
  EXPECT_THROW(lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::Ones(4), 1.0, 4), ArgumentError);
  EXPECT_THROW(lanczos_largest_eigenvalue(times(a), Eigen::VectorXd::Ones(4), 1e-6, 0), ArgumentError);
  const SymmetricOperator wrong = [](const Eigen::VectorXd&, Eigen::VectorXd& out) { out = Eigen::VectorXd::Ones(3); };
  EXPECT_THROW(lanczos_largest_eigenvalue(wrong, Eigen::VectorXd::Ones(4), 1e-6, 4), ArgumentError);
  // n = 0: nothing to estimate.
  EXPECT_TRUE(lanczos_largest_eigenvalue(times(a), Eigen::VectorXd(), 1e-6, 4).converged);
}

}  // namespace
}  // namespace icobrdf
