// Microfacet building blocks: normalization of D, the Smith visible-area identity that defines Lambda,
// Fresnel against Snell's law, and the full model against the textbook angle formulas.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/models/fresnel.hpp"
#include "icobrdf/core/models/microfacet.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;
using icobrdf::test::dir_deg;

namespace ICOBRDF_UNITY_ID {
// Quadrature: the refined integral's own convergence check must pass at this level first.
constexpr double kQuadratureTol = 1e-9;
// Closed-form comparisons evaluated by different but equivalent algebra: rounding only.
constexpr double kFormulaTol = 1e-12;
// The visible-area integrand has a kink along w.h = 0, which the tensor rule does not follow: the
// trapezoidal phi rule then converges only as 1/n^2 (measured differences ~1e-8 at 512 -> 1024 azimuths).
constexpr double kKinkQuadratureTol = 1e-6;

TEST(Microfacet, DistributionsAreNormalizedOverProjectedArea) {
  struct Case {
    MicrofacetDistribution d;
    double ax, ay;
  };
  for (const Case c : {Case{MicrofacetDistribution::Ggx, 0.05, 0.05}, Case{MicrofacetDistribution::Ggx, 0.3, 0.3},
                       Case{MicrofacetDistribution::Ggx, 1.0, 1.0}, Case{MicrofacetDistribution::Ggx, 2.5, 2.5},
                       Case{MicrofacetDistribution::Ggx, 0.05, 0.5}, Case{MicrofacetDistribution::Beckmann, 0.05, 0.05},
                       Case{MicrofacetDistribution::Beckmann, 0.3, 0.3}, Case{MicrofacetDistribution::Beckmann, 1.0, 1.0},
                       Case{MicrofacetDistribution::Beckmann, 0.1, 0.4}}) {
    // integral of D(h) cos(theta_h) dOmega_h = 1 (projected microfacet area = macro area).
    const auto r = test::refined_integral(
        [&](const Eigen::Vector3d& h) { return microfacet_d(c.d, h, c.ax, c.ay) * h.z(); }, 48, std::nan(""));
    ASSERT_LT(r.difference, kQuadratureTol) << c.ax << " " << c.ay;
    EXPECT_NEAR(r.value, 1.0, kQuadratureTol) << static_cast<int>(c.d) << " " << c.ax << " " << c.ay;
  }
}

TEST(Microfacet, SmithLambdaSatisfiesTheVisibleAreaIdentity) {
  // For Smith's G1(w) = z/(z + L(w)): integral of G1(w) max(0, w.h) D(h) dOmega_h = cos(theta_w)
  // (the visible projected area of the microsurface equals that of the macrosurface).
  struct Case {
    MicrofacetDistribution d;
    double ax, ay;
  };
  for (const Case c : {Case{MicrofacetDistribution::Ggx, 0.2, 0.2}, Case{MicrofacetDistribution::Ggx, 1.2, 1.2},
                       Case{MicrofacetDistribution::Ggx, 0.1, 0.6}, Case{MicrofacetDistribution::Beckmann, 0.2, 0.2},
                       Case{MicrofacetDistribution::Beckmann, 0.9, 0.9}})
    for (double theta : {0.0, 30.0, 60.0, 85.0, 89.9})
      for (double phi : {0.0, 50.0}) {
        const Eigen::Vector3d w = dir_deg(theta, phi);
        const double g1 = w.z() / (w.z() + smith_z_lambda(c.d, w, c.ax, c.ay));
        const auto r = test::refined_integral(
            [&](const Eigen::Vector3d& h) { return g1 * std::max(0.0, w.dot(h)) * microfacet_d(c.d, h, c.ax, c.ay); },
            96, std::nan(""));
        ASSERT_LT(r.difference, kKinkQuadratureTol) << theta;
        EXPECT_NEAR(r.value, w.z(), kKinkQuadratureTol) << static_cast<int>(c.d) << " " << c.ax << " theta " << theta;
      }
}

TEST(Fresnel, DielectricMatchesSnellsLawAndLimits) {
  for (double eta : {1.0, 1.33, 1.5, 2.4, 4.0})
    for (double theta = 0.0; theta < 90.0; theta += 2.5) {
      const double ci = std::cos(theta * M_PI / 180.0), si = std::sin(theta * M_PI / 180.0);
      const double st = si / eta, ct = std::sqrt(1.0 - st * st);
      const double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
      EXPECT_NEAR(fresnel_dielectric(ci, eta), 0.5 * (rs * rs + rp * rp), kFormulaTol) << eta << " " << theta;
    }
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, kFormulaTol);  // ((1.5-1)/(1.5+1))^2
  EXPECT_NEAR(fresnel_dielectric(0.0, 1.5), 1.0, kFormulaTol);
  EXPECT_EQ(fresnel_dielectric(0.0, 1.0), 0.0);
  // Brewster angle tan(theta_B) = eta: only the s part remains.
  const double tb = std::atan(1.5), ct = std::cos(M_PI / 2 - tb);
  const double rs = (std::cos(tb) - 1.5 * ct) / (std::cos(tb) + 1.5 * ct);
  EXPECT_NEAR(fresnel_dielectric(std::cos(tb), 1.5), 0.5 * rs * rs, kFormulaTol);
  // Total internal reflection from the denser side.
  EXPECT_EQ(fresnel_dielectric(0.2, 1.0 / 1.5), 1.0);
  EXPECT_EQ(fresnel_schlick(1.0, 0.04), 0.04);
  EXPECT_EQ(fresnel_schlick(0.0, 0.04), 1.0);
  EXPECT_NEAR(fresnel_schlick(0.5, 0.04), 0.04 + 0.96 / 32.0, kFormulaTol);
}

