// Measured data judged against their reciprocal part (icobrdf/pipeline/held_out.hpp): the data's own asymmetry
// over the held-out pairs, the reference (f + f^T)/2, and the raw data with reciprocal = false.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/basis/antisymmetric_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/sample_csv.hpp"
#include "icobrdf/pipeline/exchanged_pairs.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Sums over 256 pairs of products of cosines, and the errors of exact values: rounding only.
constexpr double kRounding = 1e-13;
// A least-squares projection of a constant onto the modes: rounding of the Gram system (Gram error <= 0.1 is
// what the fit accepts; a constant is the first mode, recovered to ~1e-13 on these grids).
constexpr double kProjectionRounding = 1e-10;

// f = a + b (cos theta_i - cos theta_r): the reciprocal part is a, the antisymmetric part b (cos_i - cos_r).
constexpr double kA = 0.3, kB = 0.2;
std::unique_ptr<BrdfSource> tilted_source() {
  auto values = [](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    out.col(0) = (kA + kB * (wi.col(2) - wr.col(2)).array()).matrix();
  };
  return model_source(std::make_unique<FunctionModel>(1, values, "tilted", true, false));
}

// Lights and cameras at cos theta = (k + 1/2) / N (the midpoint nodes u_k), at azimuths that differ.
constexpr int kNodes = 16;
SceneMaterial on_nodes() {
  SceneMaterial m;
  m.name = "tilted";
  m.source = "model:tilted";
  for (int k = 0; k < kNodes; ++k) {
    const double theta = std::acos((k + 0.5) / kNodes) * 180 / M_PI;
    m.lights.push_back({theta, 17.0 * k});
    m.cameras.push_back({theta, 180 + 11.0 * k});
  }
  return m;
}

// The cosine-weighted asymmetry over all light x camera pairs (u, v) of the nodes, with S_p = sum_k u_k^p:
//   sum u^2 v^2 (b (u - v))^2        = b^2 (2 S4 S2 - 2 S3^2)
//   sum u^2 v^2 (a + b (u - v))^2    = a^2 S2^2 + b^2 (2 S4 S2 - 2 S3^2)   (the cross term cancels)
double expected_asymmetry() {
  double s2 = 0, s3 = 0, s4 = 0;
  for (int k = 0; k < kNodes; ++k) {
    const double u = (k + 0.5) / kNodes;
    s2 += u * u;
    s3 += u * u * u;
    s4 += u * u * u * u;
  }
  const double anti = kB * kB * (2 * s4 * s2 - 2 * s3 * s3);
  return std::sqrt(anti / (kA * kA * s2 * s2 + anti));
}

TEST(Reciprocity, AsymmetryOfAKnownAntisymmetricPartAndTheReferenceIsItsReciprocalPart) {
  const auto src = tilted_source();
  ASSERT_FALSE(src->reciprocal_by_construction());
  const Scene s;
  const SceneMaterial m = on_nodes();
  ASSERT_EQ(m.metric, ErrorMetric::Cosine);
  const HeldOutSplit h = held_out_split(s, m, *src);
  EXPECT_NEAR(h.asymmetry, expected_asymmetry(), kRounding);
  EXPECT_GT(h.asymmetry, 0.05);  // far from rounding: the test can fail
  ASSERT_TRUE(h.reciprocal_reference);
  EXPECT_LT((h.pairs.f.array() - kA).abs().maxCoeff(), kRounding);  // the reference is the reciprocal part a
  // The symmetric part itself has no error against the reciprocal reference, and the asymmetry against the raw data.
  const Eigen::MatrixXd symmetric = Eigen::MatrixXd::Constant(h.pairs.f.rows(), 1, kA);
  EXPECT_LT(HeldOutErrors(h.pairs, 0, m.metric, true).of_values(symmetric).l2, kRounding);
  SceneMaterial raw = m;
  raw.reciprocal = false;
  const HeldOutSplit r = held_out_split(s, raw, *src);
  EXPECT_FALSE(r.reciprocal_reference);
  EXPECT_NEAR(r.asymmetry, expected_asymmetry(), kRounding);
  EXPECT_NEAR(HeldOutErrors(r.pairs, 0, m.metric).of_values(symmetric).l2, expected_asymmetry(), kRounding);
}

// A scene of modes alone up to order 2 (f is exactly of order 2).
Scene modes_scene(std::vector<int> levels) {
  Scene s;
  s.levels = std::move(levels);
  s.order_max = 2;
  s.representations = {"modes"};
  return s;
}

// The builder's modes (reciprocal by construction) fit the symmetric part a: an order-0 spectrum whose error
// against the reciprocal part is rounding, while the raw data's asymmetry is reported beside it.
TEST(Reciprocity, ModesOfTheSymmetricPartMeetATargetBelowTheAsymmetry) {
  const auto src = tilted_source();
  const Scene s = modes_scene({1, 2});
  SceneMaterial m = on_nodes();
  m.target = 1e-6;
  const HeldOutSplit h = held_out_split(s, m, *src);
  const HeldOutErrors errors(h.pairs, s.order_max, m.metric, h.reciprocal_reference);
  FitContexts contexts;
  const MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  const MaterialCandidate c = choose_representation(p);
  EXPECT_EQ(c.order, 0);
  EXPECT_LT(c.error.l2, kProjectionRounding);
  EXPECT_GT(h.asymmetry, m.target);
}

