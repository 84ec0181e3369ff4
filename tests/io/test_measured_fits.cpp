// Checked sample fits (icobrdf/core/fit/sample_fit_selection.hpp) of real measurements (tests/data/measured):
// the 61 CURET materials at the orders Koenderink & van Doorn fitted (2, 4, 8), held-out errors against the
// database's own reciprocity noise, and NIST's PTFE at 532 nm, fitted on its regular grid and predicting its
// random geometries.
#include <gtest/gtest.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "icobrdf/io/curet.hpp"
#include "icobrdf/io/sample_csv.hpp"
#include "measured_fixtures.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::measured_fixture;

// The relative RMS levels of Koenderink & van Doorn's CURET statement ("many BRDF's are well represented by the
// order 2 fit, and all BRDF's are accurately fitted by the order 8 fit"), as the issue counts them.
constexpr double kGoodFit = 0.05;
constexpr double kFairFit = 0.10;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Relative RMS of a prediction: ||p - y|| / ||y||.
double relative_rms(const Eigen::VectorXd& p, const Eigen::VectorXd& y) { return (p - y).norm() / y.norm(); }

SampleFitPlan given_plan(int order, bool isotropic) {
  SampleFitPlan plan;
  plan.options.order = order;
  plan.options.isotropic = isotropic;
  return plan;
}

SampleFitPlan automatic_plan() {
  SampleFitPlan plan;
  plan.choose_order = plan.choose_class = plan.choose_tikhonov = true;
  return plan;
}

// Every material at orders 2, 4 and 8 of the isotropic modes: fitted (regularized where the least-squares fit is
// not bounded by the 205 samples, never refused), and at order 8 at least as many below 5% and 10% relative RMS
// as plain least squares on the same modes (Eigen's column-pivoting QR of the modes at the samples).
TEST(MeasuredFits, CuretAllMaterialsAtOrders248) {
  const CuretDatabase db = read_curet(measured_fixture("abrdf.dat"), measured_fixture("table.txt"));
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(db.wi.rows());
  for (int order : {2, 4, 8}) {
    const Eigen::MatrixXd a = sample_fit_modes(order, true, db.wi, db.wr);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    std::vector<double> fit_rel, ls_rel;
    int regularized = 0;
    for (Eigen::Index s = 0; s < db.values.rows(); ++s) {
      const Eigen::VectorXd y = db.values.row(s).transpose();
      CheckedSampleFit c;
      ASSERT_NO_THROW(c = fit_samples_checked(db.wi, db.wr, Eigen::MatrixXd(y), ones, given_plan(order, true)))
          << "sample " << db.sample_numbers[static_cast<size_t>(s)] << " order " << order;
      EXPECT_EQ(c.fit.order, order);
      EXPECT_LE(c.max_abs_fit, kScaleGuardFactor * c.max_abs_sample);
      regularized += c.regularized_for_bound;
      fit_rel.push_back(relative_rms(a * c.fit.modes.col(0), y));
      ls_rel.push_back(relative_rms(a * qr.solve(y), y));
    }
    auto below = [](const std::vector<double>& v, double t) { return std::count_if(v.begin(), v.end(), [t](double x) { return x < t; }); };
    std::printf("CURET isotropic order %d (%d unknowns): checked fit median rel. RMS %.4f, %ld/61 < 5%%, %ld/61 < 10%% "
                "(%d regularized); plain LS median %.4f, %ld/61 < 5%%, %ld/61 < 10%%\n",
                order, sample_fit_unknowns(order, true), median(fit_rel), static_cast<long>(below(fit_rel, kGoodFit)),
                static_cast<long>(below(fit_rel, kFairFit)), regularized, median(ls_rel), static_cast<long>(below(ls_rel, kGoodFit)),
                static_cast<long>(below(ls_rel, kFairFit)));
    if (order == 8) {
      EXPECT_GE(below(fit_rel, kGoodFit), below(ls_rel, kGoodFit));
      EXPECT_GE(below(fit_rel, kFairFit), below(ls_rel, kFairFit));
    }
  }
  // No option: the class and order chosen by cross-validation on all 205 samples (reported, not asserted here:
  // the held-out test below judges the choice).
  std::vector<double> auto_rel;
  std::vector<int> orders(kMaxAutoOrderIsotropic + 1, 0);
  int isotropic = 0;
  for (Eigen::Index s = 0; s < db.values.rows(); ++s) {
    const Eigen::VectorXd y = db.values.row(s).transpose();
    const CheckedSampleFit c = fit_samples_checked(db.wi, db.wr, Eigen::MatrixXd(y), ones, automatic_plan());
    isotropic += c.fit.isotropic;
    ++orders[static_cast<size_t>(c.fit.order)];
    auto_rel.push_back(relative_rms(sample_fit_modes(c.fit.order, c.fit.isotropic, db.wi, db.wr) * c.fit.modes.col(0), y));
  }
  std::printf("CURET no option: %d of 61 isotropic, median rel. RMS %.4f; orders:", isotropic, median(auto_rel));
  for (size_t n = 0; n < orders.size(); ++n)
    if (orders[n]) std::printf(" %zu:%d", n, orders[n]);
  std::printf("\n");
}

