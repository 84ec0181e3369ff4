// OpenBLAS's dense kernels for the sample fits (icobrdf/blas/blas_dense_kernels.hpp) against Eigen's and
// against the definitions.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>

#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "tests/core/sample_pairs.hpp"
#include "tests/support/random_matrix.hpp"
#include "tests/support/unity_id.hpp"

extern "C" char* openblas_get_corename();

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

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

// The kernel widths come from OpenBLAS's kernel sources per core (kernel/x86_64/KERNEL.<CORE>: the SkylakeX and
// Cooperlake DGEMM kernels are AVX-512, Haswell's and Zen's AVX2 + FMA, Prescott's and Sandybridge's SSE2/AVX
// without FMA); names are matched in any case, as openblas_get_corename spells them.
TEST(FitKernelChoice, OpenBlasCoreNamesMapToTheirKernelWidths) {
  EXPECT_EQ(blas_kernel_vector_bits("SkylakeX"), 512);
  EXPECT_EQ(blas_kernel_vector_bits("Cooperlake"), 512);
  EXPECT_EQ(blas_kernel_vector_bits("sapphirerapids"), 512);
  EXPECT_EQ(blas_kernel_vector_bits("Haswell"), 256);
  EXPECT_EQ(blas_kernel_vector_bits("Zen"), 256);
  EXPECT_EQ(blas_kernel_vector_bits("Prescott"), 128);
  EXPECT_EQ(blas_kernel_vector_bits("Sandybridge"), 128);
  EXPECT_EQ(blas_kernel_vector_bits("NoSuchCore"), 0);
  EXPECT_EQ(blas_kernel_vector_bits(""), 0);
}

TEST(FitKernelChoice, OpenBlasServesOnlyWhenItsKernelIsAsWideAsEigens) {
  // The case that made the rule: a CPU newer than the OpenBLAS build gets the SSE3 fallback.
  EXPECT_EQ(choose_fit_kernels("Prescott", 512).kernels, &eigen_dense_kernels());
  EXPECT_EQ(choose_fit_kernels("Haswell", 512).kernels, &eigen_dense_kernels());  // OPENBLAS_CORETYPE=Haswell on AVX-512
  EXPECT_EQ(choose_fit_kernels("SkylakeX", 512).kernels, &blas_dense_kernels());
  EXPECT_EQ(choose_fit_kernels("Cooperlake", 256).kernels, &blas_dense_kernels());
  EXPECT_EQ(choose_fit_kernels("Haswell", 256).kernels, &blas_dense_kernels());
  EXPECT_EQ(choose_fit_kernels("Unknown", 128).kernels, &eigen_dense_kernels());
  const FitKernelChoice c = choose_fit_kernels("Prescott", 512);
  EXPECT_NE(c.reason.find("Prescott"), std::string::npos) << c.reason;
  EXPECT_EQ(c.reason.find('\n'), std::string::npos) << "one line";
}

TEST(FitKernelChoice, EigensWidthIsTheBuildsAndTheProcessChoiceFollowsTheRule) {
#if defined(__AVX512F__)
  EXPECT_EQ(eigen_vector_bits(), 512);
#elif defined(__AVX__)
  EXPECT_EQ(eigen_vector_bits(), 256);
#else
  EXPECT_EQ(eigen_vector_bits(), 128);
#endif
  const FitKernelChoice& c = fit_kernel_choice();
  EXPECT_EQ(c.kernels, choose_fit_kernels(openblas_get_corename(), eigen_vector_bits()).kernels) << c.reason;
  EXPECT_EQ(&fit_dense_kernels(), c.kernels);
}

}  // namespace
}  // namespace icobrdf
