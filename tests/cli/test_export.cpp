// icobrdf export, and measured-data SOURCEs through the CLI: MERL tables, CSV samples and SCATMECH
// coefficient files fitted with `icobrdf fit`, then exported as SCATMECH coefficients whose values are
// checked against their analytic expectation.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

#include "cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::run_cli;
using icobrdf::test::slurp;
using icobrdf::test::TempDir;

// A least-squares fit of data exactly in the span (constants): rounding over ~1e6 samples.
constexpr double kFitTol = 1e-10;

// A MERL file of the Lambertian f = albedo/pi: stored value f / scale_c (R 1/1500, G 1.15/1500, B 1.66/1500).
// With missing_every = k > 0, every k-th sample of each channel is stored as -1 (missing).
void write_lambert_merl(const std::string& path, double albedo, std::int64_t drop_bytes = 0, std::int64_t missing_every = 0) {
  std::ofstream o(path, std::ios::binary);
  const std::int32_t dims[3] = {90, 90, 180};
  o.write(reinterpret_cast<const char*>(dims), 12);
  const double scale[3] = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};
  const std::int64_t n = 90 * 90 * 180;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v(static_cast<size_t>(n), albedo / M_PI / scale[c]);
    if (missing_every > 0)
      for (std::int64_t k = 0; k < n; k += missing_every) v[static_cast<size_t>(k)] = -1.0;
    o.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(8 * n - (c == 2 ? drop_bytes : 0)));
  }
}

// Coefficient rows (i, j, n, m, k, l, p) -> a of a SCATMECH file written by icobrdf.
std::map<std::vector<int>, double> read_rows(const std::string& path) {
  std::map<std::vector<int>, double> rows;
  std::istringstream in(slurp(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == ';') continue;
    std::vector<int> key(7);
    double a = 0;
    EXPECT_EQ(std::sscanf(line.c_str(), "%d,%d,%d,%d,%d,%d,%d,%lf", &key[0], &key[1], &key[2], &key[3], &key[4], &key[5],
                          &key[6], &a), 8) << line;
    rows[key] = a;
  }
  return rows;
}

// f = albedo/pi is I_00^0 = 1/(2 pi) (SCATMECH's and ours) times a = 2 albedo; every other row is 0.
void expect_lambert_rows(const std::string& path, double albedo) {
  const auto rows = read_rows(path);
  ASSERT_FALSE(rows.empty());
  for (const auto& [k, a] : rows) {
    EXPECT_EQ(k[0], 1);
    EXPECT_EQ(k[1], 1);
    const bool dc = k[2] == 0 && k[3] == 0;
    EXPECT_NEAR(a, dc ? 2 * albedo : 0.0, kFitTol) << k[2] << " " << k[3] << " " << k[5];
  }
}

