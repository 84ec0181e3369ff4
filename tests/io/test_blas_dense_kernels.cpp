// OpenBLAS's dense kernels for the sample fits (icobrdf/io/blas_dense_kernels.hpp) against Eigen's and
// against the definitions.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>

#include "icobrdf/core/dense_kernels.hpp"
#include "icobrdf/core/helmholtz_modes.hpp"
#include "icobrdf/core/sample_fit.hpp"
#include "icobrdf/io/blas_dense_kernels.hpp"
#include "tests/core/sample_pairs.hpp"
#include "tests/support/random_matrix.hpp"

namespace icobrdf {
namespace {

constexpr double kEps = 2.220446049250313e-16;
// Two summation orders of n products differ by at most 2 n eps times the sum of the absolute products.
constexpr double kOrderBoundFactor = 2.0;
// Factors and solutions of a matrix of condition ~1e2 (random designs) agree to about cond * k eps.
constexpr double kFactorTol = 1e-11;
// Fitted coefficients by two kernel sets: both solve the same normal equations of condition cond(A)^2 ~ 1e3
// and refine once against the samples, so they agree to ~cond * eps; 1e-10 leaves a wide margin.
constexpr double kFitTol = 1e-10;

using test_support::random_matrix;

TEST(BlasDenseKernels, RankUpdateAddsATransposeAOnTheLowerTriangle) {
  const DenseKernels& k = blas_dense_kernels();
  EXPECT_TRUE(k.threaded);
  // Big enough for OpenBLAS's blocked, threaded path; a strided block to exercise the leading dimension.
  const Eigen::MatrixXd a = random_matrix(700, 300, 1);
  Eigen::MatrixXd g = Eigen::MatrixXd::Constant(300, 300, 3.0);
  rank_update_lower(&k, g, a.middleRows(50, 600));
  const Eigen::MatrixXd block = a.middleRows(50, 600);
  const Eigen::MatrixXd abs_sum = block.cwiseAbs().transpose() * block.cwiseAbs();
  double worst = 0.0;
  for (Eigen::Index j = 0; j < 300; ++j)
    for (Eigen::Index i = 0; i < 300; ++i) {
      if (i < j) {
        ASSERT_EQ(g(i, j), 3.0) << "upper triangle changed at " << i << "," << j;
        continue;
      }
      const double err = std::abs(g(i, j) - 3.0 - block.col(i).dot(block.col(j)));
      worst = std::max(worst, err / (kOrderBoundFactor * 600 * kEps * (abs_sum(i, j) + 3.0)));
    }
  EXPECT_LE(worst, 1.0);
}

TEST(BlasDenseKernels, CholeskyMatchesEigensLlt) {
  const Eigen::MatrixXd a = random_matrix(900, 400, 2);
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::LLT<Eigen::MatrixXd> ref(g), ours = cholesky(&blas_dense_kernels(), g);
  ASSERT_EQ(ours.info(), Eigen::Success);
  const Eigen::MatrixXd l_ref = ref.matrixL(), l_ours = ours.matrixL();
  EXPECT_LT((l_ref - l_ours).cwiseAbs().maxCoeff(), kFactorTol * l_ref.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd b = random_matrix(400, 2, 3);
  EXPECT_LT((ours.solve(b) - ref.solve(b)).norm(), kFactorTol * ref.solve(b).norm());
  EXPECT_NEAR(ours.rcond(), ref.rcond(), 1e-9 * ref.rcond());
}

TEST(BlasDenseKernels, IndefiniteMatrixHasNoFactor) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Identity(6, 6);
  g(4, 4) = 0.0;
  EXPECT_EQ(cholesky(&blas_dense_kernels(), g).info(), Eigen::NumericalIssue);
}

TEST(BlasDenseKernels, SampleFitAgreesWithEigensKernels) {
  // Data in the span of the order-4 modes: both fits recover the same coefficients.
  const test::Pairs p = test::random_pairs(3000, 11);
  const Eigen::Index k = helmholtz_mode_count(4);
  const Eigen::VectorXd truth = random_matrix(k, 1, 12).col(0);
  const Eigen::MatrixXd y = helmholtz_modes_eval(4, p.wi, p.wr) * truth;
  SampleFitOptions o;
  o.order = 4;
  const SampleFitResult eigen_fit = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  o.kernels = &blas_dense_kernels();
  const SampleFitResult blas_fit = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  ASSERT_STREQ(blas_fit.solver, "normal equations");
  EXPECT_LT((blas_fit.modes - eigen_fit.modes).norm(), kFitTol * truth.norm());
  EXPECT_LT((blas_fit.modes.col(0) - truth).norm(), kFitTol * truth.norm());
  EXPECT_NEAR(blas_fit.condition, eigen_fit.condition, 1e-6 * eigen_fit.condition);
}

}  // namespace
}  // namespace icobrdf