// Held-out samples: each material fitted with no option (class, order and lambda chosen) on the geometries
// k % 5 != 2, predicting the 41 others. The bound is the data's own noise: two measurements of reciprocal
// geometries (the same BRDF value in theory) differ by a median relative |f1 - f2| / mean over the 29 pairs x
// 61 materials (both values > 0); a prediction should not be further from a measurement than a second
// measurement is.
TEST(MeasuredFits, CuretHeldOutErrorWithinTheReciprocityNoise) {
  const CuretDatabase db = read_curet(measured_fixture("abrdf.dat"), measured_fixture("table.txt"));
  std::vector<double> reciprocal;
  for (Eigen::Index s = 0; s < db.values.rows(); ++s)
    for (const auto& [a, b] : db.reciprocal_pairs) {
      const double x = db.values(s, a), y = db.values(s, b);
      if (x > 0 && y > 0) reciprocal.push_back(std::abs(x - y) / (0.5 * (x + y)));
    }
  const double noise = median(reciprocal);
  std::vector<Eigen::Index> train, held;
  for (Eigen::Index k = 0; k < db.wi.rows(); ++k) (k % 5 == 2 ? held : train).push_back(k);
  const RowMatrix3d wi = db.wi(train, Eigen::all), wr = db.wr(train, Eigen::all);
  const RowMatrix3d hi = db.wi(held, Eigen::all), hr = db.wr(held, Eigen::all);
  std::vector<double> errors;
  int isotropic = 0;
  std::vector<int> orders(kMaxAutoOrderIsotropic + 1, 0);
  for (Eigen::Index s = 0; s < db.values.rows(); ++s) {
    const Eigen::VectorXd y = db.values.row(s).transpose();
    const CheckedSampleFit c = fit_samples_checked(wi, wr, Eigen::MatrixXd(y(train)), Eigen::VectorXd(), automatic_plan());
    isotropic += c.fit.isotropic;
    ++orders[static_cast<size_t>(c.fit.order)];
    const Eigen::VectorXd p = sample_fit_modes(c.fit.order, c.fit.isotropic, hi, hr) * c.fit.modes.col(0);
    for (size_t k = 0; k < held.size(); ++k)
      if (y(held[k]) > 0) errors.push_back(std::abs(p(static_cast<Eigen::Index>(k)) - y(held[k])) / y(held[k]));
  }
  std::printf("CURET held-out: median relative error %.4f over %zu held-out values; reciprocal pairs median %.4f (%zu pairs); "
              "%d of 61 isotropic; orders:", median(errors), errors.size(), noise, reciprocal.size(), isotropic);
  for (size_t n = 0; n < orders.size(); ++n)
    if (orders[n]) std::printf(" %zu:%d", n, orders[n]);
  std::printf("\n");
  EXPECT_GT(errors.size(), 61u * 30u);
  EXPECT_LE(median(errors), noise);
}

// NIST PTFE at 532 nm, no option: the isotropic modes of order 7 (Germer's own choice for these data) win the
// cross-validation against the general modes, whose samples lie in one plane of incidence (phi_i = 0 or
// 180 deg) and so cannot determine their anisotropic part.
// Held out: the 1,760 random geometries NIST measured separately, predicted by the fit of the 1,824 regular
// ones. The bound is Germer's own order-7 fit (PTFE.532.coeff.csv) at those geometries: RMS 0.00476 1/sr
// (ptfe_eval.py of /work/data, tests/data/measured/README.md); the fit must predict them no worse than
// kPredictionSlack times that.
constexpr double kPtfeCvBound = 0.0034;       // 1/sr: the bound for the isotropic order-7 CV RMS
constexpr double kNistHeldOutRms = 0.00476;   // 1/sr: Germer's fit at ptfe532_random.csv
constexpr double kPredictionSlack = 1.1;      // a refit of the same data, 10% for its different (penalized) estimate
TEST(MeasuredFits, PtfeChoosesIsotropicOrder7AndPredictsTheRandomGeometries) {
  const BrdfSamples s = read_sample_csv(measured_fixture("ptfe532.csv"));
  EXPECT_EQ(s.wi.rows(), 1824);
  EXPECT_EQ(s.signed_theta_rows, 1824);  // NIST's thetai = -0.001 ... -75
  const CheckedSampleFit c = fit_samples_checked(s.wi, s.wr, s.values, s.weights, automatic_plan());
  EXPECT_TRUE(c.fit.isotropic);
  EXPECT_EQ(c.fit.order, 7);
  EXPECT_EQ(c.class_choice, "cross-validation");
  EXPECT_LE(c.cv_rms, kPtfeCvBound);
  EXPECT_LT(c.cv_rms_isotropic, c.cv_rms_general);
  const BrdfSamples r = read_sample_csv(measured_fixture("ptfe532_random.csv"));
  ASSERT_EQ(r.wi.rows(), 1760);
  const Eigen::VectorXd p = sample_fit_modes(c.fit.order, true, r.wi, r.wr) * c.fit.modes.col(0);
  const double held = std::sqrt((p - r.values.col(0)).squaredNorm() / static_cast<double>(p.size()));
  std::printf("PTFE 532 nm: isotropic %d order %d, CV RMS %.5f (isotropic %.5f, general %.5f), residual RMS %.5f, lambda %.3g, "
              "held-out RMS at the random geometries %.5f 1/sr\n",
              c.fit.isotropic ? 1 : 0, c.fit.order, c.cv_rms, c.cv_rms_isotropic, c.cv_rms_general, c.fit.residual_rms[0],
              c.fit.tikhonov, held);
  EXPECT_LE(held, kPredictionSlack * kNistHeldOutRms);
}

}  // namespace
}  // namespace icobrdf
