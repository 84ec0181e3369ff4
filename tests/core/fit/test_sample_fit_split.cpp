// A fit of scattered samples split over parts (icobrdf/core/fit/sample_fit.hpp SampleFitSplit), the parts run as
// threads of this process with a sum that adds their matrices in part order, as mpirun's ranks do
// (icobrdf/cluster/distributed_projection.cpp). Every part must reach the same bits, and that solution must be
// one process's up to the order of the sums, on each path: normal equations in double, single-precision
// Gram products refined over several summed passes, and the QR path (rank-deficient data), whose factors
// are gathered and combined. Each part also passes over its own rows only: a part that saw every row would
// double the sums.
#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "tests/core/sample_pairs.hpp"
#include "tests/core/thread_exchange.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// The split sums the rows' contributions in another grouping: a few roundings of G, which reach the solution
// multiplied by cond(W^(1/2) A) (below 1e2 for these random designs, Bjorck sec. 2.9); 1e-11 relative is 100x
// that and far below a part counted twice or missed (a third of the rows changes every sum by a third).
constexpr double kSplitTol = 1e-11;
// Noise of the in-plane samples relative to their values (~1): enough that GCV's minimum is the noise's, not rounding's.
constexpr double kInPlaneNoise = 1e-2;

using test::random_vector;
using test::ThreadExchange;

// fit(part, split) on `parts` threads, one part each, with the sums of a ThreadExchange (in part order, as
// mpirun's ranks add them); the results in part order.
// Every part fails at the same point (they share the sums' results), so an error is recorded, not rethrown.
template <class Result, class Fit>
std::vector<Result> run_parts(int parts, Fit fit, long long* sums = nullptr) {
  ThreadExchange x(parts);
  std::vector<Result> out(static_cast<size_t>(parts));
  std::vector<std::string> errors(static_cast<size_t>(parts));
  std::vector<std::thread> threads;
  for (int q = 0; q < parts; ++q) {
    auto split = std::make_shared<SampleFitSplit>();
    split->part = q;
    split->parts = parts;
    split->sum = [&x, q](std::vector<Eigen::MatrixXd>& m) { ThreadExchange::Part(x, q).sum(m); };
    threads.emplace_back([&, split, q] {
      try {
        out[static_cast<size_t>(q)] = fit(split);
      } catch (const std::exception& e) {
        errors[static_cast<size_t>(q)] = e.what();
      }
    });
  }
  for (auto& t : threads) t.join();
  for (int q = 0; q < parts; ++q) EXPECT_EQ(errors[static_cast<size_t>(q)], "") << "part " << q << " of " << parts;
  if (sums) *sums = x.rounds();
  return out;
}

// fit_samples split over `parts`.
std::vector<SampleFitResult> split_fit(int parts, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& y,
                                       const Eigen::VectorXd& w, const SampleFitOptions& o, long long* sums = nullptr) {
  return run_parts<SampleFitResult>(parts, [&](std::shared_ptr<const SampleFitSplit> split) {
    SampleFitOptions op = o;
    op.split = std::move(split);
    return fit_samples(wi, wr, y, w, op);
  }, sums);
}

void expect_split_agrees(const std::vector<SampleFitResult>& parts, const SampleFitResult& one, const char* what) {
  const double scale = one.modes.cwiseAbs().maxCoeff();
  for (size_t p = 0; p < parts.size(); ++p) {
    const SampleFitResult& r = parts[p];
    EXPECT_STREQ(r.solver, one.solver) << what << ", part " << p;
    EXPECT_EQ(r.samples, one.samples) << what << ", part " << p;
    EXPECT_EQ(r.effective_rank, one.effective_rank) << what << ", part " << p;
    EXPECT_NEAR(r.weight_sum, one.weight_sum, kSplitTol * one.weight_sum) << what << ", part " << p;
    EXPECT_LE((r.modes - one.modes).cwiseAbs().maxCoeff(), kSplitTol * scale) << what << ", part " << p;
    EXPECT_NEAR(r.residual_rms[0], one.residual_rms[0], kSplitTol * scale) << what << ", part " << p;
    EXPECT_EQ((r.modes - parts[0].modes).cwiseAbs().maxCoeff(), 0.0) << what << ": every part must reach the same bits";
    EXPECT_EQ(r.residual_rms[0], parts[0].residual_rms[0]) << what;
  }
}

