// Weighted least-squares fits of scattered samples (icobrdf/core/fit/sample_fit.hpp).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "tests/core/sample_pairs.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Recovery of data in the span: limited by cond(A) (~1e2 for these random designs) times rounding.
constexpr double kRecoveryTol = 1e-9;
// Reproduction of the data by a rank-deficient fit: same rounding bound.
constexpr double kReproduceTol = 1e-9;

// The probe's eigenvalues are Lanczos estimates to 1e-4 relative (kConditionEigenTolerance in
// icobrdf/core/fit/sample_fit.cpp); the condition s_1 / sqrt(lambda_min) then carries at most ~1e-4, and forming G
// adds cond^2 k eps relative to lambda_min (below 1e-6 here).
constexpr double kConditionTol = 2e-4;

using test::Pairs;
using test::random_pairs;
using test::random_vector;

// Pairs in the plane of incidence y = 0 (phi in {0, pi}); y is exactly 0 so the sine-type K_n^l (l < 0)
// vanish exactly there.
Pairs plane_pairs(int count, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Pairs p;
  p.wi.resize(count, 3);
  p.wr.resize(count, 3);
  auto dir = [&] {
    const double th = 0.5 * M_PI * u(g), side = u(g) < 0.5 ? -1.0 : 1.0;
    return Eigen::RowVector3d(side * std::sin(th), 0.0, std::cos(th));
  };
  for (int i = 0; i < count; ++i) {
    p.wi.row(i) = dir();
    p.wr.row(i) = dir();
  }
  return p;
}

TEST(SampleFit, RecoversGeneralSpectrumFromRandomSamples) {
  const int order = 3;
  const long long k = helmholtz_mode_count(order);  // 55 unknowns
  const Eigen::VectorXd truth = random_vector(k, 1);
  const Pairs p = random_pairs(600, 2);
  const Eigen::MatrixXd y = helmholtz_modes_eval(order, p.wi, p.wr) * truth;
  Eigen::VectorXd w = random_vector(600, 3).cwiseAbs().array() + 0.1;
  SampleFitOptions o;
  o.order = order;
  const SampleFitResult r = fit_samples(p.wi, p.wr, y, w, o);
  EXPECT_EQ(r.unknowns, k);
  EXPECT_EQ(r.effective_rank, k);
  EXPECT_EQ(r.null_space_dimension, 0);
  EXPECT_EQ(r.unseen_modes, 0);
  EXPECT_LT((r.modes.col(0) - truth).cwiseAbs().maxCoeff(), kRecoveryTol);
  EXPECT_LT(r.residual_rms[0], kRecoveryTol);
  // C is the symmetric matrix of the BSSS vector (icobrdf/core/basis/helmholtz_modes.hpp).
  EXPECT_LT((r.channels[0] - coefficients_from_bsss(truth)).cwiseAbs().maxCoeff(), kRecoveryTol);
}

TEST(SampleFit, RecoversIsotropicSpectrumAndStreamsInChunks) {
  const int order = 6;
  const int k = isotropic_mode_count(order);  // 30
  const Eigen::VectorXd truth = random_vector(k, 4);
  const Pairs p = random_pairs(2000, 5);
  Eigen::MatrixXd y(2000, 2);
  y.col(0) = isotropic_modes_eval(order, p.wi, p.wr) * truth;
  y.col(1) = -2.0 * y.col(0);
  SampleFitOptions o;
  o.order = order;
  o.isotropic = true;
  // Same samples fed in three uneven chunks must give the same answer as one block (QR is exact).
  SampleFitAccumulator acc(o, 2);
  const int cuts[4] = {0, 7, 1500, 2000};
  for (int c = 0; c < 3; ++c) {
    const int b = cuts[c], n = cuts[c + 1] - cuts[c];
    acc.add(p.wi.middleRows(b, n), p.wr.middleRows(b, n), y.middleRows(b, n), Eigen::VectorXd::Ones(n));
  }
  const SampleFitResult r = acc.solve();
  EXPECT_EQ(r.samples, 2000);
  EXPECT_EQ(r.effective_rank, k);
  EXPECT_LT((r.modes.col(0) - truth).cwiseAbs().maxCoeff(), kRecoveryTol);
  EXPECT_LT((r.modes.col(1) + 2.0 * truth).cwiseAbs().maxCoeff(), 2 * kRecoveryTol);
  EXPECT_LT((r.channels[0] - coefficients_from_ibsss(order, truth)).cwiseAbs().maxCoeff(), kRecoveryTol);
}

