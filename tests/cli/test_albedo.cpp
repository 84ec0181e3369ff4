// `icobrdf albedo SOURCE --black-sky ... --white-sky [--curve] [--json]` end to end: the MODIS kernels against the
// ATBD's white-sky integrals and an independent quadrature of their black-sky integrals
// (scripts/derive/albedo_values.py), delta parts, per-channel albedos of a spectrum file fitted from RGB samples,
// the LUT form kept, and refusals. The rule's own accuracy: tests/core/models/test_albedo_quadrature.cpp.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {
// The ATBD prints the kernels' white-sky integrals to 6 decimals and its Li-Sparse-R value is 3.6e-5 off the
// integral of the published formula: 1e-4 (the acceptance criterion).
constexpr double kWhiteSkyTol = 1e-4;
// Black-sky integrals against SciPy's adaptive quadrature (error estimates <= 1.1e-10): the library's rule was
// measured to 3.9e-6 on the Li-Sparse-R kernel's kink (x 0.03 here), so 1e-5 for weighted sums of the kernels (criterion: 1e-3).
constexpr double kBlackSkyTol = 1e-5;
// Closed forms (constants, delta weights) through the quadrature and JSON's shortest round-trip decimals.
constexpr double kExactTol = 1e-12;
// A constant fitted at order 0 by least squares from samples: the fit's rounding.
constexpr double kFitTol = 1e-9;

// scripts/derive/albedo_values.py: h_vol(s), h_geo(s) at s = 0, 30, 60 degrees.
constexpr double kHvol[] = {-0.0210791764864, 0.0319520137234, 0.270481647339};
constexpr double kHgeo[] = {-1.288854382, -1.32563252642, -1.42530922482};

TEST(CliAlbedo, RossLiAlbedosAreTheKernelIntegralsWithTheAtbdCubicBeside) {
  const double iso = 0.1, vol = 0.2, geo = 0.03;
  const auto r = run_cli({"albedo", "model:ross-li:iso=0.1,vol=0.2,geo=0.03", "--black-sky", "0,30,60", "--white-sky", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["white_sky"][0].get<double>(), iso + vol * 0.189184 + geo * -1.377622, kWhiteSkyTol);
  EXPECT_NEAR(j["atbd_white_sky"].get<double>(), iso + vol * 0.189184 + geo * -1.377622, kExactTol);
  ASSERT_EQ(j["black_sky"].size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const auto& e = j["black_sky"][k];
    const double s = e["sza_deg"].get<double>() * M_PI / 180;
    EXPECT_EQ(e["sza_deg"].get<double>(), 30.0 * k);
    EXPECT_NEAR(e["albedo"][0].get<double>(), iso + vol * kHvol[k] + geo * kHgeo[k], kBlackSkyTol) << k;
    // MCD43's formula: g0 + g1 s^2 + g2 s^3 per kernel (Lucht, Schaaf & Strahler 2000, Table 1).
    const double atbd = iso + vol * (-0.007574 - 0.070987 * s * s + 0.307588 * s * s * s) + geo * (-1.284909 - 0.166314 * s * s + 0.041840 * s * s * s);
    EXPECT_NEAR(e["atbd_polynomial"].get<double>(), atbd, kExactTol) << k;
  }
  EXPECT_FALSE(j.contains("curve"));
  EXPECT_EQ(j["quadrature"]["sun_azimuths"].get<int>(), 1);  // isotropic: the sun at one azimuth
}

TEST(CliAlbedo, TheDefaultIsWhiteSkyAndTheCurveAndTextNamesBoth) {
  auto r = run_cli({"albedo", "model:mirror+0.2*lambert", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["white_sky"][0].get<double>(), 1.2, kExactTol);  // the mirror's weight 1 and Lambert's 0.2
  ASSERT_EQ(j["curve"].size(), 90u);
  for (const auto& e : j["curve"]) EXPECT_NEAR(e["albedo"][0].get<double>(), 1.2, kExactTol);
  EXPECT_EQ(j["curve"][89]["sza_deg"].get<double>(), 89.0);
  r = run_cli({"albedo", "model:lambert:albedo=0.25", "--black-sky", "10"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("black-sky albedo"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.2500000"), std::string::npos) << r.out;
}

TEST(CliAlbedo, ASpectrumFileOfRgbSamplesHasOneAlbedoPerChannel) {
  TempDir d;
  // Lambert samples of albedo 0.2, 0.4, 0.6 per channel at scattered pairs; fitted at order 0 (the constant
  // mode holds them exactly), the spectrum's albedos are those three at every zenith.
  std::ostringstream csv;
  csv << "theta_i,phi_i,theta_r,phi_r,value,g,b\n";
  csv.precision(17);
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) csv << 5 + 14 * a << "," << 37 * b << "," << 8 + 13 * b << "," << 61 * a + 11 << "," << 0.2 / M_PI << "," << 0.4 / M_PI << "," << 0.6 / M_PI << "\n";
  std::ofstream(d.file("rgb.csv")) << csv.str();
  auto r = run_cli({"fit", d.file("rgb.csv"), "--order", "0", "--level", "1", "--isotropic", "-o", d.file("rgb.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"albedo", d.file("rgb.h5"), "--white-sky", "--black-sky", "0,45,80", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["channels"].get<int>(), 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(j["white_sky"][c].get<double>(), 0.2 * (c + 1), kFitTol) << c;
    for (const auto& e : j["black_sky"]) EXPECT_NEAR(e["albedo"][c].get<double>(), 0.2 * (c + 1), kFitTol) << c;
  }
  // The samples themselves have no value between them: refused, saying to fit them first.
  r = run_cli({"albedo", d.file("rgb.csv"), "--white-sky"});
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.err.find("fit them first"), std::string::npos) << r.err;
}

TEST(CliAlbedo, TheLutFormStaysAndBadZenithsAreRefused) {
  TempDir d;
  const std::string lut = d.file("l.h5");
  ASSERT_EQ(run_cli({"lut", "model:lambert:albedo=0.7", "--level", "2", "--order", "2", "-o", lut}).exit_code, 0);
  auto r = run_cli({"albedo", lut, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out).contains("cells"));
  r = run_cli({"albedo", lut});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("passes the white furnace"), std::string::npos) << r.out;
  r = run_cli({"albedo", "model:lambert", "--black-sky", "30,95"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("solar zenith must be in [0, 90] degrees, found 95"), std::string::npos) << r.err;
}

}  // namespace ICOBRDF_UNITY_ID
