// project_lut's block kernel (core/projection.cpp: P^T F_J as register-tiled dot products along the cells)
// against the plain product P^T F P, at sizes that exercise every remainder: cells not a multiple of 4
// (scalar tail) or of the 512-cell chunk, LUT blocks whose width is not a multiple of 4 (Eigen tail),
// mode counts not a multiple of the 3-mode tile (1, 10, 21), and several 512-column blocks.
#include <gtest/gtest.h>
#include <omp.h>

#include <cfloat>
#include <random>

#include "core/projection.hpp"

namespace icobrdf {
namespace {

// Rounding steps beyond the 2 cells additions: the two multiplications of each triple product, the
// horizontal sum of a 4-lane accumulator (2) and the addition of the block partials, rounded up to 8.
constexpr double kBoundSlackOps = 8.0;

TEST(ProjectLut, EqualsThePlainProductAtEveryRemainder) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Size {
    int cells, modes;
  };
  for (const Size& s : {Size{1, 1}, Size{3, 1}, Size{7, 10}, Size{257, 3}, Size{517, 15}, Size{1030, 10}, Size{1301, 45},
                        Size{2053, 21}}) {
    ProjectionOperator p;
    p.P = Eigen::MatrixXd::NullaryExpr(s.cells, s.modes, [&] { return u(rng); });
    const Eigen::MatrixXd f = Eigen::MatrixXd::NullaryExpr(s.cells, s.cells, [&] { return u(rng); });
    const Eigen::MatrixXd reference = p.P.transpose() * f * p.P;
    // Rounding bound of any summation order of the two products: (2 cells) eps |P|^T |F| |P| entrywise
    // (each entry is a sum of cells^2 triple products reached through 2 cells additions), plus slack.
    const Eigen::MatrixXd bound =
        (2.0 * s.cells + kBoundSlackOps) * DBL_EPSILON * (p.P.cwiseAbs().transpose() * f.cwiseAbs() * p.P.cwiseAbs());
    omp_set_num_threads(2);
    const Eigen::MatrixXd two = project_lut(p, f);
    omp_set_num_threads(1);
    const Eigen::MatrixXd one = project_lut(p, f);
    omp_set_num_threads(2);
    ASSERT_EQ(two.rows(), s.modes);
    ASSERT_EQ(two.cols(), s.modes);
    EXPECT_TRUE(((two - reference).cwiseAbs().array() <= bound.array()).all())
        << s.cells << " cells, " << s.modes << " modes: max error " << (two - reference).cwiseAbs().maxCoeff();
    EXPECT_EQ((two - one).cwiseAbs().maxCoeff(), 0.0) << "1 and 2 threads must agree bitwise";
  }
}

}  // namespace
}  // namespace icobrdf