// reciprocal = false keeps the antisymmetric terms (paper section 2B). With rho^2 = 1 - cos theta and
// R_2^0 = 2 rho^2 - 1, cos theta = (1 - R_2^0(rho))/2, so
//   a                      = 2 pi a I_00^0                  (I_00^0 = 1/(2 pi))
//   b (cos_i - cos_r)      = -(b/2) (R_2^0(rho_i) - R_2^0(rho_r)) = -pi sqrt(2/3) b J_20^0
//                                                           (J_20^0 = sqrt(3/2)/(2 pi) (R_2^0(rho_i) - R_2^0(rho_r)))
// so the modes hold f exactly at order 2 with two coefficients: IBSSS (0,0,0) = 2 pi a and J (2,0,0) =
// -pi sqrt(2/3) b, the symmetric part evaluating to a and the antisymmetric part to b (cos_i - cos_r).
TEST(Reciprocity, AntisymmetricTermsHoldTheKnownAntisymmetricPart) {
  const auto src = tilted_source();
  const Scene s = modes_scene({2, 3});
  SceneMaterial m = on_nodes();
  m.target = 1e-6;
  m.reciprocal = false;
  const HeldOutSplit h = held_out_split(s, m, *src);
  ASSERT_FALSE(h.reciprocal_reference);
  const HeldOutErrors errors(h.pairs, s.order_max, m.metric, false);
  FitContexts contexts;
  const MaterialProblem p{s, m, *src, &errors, contexts, [](const std::string&) {}};
  const MaterialCandidate c = choose_representation(p);
  EXPECT_EQ(c.order, 2);
  EXPECT_TRUE(c.isotropic);
  EXPECT_LT(c.error.l2, kProjectionRounding);  // the raw data, asymmetry included
  EXPECT_EQ(c.kept, 2);
  const Eigen::MatrixXd& C = c.record.spectrum.channels.at(0);
  const Eigen::VectorXd sym = ibsss_from_coefficients(C), anti = isotropic_antisymmetric_from_coefficients(C);
  EXPECT_NEAR(sym[0], 2 * M_PI * kA, kProjectionRounding);
  EXPECT_LT(sym.tail(sym.size() - 1).cwiseAbs().maxCoeff(), kProjectionRounding);
  const auto modes = isotropic_antisymmetric_modes(2);
  for (size_t k = 0; k < modes.size(); ++k) {
    const bool j200 = modes[k].n == 2 && modes[k].m == 0 && modes[k].l == 0;
    EXPECT_NEAR(anti[static_cast<Eigen::Index>(k)], j200 ? -M_PI * std::sqrt(2.0 / 3.0) * kB : 0.0, kProjectionRounding);
  }
  // The split at the held-out pairs: symmetric part a, antisymmetric part b (cos_i - cos_r).
  const Eigen::MatrixXd half_sum = errors.modes_values({0.5 * (C + C.transpose())}, 2);
  const Eigen::MatrixXd half_diff = errors.modes_values({0.5 * (C - C.transpose())}, 2);
  const Eigen::ArrayXd expected_anti = kB * (h.pairs.wi.col(2) - h.pairs.wr.col(2)).array();
  EXPECT_LT((half_sum.array() - kA).abs().maxCoeff(), kProjectionRounding);
  EXPECT_LT((half_diff.col(0).array() - expected_anti).abs().maxCoeff(), kProjectionRounding);
  // The reciprocal modes of the same data miss the raw data by exactly its asymmetry.
  m.reciprocal = true;
  const MaterialProblem q{s, m, *src, &errors, contexts, [](const std::string&) {}};
  m.target = 1.01 * expected_asymmetry();  // met at order 0 (the symmetric part a exactly), not with no coefficient
  const MaterialCandidate r = choose_representation(q);
  EXPECT_NEAR(r.error.l2, expected_asymmetry(), kProjectionRounding);
}

TEST(Reciprocity, ReciprocalSourcesHaveNoAsymmetryAndKeepTheirValues) {
  Scene s;
  s.holdout_pairs = 64;
  SceneMaterial m;
  m.name = "g";
  m.source = "model:ggx:alpha=0.3";
  const auto src = open_source(m.source);
  EXPECT_TRUE(src->reciprocal_by_construction());
  const HeldOutSplit h = held_out_split(s, m, *src);
  EXPECT_EQ(h.asymmetry, 0.0);
  EXPECT_FALSE(h.reciprocal_reference);
  EXPECT_EQ(h.pairs.f, src->eval(h.pairs.wi, h.pairs.wr));
}

