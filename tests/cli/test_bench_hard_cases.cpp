// icobrdf bench hard-cases --quick --json: each reported error against its derived expectation.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <limits>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;

namespace ICOBRDF_UNITY_ID {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// Documented accuracy of the Zernike recurrence, |dR| <= 1e-13 for n <= 128 (icobrdf/core/basis/zernike.hpp); K_n^l carries
// the factor sqrt((n + 1)/pi).
constexpr double kZernikeAbsError = 1e-13;
// Orthonormality of K at order 128 by an exact rule (66 rings x 258 azimuths): with |dK_a| <= 1e-13
// sqrt((n_a + 1)/pi), ||K||_2 = 1 and area 2 pi, Cauchy-Schwarz gives |dG_ab| <= 2 sqrt(2) 1e-13 sqrt(129)
// = 3.21e-12, plus (66 + 258) eps = 7.2e-14 for the sums: 3.3e-12.
constexpr double kOrthonormality128Tol = 3.3e-12;
// float32 round to nearest: |fl(x) - x| <= 2^-24 |x|.
constexpr double kFloat32Roundoff = 0x1p-24;
// Two algebraic forms of the dielectric Fresnel reflectance (about ten operations each, one cancellation of
// terms of size 1 where F is smallest, F(1) = 0.04): rounding ~ 20 eps / 0.04 = 1e-13 relative.
constexpr double kFresnelFormTol = 1e-13;
// f(i, r) and f(r, i) of a reciprocal microfacet model evaluate the same symmetric expression with the roles
// swapped: rounding of a few tens of operations, relative to the largest value.
constexpr double kReciprocityTol = 1e-13;
// Relative rounding of G^-1 (a few hundred modes, condition < 2) on top of an attained bound.
constexpr double kBoundRoundingSlack = 1e-12;

const nlohmann::json& quick_run() {
  static const nlohmann::json j = [] {
    const auto r = run_cli({"bench", "hard-cases", "--quick", "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }();
  return j;
}

TEST(CliBenchHardCases, BasisIsOrthonormalToOrder128WithinTheDerivedBound) {
  const auto& o = quick_run()["data"]["orthonormality"];
  bool saw128 = false;
  for (const auto& r : o) {
    const int n = r["order"], rings = r["rings"], az = r["azimuths"];
    EXPECT_GE(2 * rings - 1, n);  // exact in t for the degree-n products
    EXPECT_GE(az, 2 * n + 1);     // exact in phi for trigonometric degree 2n
    const double bound = 2.0 * std::sqrt(2.0) * kZernikeAbsError * std::sqrt(n + 1.0) + (rings + az) * kEps;
    EXPECT_LE(r["gram_error"].get<double>(), bound) << "order " << n;
    if (!r["full_gram_error"].is_null()) {
      EXPECT_LE(r["full_gram_error"].get<double>(), bound) << "order " << n;
    }
    if (n == 128) {
      saw128 = true;
      EXPECT_LT(r["gram_error"].get<double>(), kOrthonormality128Tol);
      EXPECT_EQ(r["modes"].get<int>(), 129 * 130 / 2);
    }
  }
  EXPECT_TRUE(saw128);
}

TEST(CliBenchHardCases, ZernikeRecurrenceMatchesTheQuadPrecisionClosedSum) {
  const auto& z = quick_run()["data"]["zernike"];
  ASSERT_FALSE(z["rows"].empty());
  for (const auto& r : z["rows"]) {
    // The reference must be far more accurate than what it checks.
    EXPECT_LT(r["reference_error_bound"].get<double>(), 1e-3 * kZernikeAbsError) << r["n_from"];
    EXPECT_LE(r["recurrence_error"].get<double>(), kZernikeAbsError) << r["n_from"];
  }
}

TEST(CliBenchHardCases, DeltaSpectraWithinTheInverseGramBound) {
  const auto& d = quick_run()["data"]["delta"];
  ASSERT_EQ(d.size(), 2u);  // quick levels 2..3
  for (const auto& c : d) {
    const int m = (c["order"].get<int>() + 1) * (c["order"].get<int>() + 2) / 2;
    const double e_max = c["gram_error"], e2 = c["gram_error_2norm"];
    // max|E_ij| <= ||E||_2 <= M max|E_ij| for a symmetric M x M matrix.
    EXPECT_GE(e2, e_max * (1 - 1e-12));
    EXPECT_LE(e2, m * e_max);
    ASSERT_LT(e2, 1.0);
    EXPECT_NEAR(c["bound"].get<double>(), e2 / (1.0 - e2), 1e-14);
    // The bound is attained when G - I is dominated by one eigenvalue -e (C - I = e/(1 - e) there), so allow
    // the rounding of G^-1 on top of it.
    const double allowed = c["bound"].get<double>() * (1 + kBoundRoundingSlack);
    EXPECT_LE(c["mirror_error"].get<double>(), allowed) << "level " << c["level"];
    EXPECT_LE(c["retroreflector_error"].get<double>(), allowed) << "level " << c["level"];
  }
}

TEST(CliBenchHardCases, FresnelAndModelAtGrazingAndNormalIncidence) {
  const auto& f = quick_run()["data"]["fresnel"];
  // eta = 1.5: F(1) = (0.5 / 2.5)^2 = 0.04; F(0) = 1.
  EXPECT_DOUBLE_EQ(f["fresnel_normal_expected"].get<double>(), 0.04);
  for (const auto& p : f["fresnel"]) {
    if (p["theta_deg"] == 0.0) {
      EXPECT_NEAR(p["dielectric"].get<double>(), 0.04, 2 * kEps);
    }
    if (p["theta_deg"] == 90.0) {
      EXPECT_NEAR(p["dielectric"].get<double>(), 1.0, 2 * kEps);
    }
  }
  EXPECT_LT(f["fresnel_max_relative_difference"].get<double>(), kFresnelFormTol);
  EXPECT_TRUE(f["model_values_finite_nonnegative"].get<bool>());
  EXPECT_LT(f["reciprocity_max_relative"].get<double>(), kReciprocityTol);
  EXPECT_EQ(f["reconstruction"]["regions"].size(), 3u);
  for (const auto& r : f["reconstruction"]["regions"]) EXPECT_TRUE(std::isfinite(r["relative_rms_error"].get<double>()));
}

TEST(CliBenchHardCases, DynamicRangeRegionsAreConsistent) {
  const auto& d = quick_run()["data"]["dynamic_range"];
  // The Lambertian level is 1e-4 of the lobe's peak by construction: w / pi = 1e-4 peak.
  EXPECT_NEAR(d["background"].get<double>() / d["peak"].get<double>(), 1e-4, 1e-16);
  EXPECT_NEAR(d["lambert_weight"].get<double>(), M_PI * d["background"].get<double>(), 1e-15);
  EXPECT_GT(d["lobe_pairs"].get<int>(), 0);
  EXPECT_GT(d["background_pairs"].get<int>(), 0);
  double previous = std::numeric_limits<double>::infinity();
  for (const auto& o : d["orders"]) {
    // In the background region the true f lies in [b, 1.1 b] (GGX term <= 0.1 b), so the relative RMS error is
    // the RMS absolute error over a level between b and 1.1 b.
    const double rel = o["background_relative_rms_error"], abs = o["background_rms_abs_error"], b = d["background"];
    EXPECT_LE(rel, abs / b * (1 + 1e-12));
    EXPECT_GE(rel, abs / (1.1 * b) * (1 - 1e-12));
    // A smooth lobe's truncation error falls with the order.
    EXPECT_LT(o["lobe_relative_rms_error"].get<double>(), previous);
    previous = o["lobe_relative_rms_error"];
  }
}

TEST(CliBenchHardCases, Float32LutErrorWithinTheConditioningBound) {
  const auto& f = quick_run()["data"]["float32"];
  ASSERT_FALSE(f.empty());
  for (const auto& c : f) {
    EXPECT_LE(c["lut_relative_rounding"].get<double>(), kFloat32Roundoff);
    EXPECT_GT(c["spectrum_relative_error"].get<double>(), 0.0);  // GGX values are not all float32 numbers
    EXPECT_LE(c["spectrum_relative_error"].get<double>(), c["spectrum_a_posteriori_bound"].get<double>());
    EXPECT_LE(c["spectrum_a_posteriori_bound"].get<double>(), c["spectrum_bound"].get<double>());
    EXPECT_LE(c["reconstruction_relative_error"].get<double>(), c["reconstruction_bound"].get<double>());
    EXPECT_GE(c["condition"].get<double>(), 1.0);
  }
}

TEST(CliBenchHardCases, BadLevelsAreRefusedWithoutOutput) {
  const auto r = run_cli({"bench", "hard-cases", "--levels", "9", "--json"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
}

}  // namespace ICOBRDF_UNITY_ID