TEST(Microfacet, ModelMatchesTextbookAngleFormulas) {
  // f = D F G2 / (4 cos ti cos tr) written with tangents (Walter et al. 2007; Heitz 2014).
  const auto lambda_ggx = [](double a, double t) { return 0.5 * (-1.0 + std::sqrt(1.0 + a * a * std::tan(t) * std::tan(t))); };
  const auto lambda_beck = [](double a, double t) {
    const double m = 1.0 / (a * std::tan(t));
    return 0.5 * (std::erf(m) - 1.0) + std::exp(-m * m) / (2.0 * m * std::sqrt(M_PI));
  };
  for (int dist = 0; dist < 2; ++dist)
    for (int separable = 0; separable < 2; ++separable)
      for (double alpha : {0.1, 0.45, 1.3}) {
        const std::string name = dist == 0 ? "ggx" : "beckmann";
        const auto m = parse_model(name + ":alpha=" + format_parameter(alpha) + ",f0=0.1" +
                                   (separable ? ",masking=separable" : ""));
        for (const auto& [ti, pi, tr, pr] : std::vector<std::array<double, 4>>{
                 {30, 0, 40, 180}, {10, 20, 75, 230}, {60, 90, 60, 90}, {5, 0, 80, 0}, {70, 0, 65, 170}}) {
          const Eigen::Vector3d wi = dir_deg(ti, pi), wr = dir_deg(tr, pr);
          const Eigen::Vector3d h = (wi + wr).normalized();
          const double th = std::acos(h.z()), c4 = std::pow(h.z(), 4), t2 = std::tan(th) * std::tan(th);
          const double d = dist == 0 ? alpha * alpha / (M_PI * c4 * std::pow(alpha * alpha + t2, 2))
                                     : std::exp(-t2 / (alpha * alpha)) / (M_PI * alpha * alpha * c4);
          const double li = dist == 0 ? lambda_ggx(alpha, ti * M_PI / 180) : lambda_beck(alpha, ti * M_PI / 180);
          const double lr = dist == 0 ? lambda_ggx(alpha, tr * M_PI / 180) : lambda_beck(alpha, tr * M_PI / 180);
          const double g2 = separable ? 1.0 / ((1 + li) * (1 + lr)) : 1.0 / (1 + li + lr);
          const double f = 0.1 + 0.9 * std::pow(1.0 - wi.dot(h), 5);
          const double expected = d * f * g2 / (4.0 * wi.z() * wr.z());
          EXPECT_NEAR(m->eval(wi, wr) / expected, 1.0, 1e-11) << m->spec() << " " << ti << " " << tr;
        }
      }
}

TEST(Microfacet, GrazingLimitsAreFinite) {
  // L(w) at z = 0: q/2 for GGX and q/(2 sqrt(pi)) for Beckmann (the limits of z Lambda).
  const Eigen::Vector3d g(0.6, 0.8, 0.0);
  EXPECT_NEAR(smith_z_lambda(MicrofacetDistribution::Ggx, g, 0.3, 0.3), 0.15, kFormulaTol);
  EXPECT_NEAR(smith_z_lambda(MicrofacetDistribution::Beckmann, g, 0.3, 0.3), 0.15 / std::sqrt(M_PI), kFormulaTol);
  EXPECT_EQ(smith_z_lambda(MicrofacetDistribution::Ggx, Eigen::Vector3d(0, 0, 1), 0.3, 0.3), 0.0);
  // Separable masking stays bounded at double grazing: f = D F / (4 L_i L_r) with h horizontal.
  const auto m = parse_model("ggx:alpha=0.5,fresnel=none,masking=separable");
  const Eigen::Vector3d a(1, 0, 0), b(0, 1, 0);
  const double d = 0.25 / M_PI;  // GGX D at h_z = 0: alpha^2/pi
  EXPECT_NEAR(m->eval(a, b), d / (4 * 0.25 * 0.25), kFormulaTol);
}

}  // namespace ICOBRDF_UNITY_ID