// Noisy samples of a random spectrum with random weights: the normal equations in double (one refinement
// pass) and with single-precision Gram products (several passes, each summed), on 2, 3 and 5 parts.
TEST(SampleFitSplit, EveryPartReachesOneProcesssSolution) {
  const int order = 4, rows = 2000;
  const test::Pairs p = test::random_pairs(rows, 81);
  const Eigen::VectorXd truth = random_vector(helmholtz_mode_count(order), 82);
  const Eigen::VectorXd w = random_vector(rows, 83).cwiseAbs().array() + 0.1;
  const Eigen::MatrixXd y = helmholtz_modes_eval(order, p.wi, p.wr) * truth + 0.1 * random_vector(rows, 84);
  for (GramPrecision gram : {GramPrecision::Double, GramPrecision::Single}) {
    SampleFitOptions o;
    o.order = order;
    o.gram = gram;
    const SampleFitResult one = fit_samples(p.wi, p.wr, y, w, o);
    for (int parts : {2, 3, 5}) {
      long long sums = 0;
      const auto split = split_fit(parts, p.wi, p.wr, y, w, o, &sums);
      expect_split_agrees(split, one, gram == GramPrecision::Double ? "double" : "single");
      // One sum for the normal equations and one per refinement pass.
      EXPECT_EQ(sums, 1 + one.refinement_passes) << parts << " parts";
    }
  }
}

// In-plane samples against the general modes: unseen modes and a null space send the fit down the QR path,
// where each part's triangular factor is gathered and the factors are combined. Also a part with no rows
// (more parts than samples of positive weight).
TEST(SampleFitSplit, TheQrPathCombinesThePartsFactors) {
  const int order = 3, rows = 400;
  std::mt19937 g(85);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::Pairs p;
  p.wi.resize(rows, 3);
  p.wr.resize(rows, 3);
  for (int i = 0; i < rows; ++i) {
    const double a = 0.5 * M_PI * u(g), b = 0.5 * M_PI * u(g), si = u(g) < 0.5 ? -1.0 : 1.0, sr = u(g) < 0.5 ? -1.0 : 1.0;
    p.wi.row(i) << si * std::sin(a), 0.0, std::cos(a);
    p.wr.row(i) << sr * std::sin(b), 0.0, std::cos(b);
  }
  const Eigen::MatrixXd y = helmholtz_modes_eval(order, p.wi, p.wr) * random_vector(helmholtz_mode_count(order), 86);
  SampleFitOptions o;
  o.order = order;
  const SampleFitResult one = fit_samples(p.wi, p.wr, y, Eigen::VectorXd(), o);
  ASSERT_STREQ(one.solver, "QR");
  ASSERT_GT(one.null_space_dimension, 0);
  expect_split_agrees(split_fit(3, p.wi, p.wr, y, Eigen::VectorXd::Ones(rows), o), one, "QR");
  // Three samples of positive weight on four parts: one part has none.
  Eigen::VectorXd few = Eigen::VectorXd::Zero(rows);
  few.head(3).setOnes();
  SampleFitOptions o0;
  o0.order = 0;
  const SampleFitResult small = fit_samples(p.wi, p.wr, y, few, o0);
  expect_split_agrees(split_fit(4, p.wi, p.wr, y, few, o0), small, "three samples on four parts");
}

// fit_samples_checked split over `parts`.
std::vector<CheckedSampleFit> split_checked(int parts, const test::Pairs& p, const Eigen::MatrixXd& y, const SampleFitPlan& plan) {
  return run_parts<CheckedSampleFit>(parts, [&](std::shared_ptr<const SampleFitSplit> split) {
    SampleFitPlan pq = plan;
    pq.options.split = std::move(split);
    return fit_samples_checked(p.wi, p.wr, y, Eigen::VectorXd(), pq);
  });
}

