// Spectrum evaluation f = K(w_i)^T C K(w_r) (evaluate_coefficients, icobrdf/core/spectrum/spectrum_tile.hpp) and the block
// basis kernel it uses, on every SIMD target compiled into this build that this CPU runs (a target it cannot
// run is reported as skipped), against the plain definition: K from the one-direction evaluator
// hemisphere_basis_eval (whose accuracy test_hemisphere_basis.cpp establishes), then the sum over all M^2
// products. Orders 0..8, 13 and 40 exercise every panel width and a padded last panel; 1, 23, 25, 193 and
// 1000 pairs every remainder of the register tile (2..24 pairs) and of the 192-pair block. The directions
// include normal incidence (the pole, rho = 0), grazing (z = 0 at several azimuths, and z = -1e-13, taken as
// the horizon) and near-grazing ones. An isotropic C takes the sparse path; it is checked against the same
// definition and against the dense path.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <string>
#include <random>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/support/simd_target.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/spectrum/spectrum_tile.hpp"
#include "tests/core/hard_directions.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr double kUnitRoundoff = 0x1p-53;
// The block kernel against hemisphere_basis_eval: the same recurrences; where one contracts a * b + c into an
// FMA and the other rounds twice (always on a target without FMA), they part by up to 4 ulps of
// |K| <= sqrt((n + 1) / pi) per recurrence step, over at most 128 steps: relative to the mode's normalization.
constexpr double kBasisTol = 128 * 4 * kUnitRoundoff;
// Rounding steps of the bilinear form beyond its 2 M additions and multiplications (the final dot and the
// pairwise order of the sparse groups), rounded up.
constexpr double kFormSlackOps = 4.0;

class SpectrumOnTarget : public ::testing::TestWithParam<SimdTarget> {};

// The hard directions of the basis tests, and one near grazing (z = 1e-9).
RowMatrix3d directions(int n, unsigned seed) {
  RowMatrix3d d = test::hard_directions(n, seed);
  const double z = 1e-9, s = std::sqrt(1.0 - z * z);
  if (n > 7) d.row(n - 1) << s * std::cos(-2.5), s * std::sin(-2.5), z;
  return d;
}

Eigen::VectorXd basis(int order, const Eigen::RowVector3d& d) {
  Eigen::VectorXd k(hemisphere_basis_count(order));
  hemisphere_basis_eval(order, d.transpose(), k.data());
  return k;
}

Eigen::VectorXd norms(int order) {
  Eigen::VectorXd n(hemisphere_basis_count(order));
  for (int j = 0; j < n.size(); ++j) n[j] = std::sqrt((ansi_to_nl(j).n + 1) / M_PI);
  return n;
}

// f against sum_kj K_k(w_i) C_kj K_j(w_r) at every pair: the form's rounding (2 M + slack) u sum |K_i| |C| |K_r|
// plus the basis values' error propagated through C.
void expect_definition(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::VectorXd& f,
                       const std::string& what) {
  const int m = hemisphere_basis_count(order);
  const Eigen::VectorXd nk = norms(order);
  const Eigen::MatrixXd ac = c.cwiseAbs();
  ASSERT_EQ(f.size(), wi.rows());
  for (Eigen::Index p = 0; p < wi.rows(); ++p) {
    const Eigen::VectorXd ki = basis(order, wi.row(p)), kr = basis(order, wr.row(p));
    const double expect = ki.dot(c * kr);
    const double terms = ki.cwiseAbs().dot(ac * kr.cwiseAbs());
    const double basis_err = kBasisTol * (nk.dot(ac * kr.cwiseAbs()) + ki.cwiseAbs().dot(ac * nk));
    ASSERT_LE(std::abs(f[p] - expect), (2.0 * m + kFormSlackOps) * kUnitRoundoff * terms + basis_err)
        << what << ", order " << order << ", pair " << p << " of " << wi.rows() << ": " << f[p] << " vs " << expect;
  }
}

