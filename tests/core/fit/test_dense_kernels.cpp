// The dense kernels of the sample fits (icobrdf/core/fit/dense_kernels.hpp): Eigen's, and the Eigen::LLT built
// from a factor computed elsewhere.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/core/support/error.hpp"
#include "tests/support/random_matrix.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr double kEps = 2.220446049250313e-16;
// A sum of n products of values in [-1, 1] differs between two summation orders by at most 2 n eps times
// the sum of the absolute products (standard forward error bound, gamma_n for each order).
constexpr double kOrderBoundFactor = 2.0;
// Two Cholesky factors of a matrix of condition ~1e2 agree entrywise to about cond * k eps; 1e-11 leaves
// a margin of ~50 over that at k = 60.
constexpr double kFactorTol = 1e-11;
// rcond is Eigen's L1-norm estimate of ||G^-1||: a few solves with the factor, each adding the factor's
// rounding, so two factors agreeing to kFactorTol give estimates agreeing to ~100 kFactorTol.
constexpr double kRcondTol = 100 * kFactorTol;

using test_support::random_matrix;

// A right-looking, unblocked Cholesky written out (L_jj = sqrt(G_jj - sum_k L_jk^2), ...): an independent
// stand-in for an optimized LAPACK, to check how cholesky() wraps a foreign factor.
bool textbook_cholesky(double* g, Eigen::Index k) {
  Eigen::Map<Eigen::MatrixXd> a(g, k, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    double d = a(j, j);
    for (Eigen::Index p = 0; p < j; ++p) d -= a(j, p) * a(j, p);
    if (!(d > 0.0)) return false;
    a(j, j) = std::sqrt(d);
    for (Eigen::Index i = j + 1; i < k; ++i) {
      double s = a(i, j);
      for (Eigen::Index p = 0; p < j; ++p) s -= a(i, p) * a(j, p);
      a(i, j) = s / a(j, j);
    }
  }
  return true;
}

const DenseKernels kTextbook{"textbook", eigen_dense_kernels().rank_update, &textbook_cholesky, false};

// G = 7 + A^T A on the lower triangle within the summation-order bound, the strict upper triangle untouched.
void expect_rank_update_of(const Eigen::MatrixXd& a) {
  const Eigen::Index k = a.cols(), n = a.rows();
  Eigen::MatrixXd g = Eigen::MatrixXd::Constant(k, k, 7.0);
  rank_update_lower(nullptr, g, a);
  const Eigen::MatrixXd abs_sum = a.cwiseAbs().transpose() * a.cwiseAbs();
  for (Eigen::Index j = 0; j < k; ++j)
    for (Eigen::Index i = 0; i < k; ++i) {
      if (i < j) {
        ASSERT_EQ(g(i, j), 7.0) << "upper triangle changed at " << i << "," << j;
        continue;
      }
      const double exact = 7.0 + a.col(i).dot(a.col(j));
      ASSERT_NEAR(g(i, j), exact, kOrderBoundFactor * static_cast<double>(n) * kEps * (abs_sum(i, j) + 7.0)) << i << "," << j;
    }
}

TEST(DenseKernels, EigenRankUpdateAddsATransposeAOnTheLowerTriangleOnly) { expect_rank_update_of(random_matrix(300, 40, 1)); }