// Plane-of-incidence data, general modes of order N: only K_n^l with l >= 0 are non-zero on the plane,
// so modes built from an l < 0 function have zero columns. Restricted to the plane, K_n^l (l >= 0) is
// a polynomial of degree n in the signed coordinate s = +-rho, and these span all polynomials of degree
// <= N (N + 1 dimensions); the modes then span the symmetric polynomials in (s_i, s_r) of degree <= N in
// each: rank (N + 1)(N + 2)/2. For N = 4: M = 15, 9 functions with l >= 0 give 9 * 10 / 2 = 45 seen
// modes, so 120 - 45 = 75 unseen modes and rank 15.
TEST(SampleFit, PlaneOfIncidenceGivesMinimumNormSolution) {
  const int order = 4;
  const Pairs p = plane_pairs(800, 6);
  const Eigen::VectorXd truth = random_vector(helmholtz_mode_count(order), 7);
  const Eigen::MatrixXd a = helmholtz_modes_eval(order, p.wi, p.wr);
  const Eigen::VectorXd y = a * truth;
  SampleFitOptions o;
  o.order = order;
  const SampleFitResult r = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  EXPECT_EQ(r.unknowns, 120);
  EXPECT_EQ(r.unseen_modes, 75);
  EXPECT_EQ(r.effective_rank, 15);
  EXPECT_EQ(r.null_space_dimension, 105);
  const auto modes = helmholtz_modes(order);
  for (size_t j = 0; j < modes.size(); ++j) {
    const bool sine = modes[j].l < 0 || modes[j].lp < 0;
    EXPECT_EQ(r.unseen[j], sine) << "mode " << j;
    if (sine) {
      EXPECT_EQ(r.modes(static_cast<Eigen::Index>(j), 0), 0.0) << "unseen mode " << j << " must be exactly 0";
    }
  }
  // The fit reproduces the data ...
  const Eigen::VectorXd yfit = a * r.modes.col(0);
  EXPECT_LT((yfit - y).cwiseAbs().maxCoeff(), kReproduceTol * y.cwiseAbs().maxCoeff());
  EXPECT_LT(r.residual_rms[0], kReproduceTol * y.cwiseAbs().maxCoeff());
  // ... and has minimum norm: truth - x solves A v = 0, and the minimum-norm x is orthogonal to every such v.
  const Eigen::VectorXd x = r.modes.col(0), v = truth - x;
  EXPECT_LT(std::abs(x.dot(v)), kReproduceTol * truth.squaredNorm());
  EXPECT_LT(x.norm(), truth.norm());
}

// Isotropic modes of order 4 on plane data: restricted to the plane they are symmetric polynomials in
// (s_i, s_r) (degree <= 4 in each) invariant under (s_i, s_r) -> (-s_i, -s_r): monomial pairs (a, b),
// a <= b <= 4, a + b even: 9 of them, all reached (l = 0 gives the 6 even ones, l = 1 the 3 odd ones).
// Rank 9 of 14 unknowns; no single mode vanishes on the plane (no unseen modes).
TEST(SampleFit, PlaneOfIncidenceIsotropicRank) {
  const int order = 4;
  const Pairs p = plane_pairs(500, 8);
  const Eigen::VectorXd truth = random_vector(isotropic_mode_count(order), 9);
  const Eigen::MatrixXd a = isotropic_modes_eval(order, p.wi, p.wr);
  SampleFitOptions o;
  o.order = order;
  o.isotropic = true;
  const SampleFitResult r = fit_samples(p.wi, p.wr, a * truth, Eigen::VectorXd(), o);
  EXPECT_EQ(r.unknowns, 14);
  EXPECT_EQ(r.effective_rank, 9);
  EXPECT_EQ(r.null_space_dimension, 5);
  EXPECT_EQ(r.unseen_modes, 0);
  EXPECT_LT((a * r.modes.col(0) - a * truth).cwiseAbs().maxCoeff(), kReproduceTol * (a * truth).cwiseAbs().maxCoeff());
  const Eigen::VectorXd x = r.modes.col(0);
  EXPECT_LT(std::abs(x.dot(truth - x)), kReproduceTol * truth.squaredNorm());
}