TEST_P(SpectrumOnTarget, EqualsThePlainDefinitionAtEveryRemainderIncludingGrazingAndNormalIncidence) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  ASSERT_EQ(dispatched_simd_target().bits, target.bits) << "dispatch did not move to " << target.name;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int order : {0, 1, 2, 3, 4, 5, 6, 7, 8, 13, 40}) {
    const int m = hemisphere_basis_count(order);
    const Eigen::MatrixXd c = Eigen::MatrixXd::NullaryExpr(m, m, [&] { return u(rng); });
    const PackedSpectrum packed = pack_spectrum(c, order);
    EXPECT_FALSE(packed.sparse && order > 0) << "a random C is not azimuthally block-diagonal";
    for (int n : {1, 23, 25, 193, 1000}) {
      if (order == 40 && n > 25) continue;  // 861 x 861: the plain reference is the slow part
      const RowMatrix3d wi = directions(n, 3 + n), wr = directions(n, 1000 + n);
      omp_set_num_threads(2);
      const Eigen::VectorXd two = evaluate_coefficients(c, order, wi, wr);
      omp_set_num_threads(1);
      const Eigen::VectorXd one = evaluate_coefficients(c, order, wi, wr);
      omp_set_num_threads(2);
      expect_definition(c, order, wi, wr, two, target.name);
      EXPECT_EQ((two - one).cwiseAbs().maxCoeff(), 0.0) << target.name << ": 1 and 2 threads must agree bitwise";
    }
  }
}

TEST_P(SpectrumOnTarget, AnIsotropicSpectrumTakesTheRadialPathAndABlockDiagonalOneTheSparsePath) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  for (int order : {1, 2, 8, 13, 40}) {
    const int m = hemisphere_basis_count(order);
    const Eigen::MatrixXd iso = coefficients_from_ibsss(order, Eigen::VectorXd::Random(isotropic_mode_count(order)));
    // Block-diagonal in l but not isotropic: the block of -l scaled by 1.5 (rotation invariant only for l = 0).
    Eigen::MatrixXd aniso = iso;
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b)
        if (ansi_to_nl(a).l < 0) aniso(a, b) *= 1.5;
    const PackedSpectrum radial = pack_spectrum(iso, order), sparse = pack_spectrum(aniso, order), dense = pack_spectrum(iso, order, false);
    ASSERT_TRUE(radial.sparse && radial.isotropic) << "order " << order;
    ASSERT_TRUE(sparse.sparse && !sparse.isotropic) << "order " << order;
    ASSERT_FALSE(dense.sparse || dense.isotropic);
    const int n = order == 40 ? 25 : 193;
    const RowMatrix3d wi = directions(n, 7), wr = directions(n, 8);
    const Eigen::VectorXd f = evaluate_coefficients(iso, order, wi, wr);
    expect_definition(iso, order, wi, wr, f, target.name + ", isotropic (radial path)");
    expect_definition(aniso, order, wi, wr, evaluate_coefficients(aniso, order, wi, wr), target.name + ", block-diagonal (sparse path)");
    // The dense and the sparse tile on the same basis rows: sums of the same non-zero products.
    const Eigen::Index ld = (n + dense.tile_pairs - 1) / dense.tile_pairs * dense.tile_pairs;
    Eigen::MatrixXd ki = Eigen::MatrixXd::Zero(ld, m), kr = Eigen::MatrixXd::Zero(ld, spectrum_tile_columns(dense));
    hemisphere_basis_block(order, n, wi.data(), ki.data(), ld);
    hemisphere_basis_block(order, n, wr.data(), kr.data(), ld);
    const PackedSpectrum iso_sparse = pack_spectrum(iso, order);
    Eigen::VectorXd fd(ld), fs(ld);
    spectrum_tile(dense, n, ki.data(), kr.data(), ld, fd.data());
    spectrum_tile(iso_sparse, n, ki.data(), kr.data(), ld, fs.data());
    const Eigen::MatrixXd ac = iso.cwiseAbs();
    for (int p = 0; p < n; ++p) {
      const double terms = ki.row(p).cwiseAbs().dot(kr.row(p).head(m).cwiseAbs() * ac.transpose());  // kr's padding columns carry no C
      EXPECT_LE(std::abs(fs[p] - fd[p]), 2.0 * (2.0 * m + kFormSlackOps) * kUnitRoundoff * terms) << target.name << " pair " << p;
    }
  }
}

