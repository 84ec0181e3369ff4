// The half-angle search on measured data (icobrdf/pipeline/half_angle_representation.hpp): a target below the
// data's noise keeps the best lobe within the budget, and the report explains the
// miss by the noise (icobrdf/pipeline/material_report.hpp kNoiseMargin); the search visits the budget grids'
// (n_t, d grid) pairs (icobrdf/pipeline/lobe_budget.hpp) at the largest n_t the bytes allow, and its work cap
// ends it.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/lobe_budget.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// f = g (1 + e n(w_i, w_r)) with g = 1/pi (Lambert: a rank-1 lobe in the mean-cosine quantity, cos_i + cos_r
// = 2 cos theta_h cos theta_d) and n of unit variance, drawn independently for each ordered pair (hash of the
// eight coordinates' bits), so that n(a, b) and n(b, a) are independent. Then, in expectation over the pairs,
//   asymmetry^2            = |w g e (n_ab - n_ba)/2|^2 / |w g|^2 = e^2 / 2
//   |w (g - f_rec)|^2/|w f_rec|^2 = |w g e (n_ab + n_ba)/2|^2 / |w g|^2 = e^2 / 2   (up to 1 + e^2/2)
// so a lobe holding g is the asymmetry away from the reciprocal part: the noise, not the lobe, sets the floor.
constexpr double kE = 0.1;
double noise(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Index k) {
  std::uint64_t h = 0x6e6f697365ULL;
  const double v[6] = {wi(k, 0), wi(k, 1), wi(k, 2), wr(k, 0), wr(k, 1), wr(k, 2)};
  for (const double x : v) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = splitmix64(h ^ bits);
  }
  const double u = static_cast<double>(h >> 11) * 0x1.0p-53;  // [0, 1)
  return std::sqrt(3.0) * (2 * u - 1);                        // unit variance
}

std::unique_ptr<BrdfSource> noisy_lambert() {
  auto values = [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    for (Eigen::Index k = 0; k < wi.rows(); ++k) out(k, 0) = (1 + kE * noise(wi, wr, k)) / M_PI;
  };
  return model_source(std::make_unique<FunctionModel>(1, values, "noisy-lambert", true, false));
}

// The two estimates above agree in expectation; 4,096 held-out pairs leave each a few per cent of sampling
// error, and the lobe's own interpolation error adds to the error in quadrature.
constexpr double kEstimatesAgree = 1.25;

TEST(MeasuredSearch, ATargetBelowTheNoiseKeepsTheBestLobeAndIsExplainedByTheNoise) {
  const auto src = noisy_lambert();
  ASSERT_FALSE(src->reciprocal_by_construction());
  Scene s;
  s.representations = {"half-angle", "hybrid"};
  SceneMaterial m;
  m.name = "noisy";
  m.source = "model:noisy-lambert";
  m.target = 0.02;  // below the noise e / sqrt(2) = 0.071
  m.isotropic = IsotropicChoice::Always;
  m.max_bytes = 65536;
  m.on_miss = OnMiss::KeepBest;
  const HeldOutSplit h = held_out_split(s, m, *src);
  ASSERT_TRUE(h.reciprocal_reference);
  EXPECT_NEAR(h.asymmetry, kE / std::sqrt(2.0), (kEstimatesAgree - 1) * kE / std::sqrt(2.0));
  const HeldOutErrors errors(h.pairs, 0, m.metric, true);
  FitContexts contexts;
  const auto t0 = std::chrono::steady_clock::now();
  MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  // Every grid holds g and no lobe the noise, so the search runs to its work cap: a tenth of the bank's keeps
  // the test within a second or two (the d grids up to 32x16, ranks 1-2).
  p.lobe_work_cap = 1000000;
  const MaterialCandidate c = choose_representation(p);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(c.representation, "half-angle");  // the best lobe, not a fallback to the modes (not allowed here)
  EXPECT_FALSE(c.target_met);
  EXPECT_LE(c.bytes, m.max_bytes);
  EXPECT_FALSE(c.note.empty());
  EXPECT_GT(c.error.l2, h.asymmetry / kEstimatesAgree);
  EXPECT_LT(c.error.l2, h.asymmetry * kEstimatesAgree);
  MaterialReport rep;
  rep.measured = true;
  rep.target_met = false;
  rep.error_l2 = c.error.l2;
  rep.asymmetry = h.asymmetry;
  rep.reciprocal_reference = true;
  explain_miss(c, rep);
  EXPECT_TRUE(rep.below_noise);
  EXPECT_NE(rep.note.find("noise"), std::string::npos) << rep.note;
  std::cout << "noisy Lambert: asymmetry " << h.asymmetry << ", lobe " << c.error.l2 << " (" << c.bytes << " B), " << seconds
            << " s; " << rep.note << "\n";
}