// Fewer samples than unknowns: the rank is the number of (generic) samples.
TEST(SampleFit, TooFewSamplesIsRankDeficient) {
  const int order = 2;  // 21 unknowns
  const Pairs p = random_pairs(8, 10);
  const Eigen::VectorXd y = random_vector(8, 11);
  SampleFitOptions o;
  o.order = order;
  const SampleFitResult r = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  EXPECT_EQ(r.effective_rank, 8);
  EXPECT_EQ(r.null_space_dimension, 21 - 8);
  const Eigen::VectorXd yfit = helmholtz_modes_eval(order, p.wi, p.wr) * r.modes.col(0);
  EXPECT_LT((yfit - y).cwiseAbs().maxCoeff(), kReproduceTol);  // interpolates the 8 samples
}

// Tikhonov: compared with an independent solve of the normal equations (A^T W A + lambda D) x = A^T W y
// (LDLT, full rank), and high orders shrink monotonically as lambda grows while order 0 is unpenalized.
TEST(SampleFit, TikhonovMatchesNormalEquationsAndShrinksHighOrders) {
  const int order = 4;
  const int k = isotropic_mode_count(order);
  const Pairs p = random_pairs(300, 12);
  const Eigen::MatrixXd a = isotropic_modes_eval(order, p.wi, p.wr);
  const Eigen::VectorXd y = a * random_vector(k, 13) + 0.3 * random_vector(300, 14);
  const Eigen::VectorXd w = random_vector(300, 15).cwiseAbs().array() + 0.5;
  const Eigen::VectorXd d = tikhonov_penalties(order, true, 1.0);
  const auto modes = isotropic_modes(order);
  // d = (n(n+2) + m(m+2))^1: I_00^0 -> 0, I_20^0 -> 8, I_44^l -> 48.
  EXPECT_EQ(d[0], 0.0);
  EXPECT_EQ(d[isotropic_mode_index(2, 0, 0)], 8.0);
  EXPECT_EQ(d[isotropic_mode_index(4, 4, 2)], 48.0);
  double prev_high = 1e300;
  for (double lambda : {0.0, 0.1, 1.0, 10.0, 100.0}) {
    SampleFitOptions o;
    o.order = order;
    o.isotropic = true;
    o.tikhonov = lambda;
    const SampleFitResult r = fit_samples(p.wi, p.wr, y, w, o);
    const Eigen::MatrixXd n = a.transpose() * w.asDiagonal() * a + lambda * Eigen::MatrixXd(d.asDiagonal());
    const Eigen::VectorXd x = n.ldlt().solve(a.transpose() * (w.asDiagonal() * y));
    EXPECT_LT((r.modes.col(0) - x).norm(), 1e-9 * x.norm()) << "lambda " << lambda;
    double high = 0;
    for (int j = 0; j < k; ++j)
      if (modes[static_cast<size_t>(j)].n == 4) high += r.modes(j, 0) * r.modes(j, 0);
    EXPECT_LT(high, prev_high) << "lambda " << lambda;
    prev_high = high;
  }
}

// Order 0 isotropic fit = weighted mean of the data (one constant mode), so the weighted residual RMS is
// the weighted standard deviation: data c +- delta in equal numbers gives exactly delta.
TEST(SampleFit, ResidualRmsIsWeightedDeviation) {
  const Pairs p = random_pairs(100, 16);
  Eigen::VectorXd y(100);
  const double c = 0.7, delta = 0.05;
  for (int i = 0; i < 100; ++i) y[i] = c + (i % 2 ? delta : -delta);
  SampleFitOptions o;
  o.order = 0;
  o.isotropic = true;
  const SampleFitResult r = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  EXPECT_NEAR(r.residual_rms[0], delta, 1e-14);
  // I_00^0 = (1/2pi) sqrt(1/4) * 2 = 1/(2 pi): coefficient c * 2 pi reproduces the mean.
  EXPECT_NEAR(r.modes(0, 0), c * 2 * M_PI, 1e-12);
}