TEST(CliMeasured, MerlFitAndExport) {
  TempDir d;
  write_lambert_merl(d.file("lambert.binary"), 0.5);
  auto r = run_cli({"fit", d.file("lambert.binary"), "--order", "4", "--level", "3", "-o", d.file("x.h5"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["channels"], 3);
  EXPECT_EQ(j["order"], 4);
  EXPECT_EQ(j["isotropic"], true);
  for (int c = 0; c < 3; ++c) {
    const std::string out = d.file("c" + std::to_string(c) + ".csv");
    r = run_cli({"export", d.file("x.h5"), "--format", "scatmech", "--channel", std::to_string(c), "-o", out});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_lambert_rows(out, 0.5);
  }
  // A 3-channel spectrum needs --channel.
  r = run_cli({"export", d.file("x.h5"), "--format", "scatmech", "-o", d.file("no.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("choose one with --channel"), std::string::npos) << r.err;
  EXPECT_TRUE(slurp(d.file("no.csv")).empty());
}

// Isotropic modes up to order N (SPEC-NOTES, eqs. 22-23): n >= m >= l >= 0, n <= N, n - l and m - l even.
int isotropic_mode_count(int order) {
  int count = 0;
  for (int n = 0; n <= order; ++n)
    for (int m = 0; m <= n; ++m)
      for (int l = 0; l <= m; ++l) count += (n - l) % 2 == 0 && (m - l) % 2 == 0;
  return count;
}

TEST(CliMeasured, MerlFitReportsMissingSamplesRankAndResidual) {
  TempDir d;
  // Every 1000th of the 90*90*180 = 1458000 samples per channel missing: ceil(1458000 / 1000) = 1458 each.
  write_lambert_merl(d.file("holes.binary"), 0.5, 0, 1000);
  auto r = run_cli({"fit", d.file("holes.binary"), "--order", "4", "--level", "3", "-o", d.file("x.h5"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["missing_samples"], 3 * 1458);
  const auto& sf = j["sample_fit"];
  EXPECT_EQ(sf["unknowns"], isotropic_mode_count(4));
  // About a million well-spread nodes determine every isotropic mode of order 4: full rank.
  EXPECT_EQ(sf["effective_rank"], isotropic_mode_count(4));
  EXPECT_EQ(sf["null_space_dimension"], 0);
  // A constant is in the span: the residual is rounding.
  for (const auto& rms : sf["residual_rms"]) EXPECT_LT(rms.get<double>(), kFitTol);
  // Fewer nodes than the full table: the missing ones and those below the horizon are excluded.
  EXPECT_LT(sf["samples"].get<long long>(), 1458000 - 1458 + 1);
  EXPECT_GT(sf["samples"].get<long long>(), 0);
  // The text output names them too.
  r = run_cli({"fit", d.file("holes.binary"), "--order", "4", "--level", "3", "-o", d.file("y.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("MERL missing samples (masked, all channels): 4374"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rank 14 of 14 unknowns"), std::string::npos) << r.out;
}

TEST(CliMeasured, PlaneOfIncidenceSamplesAreRankDeficientAndSaySo) {
  TempDir d;
  // Samples only in the plane of incidence (phi_r - phi_i in {0, 180}) do not see the sin(l phi) modes of the
  // general Helmholtz basis: the fit must not pass them off as determined. It falls back (to the isotropic
  // modes, regularized when those are undetermined too) and says why, or refuses.
  std::ofstream o(d.file("p.csv"));
  o << "theta_i,phi_i,theta_r,phi_r,value\n";
  std::mt19937 g(3);
  std::uniform_real_distribution<double> th(0, 89);
  for (int k = 0; k < 400; ++k) o << th(g) << ",0," << th(g) << "," << (k % 2 ? 180 : 0) << "," << 0.3 / M_PI << "\n";
  o.close();
  const auto r = run_cli({"fit", d.file("p.csv"), "--order", "2", "--level", "2", "-o", d.file("p.h5"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto sf = nlohmann::json::parse(r.out)["sample_fit"];
  EXPECT_NE(sf["fallback"].get<std::string>().find("the samples do not determine the 21 general modes of order 2"),
            std::string::npos) << sf;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["isotropic"], true);
  const auto t = run_cli({"fit", d.file("p.csv"), "--order", "2", "--level", "2", "-o", d.file("q.h5")});
  EXPECT_NE(t.out.find("fallback: the samples do not determine"), std::string::npos) << t.out;
}

TEST(CliMeasured, BadMerlFailsWithoutOutput) {
  TempDir d;
  write_lambert_merl(d.file("cut.binary"), 0.5, 1);
  const auto r = run_cli({"fit", d.file("cut.binary"), "--order", "2", "--level", "2", "-o", d.file("x.h5")});
  EXPECT_EQ(r.exit_code, 3);  // InputError
  EXPECT_NE(r.err.find("truncated MERL file: 34992011 bytes, expected 34992012 (1 bytes missing"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  std::ifstream f(d.file("x.h5"));
  EXPECT_FALSE(f.good());
}

TEST(CliMeasured, SampleCsvFitAndExport) {
  TempDir d;
  std::ofstream o(d.file("s.csv"));
  o << "theta_i,phi_i,theta_r,phi_r,value\n";
  std::mt19937 g(1);
  std::uniform_real_distribution<double> th(0, 90), ph(-180, 180);
  char line[200];
  for (int k = 0; k < 300; ++k) {
    std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.6f,%.17g\n", th(g), ph(g), th(g), ph(g), 0.3 / M_PI);
    o << line;
  }
  o.close();
  auto r = run_cli({"fit", d.file("s.csv"), "--order", "2", "--level", "2", "--isotropic", "-o", d.file("s.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"export", d.file("s.h5"), "--format", "scatmech", "-o", d.file("s2.csv")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_lambert_rows(d.file("s2.csv"), 0.3);
}

TEST(CliMeasured, ScatmechSourceRoundTrip) {
  TempDir d;
  {
    std::ofstream o(d.file("t.zernike.csv"));
    o << "; two terms\n1,1,0,0,0,0,0,2\n1,1,2,0,0,0,1,0.25\n";
  }
  auto r = run_cli({"fit", d.file("t.zernike.csv") + "#lambda=0.5", "--order", "2", "--level", "2", "-o", d.file("t.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"export", d.file("t.h5"), "--format", "scatmech", "-o", d.file("t2.csv"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["rows"], 5);  // isotropic modes up to order 2
  const auto rows = read_rows(d.file("t2.csv"));
  EXPECT_NEAR((rows.at({1, 1, 0, 0, 0, 0, 0})), 2.0, 1e-15);
  EXPECT_NEAR((rows.at({1, 1, 2, 0, 0, 0, 0})), 0.25 * 0.5, 1e-15);  // a lambda^p with lambda = 0.5, p = 1
  // Without the wavelength the p = 1 term cannot be evaluated.
  r = run_cli({"fit", d.file("t.zernike.csv"), "--order", "2", "--level", "2", "-o", d.file("u.h5")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("need the wavelength"), std::string::npos) << r.err;
}

// Three channels, one per wavelength, exported as a polynomial in lambda and read back at another wavelength.
// Channel c holds the constant f_c [1/sr] (fitted at order 0: exact to rounding); the quadratic through
// (0.45, 0.3), (0.55, 0.5), (0.65, 0.6) at 0.5 um is, by Lagrange's weights 0.375, 0.75, -0.125 (by hand),
// 0.4125, and at 0.55 um it is 0.5.
TEST(CliMeasured, WavelengthPolynomialExportRoundTripsThroughScatmech) {
  // The Vandermonde system of 0.45 .. 0.65 um has condition ~1e3: the coefficients carry ~1e3 eps.
  constexpr double kPolynomialTol = 1e-12;
  TempDir d;
  {
    std::ofstream o(d.file("s.csv"));
    o << "theta_i,phi_i,theta_r,phi_r,a,b,c\n";
    for (int k = 0; k < 40; ++k)
      o << 2 * k << "," << 9 * k << "," << 80 - 2 * k << "," << 200 - 7 * k << ",0.3e0,0.5e0,0.6e0\n";
  }
  auto r = run_cli({"fit", d.file("s.csv"), "--order", "0", "--level", "2", "--isotropic", "-o", d.file("s.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"export", d.file("s.h5"), "--format", "scatmech", "--wavelength-degree", "2", "--wavelengths", "0.45,0.55,0.65",
               "-o", d.file("w.csv"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rows"], 3);  // one mode, powers 0, 1, 2
  EXPECT_LT(j["misfit"].get<double>(), kPolynomialTol);
  std::ofstream(d.file("pairs.csv")) << "theta_i,phi_i,theta_r,phi_r\n30,0,50,120\n";
  for (const auto& [lambda, expected] : std::vector<std::pair<std::string, double>>{{"0.5", 0.4125}, {"0.55", 0.5}}) {
    const auto v = icobrdf::test::eval_first_column(d.file("w.csv") + "#lambda=" + lambda, d.file("pairs.csv"));
    ASSERT_EQ(v.size(), 1u) << lambda;
    EXPECT_NEAR(v[0], expected, kPolynomialTol) << "lambda " << lambda;
  }
  // Refused, nothing written: more unknowns than wavelengths; --channel with it; channels not named as wavelengths.
  r = run_cli({"export", d.file("s.h5"), "--format", "scatmech", "--wavelength-degree", "3", "--wavelengths", "0.45,0.55,0.65", "-o", d.file("x.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("degree 3 needs at least 4 wavelengths"), std::string::npos) << r.err;
  r = run_cli({"export", d.file("s.h5"), "--format", "scatmech", "--wavelength-degree", "1", "-o", d.file("x.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a wavelength like '550nm'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(d.file("x.csv")).good());
}

TEST(CliMeasured, ExportRefusesUnknownFormat) {
  TempDir d;
  const auto r = run_cli({"export", d.file("none.h5"), "--format", "pdf", "-o", d.file("x.csv")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--format: expected 'scatmech', 'rgl' or 'merl', found 'pdf'"), std::string::npos) << r.err;
}

// Exports renderers load: the JSON figures of an RGL and a MERL export of a glossy model (the agreement of
// each file read back), and the one-line refusals that leave no file.
TEST(CliExport, RglAndMerlExportsReportTheirAgreementReadBack) {
  TempDir d;
  // The RGL export's acceptance figure (cosine metric); a MERL table stores doubles: rounding at its nodes.
  constexpr double kRglAgreement = 0.03, kMerlNodeTol = 1e-15;
  auto r = run_cli({"export", "model:ggx:alpha=0.3,f0=0.04", "--format", "rgl", "-o", d.file("g.bsdf"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_LE(j["cosine_rel_l2"].get<double>(), kRglAgreement);
  EXPECT_EQ(j["theta_i_nodes"], 24);
  r = run_cli({"export", "model:ggx:alpha=0.3,f0=0.04", "--format", "merl", "-o", d.file("g.binary"), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_LE(j["node_max_rel"].get<double>(), kMerlNodeTol);
  EXPECT_EQ(j["bytes"], 34992012);
  // Both files are SOURCEs again.
  std::ofstream(d.file("p.csv")) << "theta_i,phi_i,theta_r,phi_r\n30,0,30,180\n";
  for (const char* f : {"g.bsdf", "g.binary"}) EXPECT_EQ(run_cli({"eval", d.file(f), "--at", d.file("p.csv")}).exit_code, 0) << f;
  for (const auto& [source, says] : std::vector<std::pair<std::string, std::string>>{
           {"model:ggx-aniso:alpha_x=0.1,alpha_y=0.3", "is anisotropic"}, {"model:mirror", "has a delta part"}}) {
    r = run_cli({"export", source, "--format", "rgl", "-o", d.file("no.bsdf")});
    EXPECT_EQ(r.exit_code, 2) << source;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  r = run_cli({"export", "model:lambert", "--format", "merl", "--channel", "0", "-o", d.file("no.bsdf")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(slurp(d.file("no.bsdf")).empty());
}

}  // namespace