// f = (1 + a cos(k theta_h)) / pi: with the "f" metric the quantity is f itself, a rank-1 lobe whose d factor is
// constant (linear interpolation in d is exact), so a lobe's error is the linear interpolation of cos(k theta_h)
// between t nodes (theta_h = (pi/2) t^2): of order a (k dtheta)^2 with dtheta = pi t / (n_t - 1), so 256 t nodes
// leave (255/127)^2 = 4.0x less than 128. Not reciprocal by construction (a "measured" source to the search),
// though f(a, b) = f(b, a).
constexpr double kRippleAmplitude = 0.5, kRippleWaves = 30.0;
std::unique_ptr<BrdfSource> rippled_lobe() {
  auto values = [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    for (Eigen::Index k = 0; k < wi.rows(); ++k) {
      const Eigen::Vector3d h = (wi.row(k) + wr.row(k)).transpose().normalized();
      out(k, 0) = (1 + kRippleAmplitude * std::cos(kRippleWaves * std::acos(std::clamp(h.z(), -1.0, 1.0)))) / M_PI;
    }
  };
  return model_source(std::make_unique<FunctionModel>(1, values, "rippled-lobe", true, false));
}

// A budget of 1,000 B: the former measured ladder (32x16x4, 64x32x8, 128x32x8, 128x64x16, 256x128x32) reached
// n_t = 128 at most within it (256x128x32 needs 4,400 B at rank 1), the budget grids give n_t = 256 on the 8x4
// d grid (629 B at rank 1, int16).
constexpr long long kRippleBudget = 1000;
// The target: the 128-node lobe's error over this factor. t nodes at twice the density cut the interpolation
// error 4.0x; the rest (the int8 or int16 rounding of the stored form, the cells at the horizon, the
// peak-sampled estimate) left 2.1x between the chosen 256x8x4 lobe and the 128x32x8 one (measured), so 1.5
// leaves a 256-node lobe room and no 128-node lobe a chance.
constexpr double kFinerGridGain = 1.5;

struct RippleScene {
  std::unique_ptr<BrdfSource> src = rippled_lobe();
  Scene s;
  SceneMaterial m;
  HeldOutSplit h;
  std::unique_ptr<HeldOutErrors> errors;
  FitContexts contexts;
  RippleScene() {
    s.representations = {"half-angle"};
    m.name = "rippled";
    m.source = "model:rippled-lobe";
    m.metric = ErrorMetric::F;
    m.isotropic = IsotropicChoice::Always;
    m.max_bytes = kRippleBudget;
    m.on_miss = OnMiss::KeepBest;
    h = held_out_split(s, m, *src);
    errors = std::make_unique<HeldOutErrors>(h.pairs, 0, m.metric, true);
  }
  // The held-out error of a rank-1 lobe fitted (independently of the search) on n_t x n_theta_d x n_phi_d
  // nodes, stored as int16, and its bytes.
  std::pair<double, long long> lobe_error(int n_t, int n_theta_d, int n_phi_d) const {
    HalfAngleFitOptions o;
    o.quantity = HalfAngleQuantity::F;
    o.n_t = n_t, o.n_theta_d = n_theta_d, o.n_phi_d = n_phi_d, o.fixed_rank = 1, o.max_rank = 1;
    o.precision = FactorPrecision::Int16;
    const HalfAngleFactors lobe = fit_half_angle(model_pair_sampler_of(*src), 1, o).factors;
    const auto& pairs = errors->pairs();
    return {errors->of_values(add_lobe(Eigen::MatrixXd::Zero(pairs.wi.rows(), 1), lobe, pairs.wi, pairs.wr)).l2,
            stored_lobe_bytes(1, 1, n_t, n_theta_d, n_phi_d, false, FactorPrecision::Int16)};
  }
  static PairSampler model_pair_sampler_of(const BrdfSource& source) {
    return [&source](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = source.eval(wi, wr); };
  }
};

TEST(MeasuredSearch, VisitsAnNtTheFormerLadderSkippedAndPicksItWhereItIsBetterAtEqualBytes) {
  RippleScene r;
  ASSERT_FALSE(r.src->reciprocal_by_construction());
  // The former ladder's best grid within the budget for this lobe: the most t nodes, 128x32x8 (821 B).
  const auto [coarse, coarse_bytes] = r.lobe_error(128, 32, 8);
  ASSERT_LT(coarse_bytes, kRippleBudget);
  r.m.target = coarse / kFinerGridGain;
  ASSERT_GE(r.m.target, 1e-3) << "below the smallest target a lobe is fitted for";
  const MaterialProblem p{r.s, r.m, *r.src, r.errors.get(), r.contexts, [](const std::string&) {}};
  const MaterialCandidate c = choose_representation(p);
  ASSERT_TRUE(c.record.lobe);
  const HalfAngleFactors& lobe = *c.record.lobe;
  std::cout << "rippled lobe: 128x32x8 rank 1 " << coarse << " (" << coarse_bytes << " B); chosen " << lobe.n_t << "x" << lobe.n_theta_d << "x"
            << lobe.n_phi_d << " rank " << lobe.rank << " " << c.error.l2 << " (" << c.bytes << " B)\n";
  EXPECT_TRUE(c.target_met);
  EXPECT_LE(c.error.l2, r.m.target);
  EXPECT_LE(c.bytes, kRippleBudget);
  EXPECT_GT(lobe.n_t, 128);                           // no step of the former ladder within the budget had it
  EXPECT_LE(lobe.n_theta_d * lobe.n_phi_d, 8 * 4);  // the first d grid of the budget grids already meets it
}