TEST(SampleFit, RejectsBadArguments) {
  SampleFitOptions o;
  o.order = 17;
  EXPECT_THROW(SampleFitAccumulator(o, 1), ArgumentError);
  o.order = 2;
  o.tikhonov = -1;
  EXPECT_THROW(SampleFitAccumulator(o, 1), ArgumentError);
  o.tikhonov = 0;
  SampleFitAccumulator acc(o, 1);
  EXPECT_THROW(acc.solve(), ArgumentError);  // no samples
  const Pairs p = random_pairs(3, 17);
  EXPECT_THROW(acc.add(p.wi, p.wr, Eigen::MatrixXd::Ones(2, 1), Eigen::VectorXd::Ones(3)), ArgumentError);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(3);
  w[1] = -1;
  EXPECT_THROW(acc.add(p.wi, p.wr, Eigen::MatrixXd::Ones(3, 1), w), ArgumentError);
  Eigen::MatrixXd v = Eigen::MatrixXd::Ones(3, 1);
  v(2, 0) = std::nan("");
  EXPECT_THROW(acc.add(p.wi, p.wr, v, Eigen::VectorXd::Ones(3)), ArgumentError);
}

TEST(SampleFit, AGivenProbeGivesTheSameFitAsProbingAgain) {
  // The probe handed to fit_samples is the one it would compute itself: the result is bitwise the same.
  const Pairs p = random_pairs(800, 21);
  const Eigen::MatrixXd y = helmholtz_modes_eval(3, p.wi, p.wr) * Eigen::VectorXd::LinSpaced(helmholtz_mode_count(3), -1.0, 1.0);
  SampleFitOptions o;
  o.order = 3;
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(800);
  const NormalEquations ne = assemble_normal_equations(3, false, p.wi, p.wr, y, w);
  const NormalEquationsProbe probe = probe_normal_equations(ne, o.rank_tolerance);
  ASSERT_TRUE(probe.llt);
  EXPECT_EQ(probe.determinacy.unseen, 0);
  const SampleFitResult a = fit_samples(p.wi, p.wr, y, w, o, &ne, &probe), b = fit_samples(p.wi, p.wr, y, w, o, &ne);
  EXPECT_EQ((a.modes - b.modes).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(a.condition, b.condition);
  EXPECT_EQ((a.standard_error - b.standard_error).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SampleFit, AssemblyDoesNotDependOnTheThreadCount) {
  // Panels are summed in the order of the rows whatever the threads that evaluate them.
  const Pairs p = random_pairs(5000, 22);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Ones(5000, 1);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(5000);
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const NormalEquations one = assemble_normal_equations(6, false, p.wi, p.wr, y, w);
  omp_set_num_threads(std::max(2, saved));
  const NormalEquations many = assemble_normal_equations(6, false, p.wi, p.wr, y, w);
  omp_set_num_threads(saved);
  EXPECT_EQ((one.gram - many.gram).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((one.rhs - many.rhs).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SampleFit, ProbeConditionIsTheSingularValueRatioOfTheWeightedDesign) {
  // cond(W^(1/2) A) by definition (a dense SVD) against the probe's Lanczos estimates, for weights spread over
  // one and over six decades (the second condition is some hundred times the first). The SVD is Eigen's
  // JacobiSVD (Jacobi rotations after a column-pivoting QR); BDCSVD, which the fits use, takes about four times
  // as long to compile (docs/reliability.md, "CI").
  const int order = 5;  // 231 general modes
  const Pairs p = random_pairs(2000, 21);
  const Eigen::MatrixXd a = helmholtz_modes_eval(order, p.wi, p.wr);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Zero(2000, 1);
  for (double decades : {1.0, 6.0}) {
    Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(2000, 0.0, -decades);
    w = w.unaryExpr([](double e) { return std::pow(10.0, e); });
    const NormalEquations ne = assemble_normal_equations(order, false, p.wi, p.wr, y, w);
    const NormalEquationsDeterminacy d = normal_equations_determinacy(ne);
    ASSERT_TRUE(d.factored);
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(w.cwiseSqrt().asDiagonal() * a).singularValues();
    const double cond = s[0] / s[s.size() - 1];
    EXPECT_NEAR(d.condition, cond, kConditionTol * cond) << decades << " decades of weights";
  }
}

TEST(SampleFit, ProbeRunsTheCallersJobsOnceBesideItAndPassesOnTheirFailure) {
  // 666 general modes: the factorization is large enough for the probe's pool of tasks.
  const int order = 7;
  const Pairs p = random_pairs(1500, 31);
  const NormalEquations ne =
      assemble_normal_equations(order, false, p.wi, p.wr, Eigen::MatrixXd::Zero(1500, 1), Eigen::VectorXd::Ones(1500));
  const NormalEquationsProbe alone = probe_normal_equations(ne);
  std::vector<std::atomic<int>> runs(7);
  std::vector<std::function<void()>> jobs;
  for (size_t j = 0; j < runs.size(); ++j) jobs.emplace_back([&runs, j] { ++runs[j]; });
  const NormalEquationsProbe beside = probe_normal_equations(ne, -1.0, nullptr, jobs);
  for (size_t j = 0; j < runs.size(); ++j) EXPECT_EQ(runs[j].load(), 1) << "job " << j;
  ASSERT_TRUE(alone.determinacy.factored);
  EXPECT_EQ(beside.determinacy.condition, alone.determinacy.condition);  // the same arithmetic on any thread
  EXPECT_EQ(beside.s1, alone.s1);
  jobs.emplace_back([] { throw std::runtime_error("job failed"); });
  EXPECT_THROW(probe_normal_equations(ne, -1.0, nullptr, jobs), std::runtime_error);
}

// Single-precision Gram products (sample_fit.hpp). Each product a_i a_j is formed from inputs rounded to float
// (relative 2^-24 each) and summed in float over one panel: |G~_ij - G_ij| <= (rows + 2) 2^-24 sum_s |a_si a_sj|
// <= (rows + 2) 2^-24 sqrt(G_ii G_jj) (Cauchy-Schwarz; Higham, "Accuracy and Stability", sec. 3.1).
constexpr double kFloatUnitRoundoff = 0x1p-24;
// The refined single-precision fit and the double one both solve the same least-squares problem to the
// attainable accuracy ~ cond(W^(1/2) A) eps (cond ~ 10 for these random designs), far inside this.
constexpr double kSingleAgreementTol = 1e-12;
// Standard errors come from the factor of the rounded G: relative error ~ cond(G) x (its ~1e-6 rounding).
constexpr double kSingleStandardErrorTol = 1e-3;

TEST(SampleFit, SingleGramProductsAreWithinTheirRoundingBound) {
  const int order = 5;  // 231 general modes
  const int rows = 3000;
  const Pairs p = random_pairs(rows, 41);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Ones(rows, 1);
  const Eigen::VectorXd w = random_vector(rows, 42).cwiseAbs().array() + 0.1;
  const NormalEquations d = assemble_normal_equations(order, false, p.wi, p.wr, y, w);
  const NormalEquations s = assemble_normal_equations(order, false, p.wi, p.wr, y, w, {}, {}, nullptr, true);
  EXPECT_TRUE(s.single_products);
  EXPECT_FALSE(d.single_products);
  const Eigen::ArrayXd diag = d.gram.diagonal().array().sqrt();
  const Eigen::ArrayXXd scaled = (s.gram - d.gram).array() / (diag.matrix() * diag.matrix().transpose()).array();
  const double worst = scaled.abs().maxCoeff();
  EXPECT_LE(worst, (rows + 2) * kFloatUnitRoundoff);
  EXPECT_GT(worst, 0.0);  // the products did run in float
  EXPECT_EQ((s.gram - s.gram.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((s.rhs - d.rhs).cwiseAbs().maxCoeff(), 0.0);  // A^T W y stays double
}

TEST(SampleFit, SingleGramFitIsRefinedToTheDoubleFit) {
  // Noisy data (residual not zero) and data far outside float's range (1e-150 and 1e150): the refinement
  // takes more than the double path's one pass and ends at the double path's solution.
  const int order = 5;
  const long long k = helmholtz_mode_count(order);
  const int rows = 3000;
  const Pairs p = random_pairs(rows, 43);
  const Eigen::VectorXd truth = random_vector(k, 44);
  const Eigen::VectorXd w = random_vector(rows, 45).cwiseAbs().array() + 0.1;
  for (double scale : {1.0, 1e-150, 1e150}) {
    const Eigen::MatrixXd y = scale * (helmholtz_modes_eval(order, p.wi, p.wr) * truth + 0.1 * random_vector(rows, 46));
    SampleFitOptions o;
    o.order = order;
    o.gram = GramPrecision::Double;
    const SampleFitResult d = fit_samples(p.wi, p.wr, y, w, o);
    o.gram = GramPrecision::Single;
    const SampleFitResult s = fit_samples(p.wi, p.wr, y, w, o);
    EXPECT_STREQ(d.solver, "normal equations");
    EXPECT_STREQ(s.solver, "normal equations, single-precision Gram") << scale;
    EXPECT_EQ(d.refinement_passes, 1);
    EXPECT_GE(s.refinement_passes, 2) << scale;
    EXPECT_LE(s.refinement_passes, kMaxRefinementPasses);
    EXPECT_LE((s.modes - d.modes).cwiseAbs().maxCoeff(), kSingleAgreementTol * d.modes.cwiseAbs().maxCoeff()) << scale;
    EXPECT_NEAR(s.residual_rms[0], d.residual_rms[0], kSingleAgreementTol * d.residual_rms[0]) << scale;
    EXPECT_LE(((s.standard_error - d.standard_error).array() / d.standard_error.array()).abs().maxCoeff(), kSingleStandardErrorTol)
        << scale;
  }
}

TEST(SampleFit, SingleGramOfAnIllConditionedDesignIsAssembledAgainInDouble) {
  // Few samples per unknown, weights over six decades: cond(W^(1/2) A) beyond kSingleGramMaxCondition (checked), within the normal
  // equations' limit. The fit asked for single products refuses them and gives the double path's result.
  const int order = 5;
  const int rows = 400;  // 1.7 samples per unknown
  const Pairs p = random_pairs(rows, 21);
  Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(rows, 0.0, -6.0).unaryExpr([](double e) { return std::pow(10.0, e); });
  const Eigen::MatrixXd y = helmholtz_modes_eval(order, p.wi, p.wr) * random_vector(helmholtz_mode_count(order), 47);
  SampleFitOptions o;
  o.order = order;
  o.gram = GramPrecision::Double;
  const SampleFitResult d = fit_samples(p.wi, p.wr, y, w, o);
  ASSERT_GT(d.condition, kSingleGramMaxCondition);
  ASSERT_LE(d.condition, kNormalEquationsMaxCondition);
  o.gram = GramPrecision::Single;
  const SampleFitResult s = fit_samples(p.wi, p.wr, y, w, o);
  EXPECT_STREQ(s.solver, "normal equations");
  EXPECT_EQ((s.modes - d.modes).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SampleFit, AutomaticGramPrecisionFollowsTheWork) {
  EXPECT_TRUE(single_gram_products(GramPrecision::Automatic, 20000, 2211));  // 9.8e10 multiply-adds
  EXPECT_FALSE(single_gram_products(GramPrecision::Automatic, 20000, 500));  // 5e9
  EXPECT_TRUE(single_gram_products(GramPrecision::Single, 10, 3));
  EXPECT_FALSE(single_gram_products(GramPrecision::Double, 1000000, 5000));
}

}  // namespace
}  // namespace icobrdf