TEST_P(SpectrumOnTarget, TheBlockBasisEqualsTheOneDirectionEvaluator) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  for (int order : {0, 1, 8, 40, 128}) {
    const int m = hemisphere_basis_count(order);
    const Eigen::VectorXd nk = norms(order);
    for (int n : {1, 7, 9, 31, 32, 33, 70}) {
      const RowMatrix3d d = directions(n, 11 + n);
      const int ld = n + 3;  // rows past n must stay untouched
      std::vector<double> out(static_cast<size_t>(ld) * m, -7.0);
      hemisphere_basis_block(order, n, d.data(), out.data(), ld);
      for (int r = 0; r < n; ++r) {
        const Eigen::VectorXd k = basis(order, d.row(r));
        for (int j = 0; j < m; ++j)
          ASSERT_LE(std::abs(out[static_cast<size_t>(j) * ld + r] - k[j]), kBasisTol * nk[j])
              << target.name << ", order " << order << ", direction " << r << ", mode " << j;
      }
      for (int j = 0; j < m; ++j)
        for (int r = n; r < ld; ++r) ASSERT_EQ(out[static_cast<size_t>(j) * ld + r], -7.0) << "padding row written";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryCompiledTarget, SpectrumOnTarget, ::testing::ValuesIn(compiled_simd_targets()),
                         [](const ::testing::TestParamInfo<SimdTarget>& info) { return info.param.name; });

TEST(SpectrumTile, OneCouplingEntryMakesTheDensePath) {
  const int order = 4, m = hemisphere_basis_count(order);
  Eigen::MatrixXd c = coefficients_from_ibsss(order, Eigen::VectorXd::Ones(isotropic_mode_count(order)));
  ASSERT_TRUE(pack_spectrum(c, order).sparse);
  // K_2^2 (ANSI 5) against K_2^0 (ANSI 4): l = 2 and l = 0 couple.
  ASSERT_EQ(ansi_to_nl(5).l, 2);
  ASSERT_EQ(ansi_to_nl(4).l, 0);
  c(5, 4) = 1e-300;
  EXPECT_FALSE(pack_spectrum(c, order).sparse);
  EXPECT_THROW(pack_spectrum(Eigen::MatrixXd::Zero(m, m + 1), order), ArgumentError);
}

TEST(SpectrumEvaluation, TheFirstInvalidDirectionOfEachSideIsReportedOnAnyNumberOfThreads) {
  const int order = 2, m = hemisphere_basis_count(order), n = 1000;
  const Eigen::MatrixXd c = Eigen::MatrixXd::Identity(m, m);
  RowMatrix3d wi = directions(n, 1), wr = directions(n, 2);
  wi(900, 2) = -0.5;                                   // below the horizon, in a later block
  wi(300, 0) = std::numeric_limits<double>::infinity();  // the first bad incident row
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    try {
      evaluate_coefficients(c, order, wi, wr);
      ADD_FAILURE() << "no error for invalid incident directions";
    } catch (const ArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find("incident direction 300 "), std::string::npos) << e.what();
    }
    RowMatrix3d ok = directions(n, 1), bad = wr;
    bad(777, 1) = std::nan("");
    try {
      evaluate_coefficients(c, order, ok, bad);
      ADD_FAILURE() << "no error for an invalid remitted direction";
    } catch (const ArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find("remitted direction 777 "), std::string::npos) << e.what();
    }
  }
  omp_set_num_threads(2);
}

}  // namespace
}  // namespace icobrdf