// The checked fit with every choice automatic: the order by 5-fold cross-validation (the folds' normal
// equations summed over the parts), lambda by GCV, the CV error of the final fit; and a given order with
// single-precision Gram products, whose folds' held-out passes are summed too. Every part makes the same choices and reaches
// one process's fit. In-plane samples against the general modes take the isotropic fallback, also split.
TEST(SampleFitSplit, TheCheckedFitChoosesAsOneProcessDoes) {
  const int rows = 3000;
  const test::Pairs p = test::random_pairs(rows, 91);
  const Eigen::MatrixXd y = helmholtz_modes_eval(3, p.wi, p.wr) * random_vector(helmholtz_mode_count(3), 92) + 0.01 * random_vector(rows, 93);
  for (GramPrecision gram : {GramPrecision::Double, GramPrecision::Single}) {
    SampleFitPlan plan;
    plan.options.gram = gram;
    if (gram == GramPrecision::Double) {  // every choice automatic (the cross-validation of orders assembles in double)
      plan.choose_order = true;
      plan.choose_tikhonov = true;
      plan.max_order = 5;
    } else {  // a given order: the folds in single precision, their held-out passes summed
      plan.options.order = 3;
    }
    const CheckedSampleFit one = fit_samples_checked(p.wi, p.wr, y, Eigen::VectorXd(), plan);
    ASSERT_EQ(one.order_choice, gram == GramPrecision::Double ? "cross-validation" : "given");
    ASSERT_STREQ(one.fit.solver, gram == GramPrecision::Double ? "normal equations" : kSingleGramSolver);
    for (int parts : {2, 3}) {
      const auto split = split_checked(parts, p, y, plan);
      for (size_t q = 0; q < split.size(); ++q) {
        const CheckedSampleFit& c = split[q];
        EXPECT_EQ(c.fit.order, one.fit.order) << "part " << q;
        EXPECT_EQ(c.order_cv.chosen, one.order_cv.chosen) << "part " << q;
        for (size_t i = 0; i < one.order_cv.rms.size(); ++i)
          if (one.order_cv.determined[i]) {
            EXPECT_NEAR(c.order_cv.rms[i], one.order_cv.rms[i], kSplitTol * one.order_cv.rms[i]) << i;
          }
        EXPECT_NEAR(c.fit.tikhonov, one.fit.tikhonov, kSplitTol * one.fit.tikhonov) << "the same GCV grid point";
        EXPECT_NEAR(c.cv_rms, one.cv_rms, kSplitTol * one.cv_rms) << "part " << q;
        EXPECT_EQ(c.cv_rms, split[0].cv_rms) << "every part the same bits";
      }
      std::vector<SampleFitResult> fits;
      for (const auto& c : split) fits.push_back(c.fit);
      expect_split_agrees(fits, one.fit, gram == GramPrecision::Double ? "checked, double" : "checked, single");
    }
  }
  // In plane: the general modes of order 3 are not determined; the isotropic ones are.
  test::Pairs plane;
  plane.wi = p.wi;
  plane.wr = p.wr;
  plane.wi.col(1).setZero();
  plane.wr.col(1).setZero();
  plane.wi.rowwise().normalize();
  plane.wr.rowwise().normalize();
  // Noisy, as measurements are: on exact values the GCV curve is flat down to rounding and its minimum (the
  // lambda the fallback message names) moves a grid point with the order of the sums.
  const Eigen::MatrixXd yp = isotropic_modes_eval(3, plane.wi, plane.wr) * random_vector(isotropic_mode_count(3), 94) +
                             kInPlaneNoise * random_vector(plane.wi.rows(), 95);
  SampleFitPlan plan;
  plan.options.order = 3;
  const CheckedSampleFit one = fit_samples_checked(plane.wi, plane.wr, yp, Eigen::VectorXd(), plan);
  ASSERT_FALSE(one.fallback.empty());
  const auto split = split_checked(3, plane, yp, plan);
  std::vector<SampleFitResult> fits;
  for (const auto& c : split) {
    EXPECT_EQ(c.fallback, one.fallback);
    fits.push_back(c.fit);
  }
  expect_split_agrees(fits, one.fit, "in-plane fallback");
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