// 450 columns: two full column blocks of the parallel update and a short last one (icobrdf/core/fit/dense_kernels.cpp),
// 500 rows x 450^2 / 2 multiply-adds: above the parallel threshold. The result must not depend on the threads.
TEST(DenseKernels, EigenRankUpdateInColumnBlocksOnAllThreads) {
  const Eigen::MatrixXd a = random_matrix(500, 450, 6);
  expect_rank_update_of(a);
  const int saved = omp_get_max_threads();
  Eigen::MatrixXd one = Eigen::MatrixXd::Zero(450, 450), many = one;
  omp_set_num_threads(1);
  rank_update_lower(nullptr, one, a);
  omp_set_num_threads(std::max(2, saved));
  rank_update_lower(nullptr, many, a);
  omp_set_num_threads(saved);
  EXPECT_EQ((one - many).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DenseKernels, RankUpdateOfAStridedBlockUsesOnlyItsRows) {
  const Eigen::MatrixXd a = random_matrix(100, 12, 2);
  Eigen::MatrixXd g1 = Eigen::MatrixXd::Zero(12, 12), g2 = Eigen::MatrixXd::Zero(12, 12);
  rank_update_lower(nullptr, g1, a.middleRows(30, 50));
  const Eigen::MatrixXd copy = a.middleRows(30, 50);
  rank_update_lower(nullptr, g2, copy);
  EXPECT_EQ((g1 - g2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DenseKernels, ShapeMismatchIsRefused) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(5, 5);
  EXPECT_THROW(rank_update_lower(nullptr, g, Eigen::MatrixXd::Zero(10, 4)), ArgumentError);
  EXPECT_THROW(cholesky(nullptr, Eigen::MatrixXd::Zero(3, 4)), ArgumentError);
}

TEST(DenseKernels, AForeignFactorBehavesAsEigensLlt) {
  const Eigen::MatrixXd a = random_matrix(400, 60, 3);
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::LLT<Eigen::MatrixXd> ref(g);
  const Eigen::LLT<Eigen::MatrixXd> ours = cholesky(&kTextbook, g);
  ASSERT_EQ(ours.info(), Eigen::Success);
  const Eigen::MatrixXd l_ref = ref.matrixL(), l_ours = ours.matrixL();
  EXPECT_LT((l_ref - l_ours).cwiseAbs().maxCoeff(), kFactorTol * l_ref.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd b = random_matrix(60, 3, 4);
  const Eigen::MatrixXd x_ref = ref.solve(b), x = ours.solve(b);
  EXPECT_LT((x - x_ref).norm(), kFactorTol * x_ref.norm());
  // rcond: the same L1 norm of G and the same estimator on the same factor (to rounding).
  EXPECT_NEAR(ours.rcond(), ref.rcond(), kRcondTol * ref.rcond());
}

TEST(DenseKernels, AForeignFactorOfAnIndefiniteMatrixReportsNumericalIssue) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Identity(4, 4);
  g(2, 2) = -1.0;
  EXPECT_EQ(cholesky(&kTextbook, g).info(), Eigen::NumericalIssue);
  EXPECT_EQ(cholesky(nullptr, g).info(), Eigen::NumericalIssue);
}

TEST(DenseKernels, TheProcessWideDefaultIsEigensUntilAnotherIsInstalled) {
  EXPECT_EQ(&default_dense_kernels(), &eigen_dense_kernels());
  set_default_dense_kernels(&kTextbook);
  EXPECT_EQ(&default_dense_kernels(), &kTextbook);
  set_default_dense_kernels(nullptr);  // restores Eigen's (and leaves the process as the other tests expect it)
  EXPECT_EQ(&default_dense_kernels(), &eigen_dense_kernels());
}

// 500 unknowns: three panels of the blocked factorization (192, 192, 116) with the parallel trailing update,
// against Eigen's LLT within kFactorTol (cond(G) ~ 21 for a random 1200 x 500 A, so cond * k * eps ~ 2.3e-12), and
// 1 thread = 2 threads bitwise.
TEST(DenseKernels, EigensBlockedCholeskyOfSeveralPanels) {
  const Eigen::MatrixXd a = random_matrix(1200, 500, 7);
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::LLT<Eigen::MatrixXd> ref(g);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const Eigen::LLT<Eigen::MatrixXd> one = cholesky(nullptr, g);
  omp_set_num_threads(std::max(2, saved));
  const Eigen::LLT<Eigen::MatrixXd> many = cholesky(nullptr, g);
  omp_set_num_threads(saved);
  ASSERT_EQ(many.info(), Eigen::Success);
  const Eigen::MatrixXd l_ref = ref.matrixL(), l_one = one.matrixL(), l_many = many.matrixL();
  EXPECT_LT((l_ref - l_many).cwiseAbs().maxCoeff(), kFactorTol * l_ref.cwiseAbs().maxCoeff());
  EXPECT_EQ((l_one - l_many).cwiseAbs().maxCoeff(), 0.0);
  const Eigen::MatrixXd b = random_matrix(500, 2, 8);
  EXPECT_LT((many.solve(b) - ref.solve(b)).norm(), kFactorTol * ref.solve(b).norm());
  EXPECT_NEAR(many.rcond(), ref.rcond(), kRcondTol * ref.rcond());
  // An indefinite matrix beyond the first panel is reported, not factored.
  Eigen::MatrixXd bad = g;
  bad(400, 400) = -1.0;
  EXPECT_EQ(cholesky(nullptr, bad).info(), Eigen::NumericalIssue);
}

TEST(DenseKernels, EigensCholeskyIsEigensLlt) {
  const Eigen::MatrixXd a = random_matrix(50, 8, 5);
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::MatrixXd l1 = cholesky(nullptr, g).matrixL(), l2 = Eigen::LLT<Eigen::MatrixXd>(g).matrixL();
  EXPECT_EQ((l1 - l2).cwiseAbs().maxCoeff(), 0.0);
}

// Single precision: a Cholesky factor's backward error is at most ~(k + 1) u ||G|| (Higham, "Accuracy and
// Stability", thm. 10.3; u = 2^-24 for float), so ||L L^T - G||_max <= 2 (k + 1) u max|G| leaves a factor 2.
constexpr double kFloatRoundoff = 0x1p-24;

TEST(DenseKernels, SingleBlockedCholeskyOfSeveralPanelsHasItsBackwardError) {
  const int k = 500;
  const Eigen::MatrixXd a = random_matrix(1200, k, 9);
  const Eigen::MatrixXf g = (a.transpose() * a).cast<float>();
  const Eigen::LLT<Eigen::MatrixXf> f = cholesky(Eigen::MatrixXf(g));
  ASSERT_EQ(f.info(), Eigen::Success);
  const Eigen::MatrixXd l = Eigen::MatrixXf(f.matrixL()).cast<double>();
  const Eigen::MatrixXd gd = g.cast<double>();
  EXPECT_LE((l * l.transpose() - gd).cwiseAbs().maxCoeff(), 2.0 * (k + 1) * kFloatRoundoff * gd.cwiseAbs().maxCoeff());
  EXPECT_GT(f.rcond(), 0.0f);
  Eigen::MatrixXf bad = g;
  bad(400, 400) = -1.0f;
  EXPECT_EQ(cholesky(bad).info(), Eigen::NumericalIssue);
  EXPECT_THROW(cholesky(Eigen::MatrixXf::Zero(3, 4)), ArgumentError);
}

TEST(DenseKernels, SingleRankUpdateIsTheProductInFloat) {
  const Eigen::MatrixXd a = random_matrix(300, 250, 10);
  const Eigen::MatrixXf af = a.cast<float>();
  Eigen::MatrixXf g = Eigen::MatrixXf::Zero(250, 250);
  rank_update_lower(g, af);
  const Eigen::MatrixXd exact = af.cast<double>().transpose() * af.cast<double>();
  // Sums of 300 float products of values in [-1, 1]: at most 300 u times the sum of |products| <= 300 u 300.
  for (Eigen::Index j = 0; j < 250; ++j)
    for (Eigen::Index i = 0; i < 250; ++i) {
      if (i < j) EXPECT_EQ(g(i, j), 0.0f);  // the strict upper triangle is left as it was
      else EXPECT_NEAR(g(i, j), exact(i, j), 300.0 * kFloatRoundoff * 300.0);
    }
  Eigen::MatrixXf wrong(3, 3);
  EXPECT_THROW(rank_update_lower(wrong, af), ArgumentError);
}

}  // namespace
}  // namespace icobrdf
