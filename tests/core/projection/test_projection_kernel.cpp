// project_lut's block kernel (icobrdf/core/projection/projection_tile.cpp: P^T F_J as register-tiled dot products along the
// cells) against the plain product P^T F P, on every SIMD target compiled into this build that this CPU runs
// (a target it cannot run is reported as skipped), at sizes that exercise every remainder: cells not a
// multiple of the vector width (scalar tail), of the cell chunk or of the cell block (2600 cells at 45 modes:
// blocks of 1024 cells, and the symmetric path's ranges starting mid-block), LUT blocks whose width is not a multiple
// of the tile width (one-column tiles), mode counts not a multiple of the tile's mode group (5 on AVX-512, 3
// otherwise: 1, 3, 7, 10, 14 and 21 leave every remainder of both), and
// several 512-column blocks; and the symmetric-F path (LutSymmetry::Symmetric) at the same sizes.
#include <gtest/gtest.h>
#include <omp.h>

#include <cfloat>
#include <cmath>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/support/simd_target.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Rounding steps beyond the 2 cells additions: the two multiplications of each triple product, rounded up
// to 8 (the lanes' pairwise sum and the block partials are additions among the 2 cells of any summation order).
constexpr double kBoundSlackOps = 8.0;

class ProjectLutOnTarget : public ::testing::TestWithParam<SimdTarget> {};

// FP64 lanes of a target's vector registers, from the instruction set's register width / 64 bits:
// AVX-512 zmm 512, AVX2 ymm 256, SSE xmm 128 and Highway's 128-bit emulation; 0 for a target not listed.
int register_lanes(const std::string& name) {
  if (name.rfind("AVX3", 0) == 0) return 512 / 64;
  if (name == "AVX2") return 256 / 64;
  if (name == "SSE4" || name == "SSSE3" || name == "EMU128") return 128 / 64;
  if (name == "SCALAR") return 1;
  return 0;
}

TEST_P(ProjectLutOnTarget, EqualsThePlainProductAtEveryRemainder) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  ASSERT_EQ(dispatched_simd_target().bits, target.bits) << "dispatch did not move to " << target.name;
  EXPECT_EQ(dispatched_f64_lanes(), register_lanes(target.name)) << target.name;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Size {
    int cells, modes;
  };
  for (const Size& s : {Size{1, 1}, Size{3, 1}, Size{7, 10}, Size{257, 3}, Size{259, 7}, Size{517, 15}, Size{1030, 10},
                        Size{1283, 14}, Size{1301, 45}, Size{2053, 21}, Size{2600, 45}}) {
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
        << target.name << ", " << s.cells << " cells, " << s.modes << " modes: max error " << (two - reference).cwiseAbs().maxCoeff();
    EXPECT_EQ((two - one).cwiseAbs().maxCoeff(), 0.0) << target.name << ": 1 and 2 threads must agree bitwise";

    // The same F made symmetric, with every entry the symmetric path must not read (above its column's
    // diagonal block) poisoned: the result is the projection of the symmetric F. The terms are those of the
    // general product (each mirrored pair counted from the lower triangle), with 2 more additions per
    // entry (A + A^T + D), within the same slack.
    const Eigen::MatrixXd sym = 0.5 * (f + f.transpose());
    const Eigen::MatrixXd sym_reference = p.P.transpose() * sym * p.P;
    const Eigen::MatrixXd sym_bound =
        (2.0 * s.cells + kBoundSlackOps) * DBL_EPSILON * (p.P.cwiseAbs().transpose() * sym.cwiseAbs() * p.P.cwiseAbs());
    Eigen::MatrixXd poisoned = sym;
    for (Eigen::Index j = 0; j < s.cells; ++j)
      for (Eigen::Index k = 0; k < j / kProjectBlockColumns * kProjectBlockColumns; ++k) poisoned(k, j) = std::nan("");
    const Eigen::MatrixXd sym_two = project_lut(p, poisoned, LutSymmetry::Symmetric);
    omp_set_num_threads(1);
    const Eigen::MatrixXd sym_one = project_lut(p, poisoned, LutSymmetry::Symmetric);
    omp_set_num_threads(2);
    EXPECT_TRUE(((sym_two - sym_reference).cwiseAbs().array() <= sym_bound.array()).all())
        << target.name << ", symmetric, " << s.cells << " cells, " << s.modes << " modes: max error "
        << (sym_two - sym_reference).cwiseAbs().maxCoeff();
    EXPECT_EQ((sym_two - sym_one).cwiseAbs().maxCoeff(), 0.0) << target.name << ", symmetric: 1 and 2 threads must agree bitwise";
  }
}

INSTANTIATE_TEST_SUITE_P(EveryCompiledTarget, ProjectLutOnTarget, ::testing::ValuesIn(compiled_simd_targets()),
                         [](const ::testing::TestParamInfo<SimdTarget>& info) { return info.param.name; });

TEST(SimdTargets, TheDispatchedTargetIsTheBestCompiledOneThisCpuRuns) {
  const auto targets = compiled_simd_targets();
  ASSERT_FALSE(targets.empty());
  const SimdTarget* best = nullptr;
  for (const auto& t : targets)
    if (t.runs_here && (best == nullptr || t.bits < best->bits)) best = &t;  // lower bits are better targets
  ASSERT_NE(best, nullptr) << "no compiled target runs on this CPU";
  EXPECT_EQ(dispatched_simd_target().name, best->name);
}

TEST(SimdTargets, ATargetThisCpuCannotRunIsRefused) {
  for (const auto& t : compiled_simd_targets())
    if (!t.runs_here) {
      EXPECT_THROW(ScopedSimdTarget{t}, UnsupportedError) << t.name;
    }
  SimdTarget unknown;
  unknown.bits = 0;
  unknown.name = "none";
  EXPECT_THROW(ScopedSimdTarget{unknown}, UnsupportedError);
}

}  // namespace
}  // namespace icobrdf