TEST(MeasuredSearch, AWorkCapEndsTheSearchAndTheNoteSaysSo) {
  RippleScene r;
  r.m.target = 1e-3;  // out of reach of a rank-1 lobe on these grids (the interpolation alone is above it)
  MaterialProblem p{r.s, r.m, *r.src, r.errors.get(), r.contexts, [](const std::string&) {}};
  // Room for the first lobe only: rank 1 on 256 x 8x4 (8,192 node-terms); rank 2 there (n_t 192 within the
  // budget) would need 12,288 more.
  p.lobe_work_cap = 256 * 8 * 4;
  const MaterialCandidate c = choose_representation(p);
  ASSERT_TRUE(c.record.lobe);
  EXPECT_FALSE(c.target_met);
  EXPECT_EQ(c.record.lobe->rank, 1);
  EXPECT_EQ(c.record.lobe->n_theta_d * c.record.lobe->n_phi_d, 8 * 4);
  EXPECT_NE(c.note.find("work cap (8192 node-terms)"), std::string::npos) << c.note;
  EXPECT_NE(c.note.find("error against bytes"), std::string::npos) << c.note;
  std::cout << c.note << "\n";
}

// Lambert as measured data (not reciprocal by construction), cosine metric: the search fits the metric's own
// quantity q = f cos(theta_i) cos(theta_r) (kMeasuredLobeQuantity). In half-angle coordinates
//   cos_i cos_r = (cos th cos td)^2 - (sin th sin td cos pd)^2,
// exactly rank 2, so the chosen lobe holds q at every node on or above the horizon up to its storage rounding
// (kNodeRounding), whatever grid the search ends on.
// Largest node deviation, as a share of q's largest value 1/pi: int8 storage rounds each factor to 1/254 of its
// column's largest value (two factors, two terms: 0.016 at most); a rank-1 lobe misses q by up to 0.25 there.
constexpr double kNodeRounding = 2e-2;
constexpr double kLambertTarget = 0.05;  // met on the first d grids (interpolation of q between nodes only)
std::unique_ptr<BrdfSource> measured_lambert() {
  auto values = [](const RowMatrix3d&, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) { out.col(0).setConstant(1.0 / M_PI); };
  return model_source(std::make_unique<FunctionModel>(1, values, "measured-lambert", true, false));
}

TEST(MeasuredSearch, ALambertBodyIsHeldExactlyAtTheNodesInTheMetricsQuantity) {
  const auto src = measured_lambert();
  ASSERT_FALSE(src->reciprocal_by_construction());
  Scene s;
  s.representations = {"half-angle"};
  SceneMaterial m;
  m.name = "lambert";
  m.source = "model:measured-lambert";
  m.target = kLambertTarget;
  m.isotropic = IsotropicChoice::Always;
  m.max_bytes = 65536;
  const HeldOutSplit h = held_out_split(s, m, *src);
  const HeldOutErrors errors(h.pairs, 0, m.metric, true);
  FitContexts contexts;
  MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  p.lobe_work_cap = 1000000;
  const MaterialCandidate c = choose_representation(p);
  ASSERT_TRUE(c.record.lobe);
  const HalfAngleFactors& lobe = *c.record.lobe;
  EXPECT_TRUE(c.target_met);
  EXPECT_EQ(lobe.quantity, HalfAngleQuantity::Cosine);
  ASSERT_GE(lobe.rank, 1);
  ASSERT_EQ(lobe.u.size(), 1u);
  double worst = 0.0;
  int valid = 0;
  for (int k = 0; k < lobe.n_t; ++k)
    for (int a = 0; a < lobe.n_theta_d; ++a)
      for (int b = 0; b < lobe.n_phi_d; ++b) {
        const double th = lobe.theta_h_of_t(lobe.node_t(k)), td = lobe.node_theta_d(a), pd = lobe.node_phi_d(b);
        const double along = std::cos(th) * std::cos(td), across = std::sin(th) * std::sin(td) * std::cos(pd);
        if (along < std::abs(across)) continue;  // a direction below the horizon: not a node the data give
        ++valid;
        const double q = (along * along - across * across) / M_PI;
        const double fitted = lobe.u[0].row(k).dot(lobe.v[0].row(static_cast<Eigen::Index>(a) * lobe.n_phi_d + b));
        worst = std::max(worst, std::abs(fitted - q));
      }
  std::cout << "Lambert as measured data: " << lobe.n_t << "x" << lobe.n_theta_d << "x" << lobe.n_phi_d << " rank " << lobe.rank << ", error "
            << c.error.l2 << ", worst node deviation " << worst * M_PI << " of 1/pi over " << valid << " nodes\n";
  EXPECT_GT(valid, 0);
  EXPECT_LE(worst, kNodeRounding / M_PI);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
