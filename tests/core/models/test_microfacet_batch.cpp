// The vectorized batch evaluation of the microfacet models (MicrofacetModel::eval, the dispatched kernel of
// icobrdf/core/models/microfacet_kernel.hpp) against the pair-by-pair formula (value()) for GGX and Beckmann with every
// Fresnel and masking choice, the exact (bitwise) reciprocity of the batch path, and eval_row (one incident
// direction against many, the incident side taken once) against eval with that direction repeated, bit for
// bit, for the microfacet models and a sum of models: each on every SIMD target compiled in that this CPU runs.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <memory>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/microfacet.hpp"
#include "icobrdf/core/models/microfacet_kernel.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/simd_target.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

// Batch and pair-by-pair use the same formulas with the normalization of h folded differently and Highway's
// vectorized exp (<= 1 ulp from std::exp by its documentation): a few ulps, amplified by the exponent t (<= ~40
// where f >= 1, relative error ~ t ulp) to < 1e-13.
constexpr double kReorderTol = 1e-13;

MicrofacetParams beckmann(double alpha, FresnelMode fresnel, SmithMasking masking) {
  MicrofacetParams p;
  p.distribution = MicrofacetDistribution::Beckmann;
  p.alpha_x = p.alpha_y = alpha;
  p.fresnel = fresnel;
  p.masking = masking;
  return p;
}

// Pairs: the shared random and hard-polar-angle set (tests/core/brdf_quadrature.hpp), a LUT-row-like run of
// one replicated incident direction (the cached L path), and the hard cases: normal incidence both ways,
// grazing, double grazing, within the horizon slack, below the horizon, h horizontal (D's limit 0),
// opposite horizontal directions (no half vector).
void test_pairs(RowMatrix3d& wi, RowMatrix3d& wr) {
  const auto base = test::test_pairs(1000, 11);
  const Eigen::Index first = base.wi.rows(), run = 300;
  const double sq = std::sqrt(0.5);
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> hard = {
      {{0, 0, 1}, {0, 0, 1}},      {{1, 0, 0}, {0, 0, 1}},      {{1, 0, 0}, {0, 1, 0}},     {{1, 0, 0}, {1, 0, 0}},
      {{sq, 0, sq}, {-sq, 0, sq}}, {{1, 0, -1e-13}, {0, 0, 1}}, {{0, 0.6, -0.8}, {0, 0, 1}}, {{0.6, 0.8, 0}, {0.8, -0.6, 0}},
      {{1, 0, 0}, {-1, 0, 0}}};
  const Eigen::Index n = first + run + static_cast<Eigen::Index>(hard.size());
  wi = base.wi;
  wr = base.wr;
  wi.conservativeResize(n, 3);
  wr.conservativeResize(n, 3);
  for (Eigen::Index k = 0; k < run; ++k) {
    wi.row(first + k) = base.wi.row(7);
    wr.row(first + k) = base.wr.row(k);
  }
  for (size_t k = 0; k < hard.size(); ++k) {
    wi.row(first + run + static_cast<Eigen::Index>(k)) = hard[k].first.transpose();
    wr.row(first + run + static_cast<Eigen::Index>(k)) = hard[k].second.transpose();
  }
}

std::vector<MicrofacetParams> cases() {
  return {beckmann(0.3, FresnelMode::Schlick, SmithMasking::HeightCorrelated),
          beckmann(0.05, FresnelMode::Dielectric, SmithMasking::Separable),
          beckmann(1.3, FresnelMode::None, SmithMasking::HeightCorrelated), beckmann(1e-3, FresnelMode::None, SmithMasking::Separable)};
}

// GGX: isotropic and anisotropic with an azimuth, every Fresnel choice (a dielectric below index 1 has total
// reflection, the g^2 < 0 branch, at grazing half-angle incidence) and both maskings.
std::vector<MicrofacetParams> ggx_cases() {
  std::vector<MicrofacetParams> out;
  MicrofacetParams p;  // GGX alpha 0.3, Schlick, height-correlated
  out.push_back(p);
  p.alpha_x = p.alpha_y = 0.02;
  p.fresnel = FresnelMode::Dielectric;
  p.ior = 1.5;
  p.masking = SmithMasking::Separable;
  out.push_back(p);
  p.alpha_x = p.alpha_y = 0.5;
  p.ior = 0.7;
  p.masking = SmithMasking::HeightCorrelated;
  out.push_back(p);
  p.anisotropic = true;
  p.alpha_x = 0.1;
  p.alpha_y = 0.5;
  p.azimuth_deg = 30;
  p.fresnel = FresnelMode::None;
  out.push_back(p);
  p.fresnel = FresnelMode::Dielectric;
  p.ior = 1.5;
  out.push_back(p);
  return out;
}

