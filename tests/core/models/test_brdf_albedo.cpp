// White-furnace checks: directional albedo a(w_i) = integral of f(w_i, w_r) cos(theta_r) dOmega_r by an
// independent quadrature (tests/core/brdf_quadrature.hpp: composite Gauss-Legendre in theta graded
// towards the horizon x uniform phi, evaluated twice with doubled resolution; the difference is checked),
// against closed forms where they exist and against the bound a <= 1 for physical parameter sets.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>

#include "icobrdf/core/models/hapke.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "tests/core/brdf_quadrature.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;
using icobrdf::test::dir_deg;

namespace ICOBRDF_UNITY_ID {

// Smooth integrands: the refined quadrature agrees with itself to ~1e-12; closed forms are compared at
// this level (it also covers Hapke's tabulated H, accurate to ~1e-8, see test_brdf_hapke).
constexpr double kClosedFormTol = 2e-8;
// Lobes peaked near the horizon (grazing incidence on microfacets, Oren-Nayar's tan(beta)) converge
// more slowly; the refinement difference must be below this, and the bound a <= 1 is checked with it.
constexpr double kFurnaceTol = 2e-5;
// Incidence angles of the survey [deg]: normal, oblique, and grazing.
const double kThetas[] = {0.0, 20.0, 40.0, 60.0, 75.0, 85.0, 89.0, 89.9};

test::Converged albedo(const BrdfModel& m, double theta_deg, double phi_deg = 17.0) {
  return test::directional_albedo(m, dir_deg(theta_deg, phi_deg), 16);
}

TEST(WhiteFurnace, LambertAlbedoIsItsParameter) {
  for (double rho : {0.0, 0.37, 1.0}) {
    const auto m = parse_model("lambert:albedo=" + format_parameter(rho));
    for (double t : kThetas) EXPECT_NEAR(albedo(*m, t).value, rho, kClosedFormTol) << rho << " " << t;
  }
}

TEST(WhiteFurnace, MinnaertAlbedoIsCosineToTheKMinusOne) {
  // a = (k+1)/(2 pi) mu_i^(k-1) * 2 pi * integral_0^1 mu^(k-1) mu dmu = (k+1)/(2 pi) mu_i^(k-1) 2 pi/(k+1)
  //   = mu_i^(k-1): 1 at normal incidence, < 1 elsewhere for k > 1.
  for (double k : {1.0, 2.0, 3.0, 1.5, 7.3}) {
    const auto m = parse_model("minnaert:k=" + format_parameter(k));
    for (double t : kThetas) {
      const auto r = albedo(*m, t);
      ASSERT_LT(r.difference, kClosedFormTol) << k << " " << t;
      EXPECT_NEAR(r.value, std::pow(std::cos(t * M_PI / 180.0), k - 1.0), kClosedFormTol) << k << " " << t;
    }
  }
  // k < 1 (the printed range of eq. 35) is not energy conserving: a = mu_i^(k-1) > 1 off normal.
  const auto m = parse_model("minnaert:k=0.5");
  EXPECT_NEAR(albedo(*m, 60.0).value, std::sqrt(2.0), 1e-6);  // mu_r^0.5 kink at the horizon: slower
}

TEST(WhiteFurnace, PhongAndBlinnPhongAlbedoIsKsAtNormalIncidence) {
  // Phong: ks (n+2)/(2 pi) * integral cos^n(theta) cos(theta) dOmega = ks (n+2)/(2 pi) * 2 pi/(n+2) = ks.
  // Blinn-Phong: N(n) * integral cos^n(theta/2) cos(theta) dOmega = 1 by construction of N(n), whose
  // closed form 8 pi (n + 2^(-n/2))/((n+2)(n+4)) is what this checks.
  for (double n : {0.0, 0.5, 1.0, 5.0, 20.0, 200.0})
    for (const char* name : {"phong", "blinn-phong"}) {
      const auto m = parse_model(std::string(name) + ":n=" + format_parameter(n) + ",ks=0.8");
      const auto r = albedo(*m, 0.0);
      ASSERT_LT(r.difference, 1e-7) << name << " " << n;  // n = 0.5: sqrt kink at the horizon
      EXPECT_NEAR(r.value, 0.8, 1e-7) << name << " " << n;
      for (double t : kThetas) EXPECT_LE(albedo(*m, t).value, 0.8 + kFurnaceTol) << name << " " << n << " " << t;
    }
}

TEST(WhiteFurnace, LafortunePhongLikeLobeHasTheClosedFormAlbedo) {
  // cx = cy = -c, cz = c: base = c cos(angle to mirror); at normal incidence a = c^n 2 pi/(n+2).
  const double c = 0.9, n = 6.0;
  const auto m = parse_model("lafortune:cx=-0.9,cy=-0.9,cz=0.9,n=6,azimuth=25");
  EXPECT_NEAR(albedo(*m, 0.0).value, std::pow(c, n) * 2.0 * M_PI / (n + 2.0), kClosedFormTol);
}

TEST(WhiteFurnace, LommelSeeligerAndHapkeClosedForms) {
  // Lommel-Seeliger: a = w/(4 pi) 2 pi integral_0^1 mu/(mu_i + mu) dmu = (w/2)(1 - mu_i ln((1 + mu_i)/mu_i)).
  // Hapke with Chandrasekhar's H: a = 1 - sqrt(1 - w) H(mu_i) (Chandrasekhar 1950, the albedo of a
  // semi-infinite isotropically scattering atmosphere).
  for (double w : {0.3, 0.9, 1.0}) {
    const auto ls = parse_model("lommel-seeliger:w=" + format_parameter(w));
    const HapkeModel hapke(w);
    for (double t : kThetas) {
      const double mu = std::cos(t * M_PI / 180.0);
      const auto rl = albedo(*ls, t), rh = albedo(hapke, t);
      const double tol = t > 89.0 ? kFurnaceTol : kClosedFormTol;  // 1/(mu_i + mu_r) peaks at the horizon
      ASSERT_LT(rl.difference, tol) << w << " " << t;
      EXPECT_NEAR(rl.value, 0.5 * w * (1.0 - mu * std::log((1.0 + mu) / mu)), tol) << w << " " << t;
      EXPECT_NEAR(rh.value, 1.0 - std::sqrt(1.0 - w) * hapke.h_function().exact(mu), tol) << w << " " << t;
    }
  }
}

TEST(WhiteFurnace, MicrofacetAlbedoNeverExceedsOne) {
  // Smith masking: G2 <= G1(w_i) and integral of G1(w_i) D(h) (w_i.h) / cos(theta_i) dOmega_h = 1, so with
  // F = 1 the albedo is <= 1 (equal to 1 minus the energy lost to masking); a Fresnel factor <= 1 lowers it.
  for (const char* spec : {"ggx:alpha=0.1,fresnel=none", "ggx:alpha=0.5,fresnel=none", "ggx:alpha=2,fresnel=none",
                           "ggx:alpha=0.3,fresnel=none,masking=separable", "beckmann:alpha=0.1,fresnel=none",
                           "beckmann:alpha=0.8,fresnel=none", "ggx-aniso:alpha_x=0.1,alpha_y=0.6,fresnel=none",
                           "ggx:alpha=0.3,fresnel=dielectric,ior=2.4", "beckmann:alpha=0.3,f0=1"}) {
    const auto m = parse_model(spec);
    for (double t : kThetas) {
      const auto r = albedo(*m, t);
      ASSERT_LT(r.difference, kFurnaceTol) << spec << " " << t;
      EXPECT_LE(r.value, 1.0 + kFurnaceTol) << spec << " " << t;
    }
  }
}

TEST(WhiteFurnace, OrenNayarReducesToLambertAndStaysNearItsAlbedo) {
  const auto flat = parse_model("oren-nayar:sigma=0,albedo=0.6");
  for (double t : kThetas) EXPECT_NEAR(albedo(*flat, t).value, 0.6, kClosedFormTol);
  // The qualitative model is not exactly energy conserving: at grazing incidence and small sigma its
  // albedo exceeds the facet albedo by up to 1.5 % (docs/models.md); it never exceeds it by 2 %.
  double worst = 0.0;
  for (double sigma : {5.0, 10.0, 15.0, 20.0, 40.0, 90.0}) {
    const auto m = parse_model("oren-nayar:albedo=1,sigma=" + format_parameter(sigma));
    for (double t : kThetas) {
      const auto r = albedo(*m, t);
      ASSERT_LT(r.difference, 1e-3) << sigma << " " << t;  // tan(beta) ~ 1/mu near double grazing
      worst = std::max(worst, r.value);
    }
  }
  std::cout << "oren-nayar max albedo (albedo=1): " << worst << "\n";
  EXPECT_GT(worst, 1.0);
  EXPECT_LT(worst, 1.02);
}

TEST(WhiteFurnace, SurveyOfPhysicalModelsAtDefaultsAndPhysicalSets) {
  // Every model the registry calls physical, at its defaults, plus the physical subsets of the others.
  std::vector<std::string> specs;
  for (const auto& info : model_registry())
    if (info.physical && !info.delta) specs.push_back(info.name);
  for (const char* s : {"minnaert:k=1", "minnaert:k=4.5", "blinn-phong:n=10", "0.5*lambert+0.5*ggx:alpha=0.2",
                        "0.2*lafortune:cx=-1,cy=-1,cz=1,n=10", "hapke:w=1", "0.4*minnaert:k=2+0.5*phong"})
    specs.push_back(s);
  for (const auto& spec : specs) {
    const auto m = parse_model(spec);
    double worst = 0.0, at = 0.0;
    for (double t : kThetas) {
      const auto r = albedo(*m, t);
      ASSERT_LT(r.difference, kFurnaceTol) << spec << " " << t;
      if (r.value > worst) worst = r.value, at = t;
    }
    std::cout << std::setprecision(10) << "max albedo " << spec << ": " << worst << " at theta_i = " << at << "\n";
    EXPECT_LE(worst, 1.0 + kFurnaceTol) << spec;
  }
}

}  // namespace ICOBRDF_UNITY_ID