// CSV samples in exchanged pairs (k, k'): f = (1 - e) g_k at (w_i, w_r) and (1 + e) g_k at (w_r, w_i). Where both
// are held out, f - (f + f^T)/2 = -/+ e g_k, so over those pairs the asymmetry is
//   sqrt(sum w^2 e^2 g^2 * 2 / sum w^2 g^2 ((1 - e)^2 + (1 + e)^2)) = e / sqrt(1 + e^2)
// whatever g and w (w = cos_i cos_r is the same for both). No two other samples are within 1 degree of an exchange.
constexpr double kE = 0.25;
std::string write_exchanged_samples(const test::ScratchDir& d) {
  const std::string p = d / "x.csv";
  std::ofstream out(p);
  out << "theta_i,phi_i,theta_r,phi_r,value\n";
  for (int k = 0; k < 300; ++k) {
    const double ti = 10 + 7 * (k % 10), tr = 12 + 7 * ((k / 10) % 10), pr = 20 + 100 * (k / 100), g = 0.2 + 0.01 * (k % 13);
    out << ti << ",0," << tr << "," << pr << "," << (1 - kE) * g << "\n";
    out << tr << "," << pr << "," << ti << ",0," << (1 + kE) * g << "\n";
  }
  return p;
}

TEST(Reciprocity, SamplesAreJudgedAgainstTheReciprocalPartWhereHeldOutSamplesAreExchanges) {
  test::ScratchDir d;
  const auto src = open_source(write_exchanged_samples(d));
  EXPECT_FALSE(src->reciprocal_by_construction());
  const Scene s;
  SceneMaterial m;
  m.name = "x";
  m.source = src->spec();
  const HeldOutSplit h = held_out_split(s, m, *src);
  EXPECT_NEAR(h.asymmetry, kE / std::sqrt(1 + kE * kE), kRounding);
  SceneMaterial raw = m;
  raw.reciprocal = false;
  const HeldOutSplit r = held_out_split(s, raw, *src);
  EXPECT_NEAR(r.asymmetry, h.asymmetry, kRounding);
  ASSERT_EQ(r.pairs.f.rows(), h.pairs.f.rows());
  // The exchanged held-out samples (both of each pair) take g; the others keep their raw values.
  int changed = 0;
  for (Eigen::Index k = 0; k < h.pairs.f.rows(); ++k) {
    if (h.pairs.f(k, 0) == r.pairs.f(k, 0)) continue;
    ++changed;
    const double ratio = r.pairs.f(k, 0) / h.pairs.f(k, 0);
    EXPECT_TRUE(std::abs(ratio - (1 - kE)) < kRounding || std::abs(ratio - (1 + kE)) < kRounding) << ratio;
  }
  EXPECT_GT(changed, 0);
  EXPECT_EQ(changed % 2, 0);
  EXPECT_LT(changed, h.pairs.f.rows());
}

// All 600 samples of the file are in exchanged pairs: the fraction `icobrdf fit` reports is e / sqrt(1 + e^2) for
// either metric (w is the same for both samples of a pair), and every pair differs by |(1+e) - (1-e)| / 1 = 2e.
TEST(Reciprocity, EveryExchangedSamplePairOfAFileGivesItsNonReciprocalFraction) {
  test::ScratchDir d;
  const BrdfSamples samples = read_sample_csv(write_exchanged_samples(d));
  ASSERT_EQ(samples.wi.rows(), 600);
  for (const bool cosine : {false, true}) {
    const ExchangedAsymmetry a = exchanged_asymmetry(samples.wi, samples.wr, samples.values, cosine, kSwapToleranceDeg);
    EXPECT_EQ(a.samples, 600);
    EXPECT_NEAR(a.asymmetry, kE / std::sqrt(1 + kE * kE), kRounding);
    EXPECT_NEAR(a.median_relative_difference, 2 * kE, kRounding);
  }
  // Every second sample (the partners, written right after theirs) turned about the normal by 40 degrees: no
  // exact exchange is left, but each is its partner's exchange up to that rotation (an isotropic surface's
  // reciprocal partner, as CURET pairs its geometries), with the same fraction.
  RowMatrix3d wi = samples.wi, wr = samples.wr;
  const double c = std::cos(40 * M_PI / 180), s = std::sin(40 * M_PI / 180);
  for (Eigen::Index k = 1; k < wi.rows(); k += 2)
    for (RowMatrix3d* w : {&wi, &wr}) {
      const double x = (*w)(k, 0), y = (*w)(k, 1);
      (*w)(k, 0) = c * x - s * y;
      (*w)(k, 1) = s * x + c * y;
    }
  EXPECT_EQ(exchanged_asymmetry(wi, wr, samples.values, false, kSwapToleranceDeg).samples, 0);
  const ExchangedAsymmetry turned = exchanged_asymmetry(wi, wr, samples.values, false, kSwapToleranceDeg, true);
  EXPECT_EQ(turned.samples, 600);
  EXPECT_NEAR(turned.asymmetry, kE / std::sqrt(1 + kE * kE), kRounding);
  // One sample alone has no partner: not measurable.
  const ExchangedAsymmetry none = exchanged_asymmetry(samples.wi.topRows(1), samples.wr.topRows(1), samples.values.topRows(1), false, kSwapToleranceDeg);
  EXPECT_EQ(none.samples, 0);
  EXPECT_TRUE(std::isnan(none.asymmetry));
}

}  // namespace
}  // namespace icobrdf