class MicrofacetOnTarget : public ::testing::TestWithParam<SimdTarget> {};

TEST_P(MicrofacetOnTarget, BatchEqualsPairByPairIncludingHardCases) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  RowMatrix3d wi, wr;
  test_pairs(wi, wr);
  const Eigen::Index n = wi.rows();
  auto all = cases();
  for (const auto& p : ggx_cases()) all.push_back(p);
  bool total_reflection_met = false;
  for (const auto& p : all) {
    const MicrofacetModel m(p);
    Eigen::MatrixXd batch(n, 1);
    m.eval(wi, wr, batch);
    // Reference: the pair-by-pair path (value() with the horizon rule of icobrdf/core/models/brdf_model.hpp).
    Eigen::MatrixXd one(n, 1);
    m.ScalarBrdfModel::eval(wi, wr, one);
    for (Eigen::Index k = 0; k < n; ++k) {
      ASSERT_TRUE(std::isfinite(batch(k, 0))) << target.name << ", " << m.spec() << " pair " << k;
      EXPECT_NEAR(batch(k, 0), one(k, 0), kReorderTol * std::max(1.0, std::abs(one(k, 0)))) << target.name << ", " << m.spec() << " pair " << k;
      if (p.fresnel == FresnelMode::Dielectric && p.ior < 1.0) {
        const Eigen::Vector3d h = (wi.row(k) + wr.row(k)).normalized();
        total_reflection_met |= batch(k, 0) > 0.0 && wi.row(k).dot(h) < std::sqrt(1.0 - p.ior * p.ior);
      }
    }
    EXPECT_EQ(batch(n - 1, 0), 0.0) << target.name << ": opposite horizontal directions";
    if (p.distribution == MicrofacetDistribution::Beckmann) {
      EXPECT_EQ(batch(n - 2, 0), 0.0) << target.name << ": h horizontal: Beckmann D's limit";
    }
    EXPECT_EQ(batch(n - 3, 0), 0.0) << target.name << ": below the horizon";
  }
  EXPECT_TRUE(total_reflection_met) << "no pair reached the dielectric's total reflection";
}

TEST_P(MicrofacetOnTarget, ExactlyReciprocalForBothDistributions) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  RowMatrix3d wi, wr;
  test_pairs(wi, wr);
  auto all = cases();
  for (const auto& p : ggx_cases()) all.push_back(p);
  for (const auto& p : all) {
    const MicrofacetModel m(p);
    Eigen::MatrixXd f(wi.rows(), 1), g(wi.rows(), 1);
    m.eval(wi, wr, f);
    m.eval(wr, wi, g);
    for (Eigen::Index k = 0; k < wi.rows(); ++k) EXPECT_EQ(f(k, 0), g(k, 0)) << target.name << ", " << m.spec() << " pair " << k;
  }
}

// Incident directions: random ones, normal incidence, grazing, within the horizon slack and below the
// horizon; remitted: the shared pairs' remitted side cut to 1 pair, one whole block of 128, a block and one
// pair, and all of them (several blocks and a short last one).
TEST_P(MicrofacetOnTarget, EvalRowIsEvalWithTheIncidentRepeatedBitForBit) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  RowMatrix3d wi_pairs, wr_pairs;
  test_pairs(wi_pairs, wr_pairs);
  std::vector<Eigen::Vector3d> incident = {{0, 0, 1}, {1, 0, 0}, {1, 0, -1e-13}, {0, 0.6, -0.8}};
  for (int k : {0, 7, 123, 456}) incident.push_back(wi_pairs.row(k).transpose());
  std::vector<std::unique_ptr<BrdfModel>> models;
  for (const char* spec : {"ggx:alpha=0.1", "ggx-aniso:alpha_x=0.4,alpha_y=0.05,azimuth=30,fresnel=dielectric,ior=1.5",
                           "ggx:alpha=0.3,masking=separable,fresnel=none", "beckmann:alpha=0.2", "beckmann:alpha=0.05,masking=separable",
                           "0.7*lambert+0.3*ggx:alpha=0.2", "0.5*lambert"})
    models.push_back(parse_model(spec));
  for (const Eigen::Index n : {Eigen::Index{1}, Eigen::Index{128}, Eigen::Index{129}, wr_pairs.rows()}) {
    const RowMatrix3d wr = wr_pairs.topRows(n);
    for (const auto& m : models)
      for (const Eigen::Vector3d& wi : incident) {
        const RowMatrix3d wi_all = wi.transpose().replicate(n, 1);
        Eigen::MatrixXd pairs(n, m->channels()), row(n, m->channels());
        m->eval(wi_all, wr, pairs);
        m->eval_row(wi, wr, row);
        Eigen::Index differ = 0;
        for (Eigen::Index k = 0; k < n; ++k)
          for (Eigen::Index c = 0; c < m->channels(); ++c) differ += pairs(k, c) == row(k, c) ? 0 : 1;
        EXPECT_EQ(differ, 0) << target.name << ", " << m->spec() << ", " << n << " pairs, wi = " << wi.transpose();
      }
  }
}

// The kernel's erfc (exp(-a^2) erfcx(a)) against glibc's std::erfc (< 1 ulp): 2 ulps of the erfcx expansion
// (scripts/derive/erfcx_chebyshev.py, against 40 digits), 1 of Highway's exp, 1 of std::erfc, 1 for the product;
// the rounding of a^2 adds a^2 ulps (relative error of exp(-a^2) is |a^2| times that of a^2).
constexpr double kErfcUlps = 5.0;
// Beyond a = 26.5 erfc < 1e-306 falls into the subnormals; only its smallness matters to the model there.
constexpr double kErfcSubnormalFrom = 26.5, kErfcSubnormalAbsTol = 1e-300;

TEST_P(MicrofacetOnTarget, ErfcIsStdErfcWithinItsUlps) {
  const SimdTarget& target = GetParam();
  if (!target.runs_here) GTEST_SKIP() << "SIMD target " << target.name << " is compiled in but this CPU cannot run it";
  const ScopedSimdTarget on(target);
  std::vector<double> a;
  for (int k = 0; k <= 6000; ++k) a.push_back(k * 1e-3);                            // [0, 6]: the lobe's working range
  for (int k = 0; k <= 2000; ++k) a.push_back(6.0 * std::pow(30.0 / 6.0, k / 2000.0));  // to beyond the underflow
  for (double x : {1e-300, 5e-324, 1e3, 1e150, 1e300, 1.7e308}) a.push_back(x);
  std::vector<double> out(a.size(), -1.0);
  microfacet_kernel_erfc(a.data(), static_cast<std::ptrdiff_t>(a.size()), out.data());
  double worst_ulps = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    const double ref = std::erfc(a[k]);
    if (a[k] > kErfcSubnormalFrom) {
      EXPECT_LE(std::abs(out[k] - ref), kErfcSubnormalAbsTol) << target.name << ", a = " << a[k];
      continue;
    }
    const double ulps = std::abs(out[k] - ref) / (ref * DBL_EPSILON);
    worst_ulps = std::max(worst_ulps, ulps / (kErfcUlps + a[k] * a[k]));
    EXPECT_LE(ulps, kErfcUlps + a[k] * a[k]) << target.name << ", a = " << a[k] << ": " << out[k] << " against " << ref;
  }
  RecordProperty("worst_share_of_bound_" + target.name, std::to_string(worst_ulps));
  const double negative = -1e-3, nan = std::nan("");
  double sink = 0.0;
  EXPECT_THROW(microfacet_kernel_erfc(&negative, 1, &sink), ArgumentError);
  EXPECT_THROW(microfacet_kernel_erfc(&nan, 1, &sink), ArgumentError);
}

// The kernel loads whole vectors of incident rows de-interleaved: rows of 3 one after another, or one direction.
TEST(MicrofacetKernel, AnIncidentStrideOtherThanZeroOrThreeIsRefused) {
  const double wi[6] = {0, 0, 1, 0, 0, 1}, wr[6] = {0, 0, 1, 0, 0, 1};
  double out[2] = {-1, -1};
  EXPECT_THROW(microfacet_kernel_values(MicrofacetParams{}, 1.0, 0.0, wi, 6, wr, 1, out), ArgumentError);
  EXPECT_EQ(out[0], -1.0) << "nothing written";
  microfacet_kernel_values(MicrofacetParams{}, 1.0, 0.0, wi, 3, wr, 2, out);
  EXPECT_GT(out[0], 0.0);
  EXPECT_EQ(out[0], out[1]);
}

INSTANTIATE_TEST_SUITE_P(EveryCompiledTarget, MicrofacetOnTarget, ::testing::ValuesIn(compiled_simd_targets()),
                         [](const ::testing::TestParamInfo<SimdTarget>& info) { return info.param.name; });

}  // namespace
}  // namespace icobrdf
