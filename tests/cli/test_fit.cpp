// icobrdf fit / spectrum / lut / smooth / albedo end to end. Expected values derived in comments.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace ICOBRDF_UNITY_ID {

// The Lambert spectrum is exact on any grid (only rounding of sums over cells).
constexpr double kExactTol = 1e-10;
// Albedos use cell-mean cosines from the cells' cubature; cos(theta) is not a polynomial in the planar cell
// coordinates, so the degree-9 rule integrates it to ~5e-9 relative at level 2.
constexpr double kCellCosineTol = 1e-7;
// GGX with alpha_x = 0.3, alpha_y = 0.8 has an anisotropic part far above 1e-4 of the energy; grid-induced
// anisotropy of isotropic models at level 3 stays below that.
constexpr double kClearlyAnisotropic = 1e-4;
// Level 4, order 6: Gram error 0.022 (max |G - I|), ||G - I||_2 below 0.05; the mirror's C = D G^-1 deviates
// from the analytic value by at most ||G - I||_2 / (1 - ||G - I||_2) per entry, and IBSSS entries combine two
// entries with weight 1/sqrt(2) each: 0.08 covers it.
constexpr double kMirrorLevel4Tol = 0.08;

json spectrum_json(const std::string& file) {
  const auto r = run_cli({"spectrum", file, "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out);
}

TEST(CliFit, LambertIsotropicSpectrumIsTwiceTheAlbedoAtDc) {
  // f = a/pi: C = 2a e_0 e_0^T (SPEC-NOTES, derived in tests/core/projection/test_operators.cpp), IBSSS a_00^0 = C_00.
  TempDir dir;
  const auto out = dir.file("lambert.h5");
  const auto r = run_cli({"fit", "model:lambert:albedo=0.5", "--order", "4", "--level", "3", "--isotropic", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto fig = json::parse(r.out);
  EXPECT_EQ(fig["cells"].get<int>(), 10 * 64 + 16);
  EXPECT_NEAR(fig["max_albedo"].get<double>(), 0.5, kExactTol);
  const auto j = spectrum_json(out);
  EXPECT_TRUE(j["isotropic"].get<bool>());
  EXPECT_EQ(j["indices"].size(), 14u);  // 14 isotropic modes up to order 4
  for (size_t k = 0; k < j["indices"].size(); ++k) {
    const double expected = k == 0 ? 1.0 : 0.0;
    EXPECT_NEAR(j["coefficients"][0][k].get<double>(), expected, kExactTol) << j["indices"][k].dump();
  }
}

TEST(CliFit, MirrorHasTheFlatDiagonalSpectrum) {
  // Ideal mirror (g form): isotropic a_nn^0 = 1, a_nn^l = sqrt(2) (-1)^l, all n != m vanish (SPEC-NOTES).
  TempDir dir;
  const auto out = dir.file("mirror.h5");
  ASSERT_EQ(run_cli({"fit", "model:mirror", "--order", "6", "--level", "4", "--isotropic", "-o", out}).exit_code, 0);
  const auto j = spectrum_json(out);
  EXPECT_TRUE(j["cosine"].get<bool>()) << "delta models are projected in g form";
  for (size_t k = 0; k < j["indices"].size(); ++k) {
    const auto idx = j["indices"][k].get<std::vector<int>>();
    const int n = idx[0], m = idx[1], l = idx[2];
    const double expected = n != m ? 0.0 : (l == 0 ? 1.0 : std::sqrt(2.0) * (l % 2 ? -1.0 : 1.0));
    EXPECT_NEAR(j["coefficients"][0][k].get<double>(), expected, kMirrorLevel4Tol) << j["indices"][k].dump();
  }
}

TEST(CliFit, OrderBeyondTheGridIsRefusedWithTheLimit) {
  TempDir dir;
  const auto r = run_cli({"fit", "model:lambert", "--order", "12", "--level", "2", "-o", dir.file("x.h5")});
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("largest supported order is"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(dir.file("x.h5")).good()) << "no output on failure";
}

TEST(CliFit, BadSourcesAreArgumentErrors) {
  TempDir dir;
  for (const char* src : {"model:nosuchmodel", "model:ggx:alpha=-1", "model:ggx:beta=2", "whatever.xyz"}) {
    const auto r = run_cli({"fit", src, "--order", "2", "--level", "1", "-o", dir.file("x.h5")});
    EXPECT_EQ(r.exit_code, 2) << src << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one-line error: " << r.err;
  }
  const auto missing = run_cli({"fit", dir.file("missing.h5"), "--order", "2", "--level", "1", "-o", dir.file("x.h5")});
  EXPECT_EQ(missing.exit_code, 3) << missing.err;
}

TEST(CliFit, AnisotropicModelReportsAnisotropyAndSpectrumListsHelmholtzIndices) {
  TempDir dir;
  const auto out = dir.file("aniso.h5");
  const auto r = run_cli({"fit", "model:ggx-aniso:alpha_x=0.3,alpha_y=0.8", "--order", "4", "--level", "3", "--sampling", "centre", "-o", out, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(json::parse(r.out)["anisotropy_fraction"].get<double>(), kClearlyAnisotropic);
  const auto j = spectrum_json(out);
  EXPECT_FALSE(j["isotropic"].get<bool>());
  EXPECT_EQ(j["indices"].size(), 120u);  // M(M+1)/2 with M = 15 at order 4
  EXPECT_EQ(j["indices"][0].size(), 4u);
}

TEST(CliLut, LambertLutAlbedoSmoothAndFloat32) {
  // f = 0.7/pi: every directional albedo is 0.7 (exact with cell-mean cosines); the constant is in the span
  // of order 0, so smoothing to order 0 returns the same LUT.
  TempDir dir;
  const auto lut = dir.file("lut.h5"), sm = dir.file("smooth.h5");
  ASSERT_EQ(run_cli({"lut", "model:lambert:albedo=0.7", "--level", "2", "--order", "2", "-o", lut}).exit_code, 0);
  auto r = run_cli({"albedo", lut, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = json::parse(r.out);
  EXPECT_NEAR(j["channels"][0]["max_albedo"].get<double>(), 0.7, kCellCosineTol);
  EXPECT_NEAR(j["channels"][0]["min_albedo"].get<double>(), 0.7, kCellCosineTol);
  ASSERT_EQ(run_cli({"smooth", lut, "--order", "0", "-o", sm}).exit_code, 0);
  r = run_cli({"albedo", sm, "--json"});
  j = json::parse(r.out);
  EXPECT_NEAR(j["channels"][0]["max_albedo"].get<double>(), 0.7, kCellCosineTol);
  // A mirror LUT passes the white furnace with albedo 1 in every cell.
  ASSERT_EQ(run_cli({"lut", "model:mirror", "--level", "2", "--order", "2", "-o", dir.file("m.h5"), "--float32"}).exit_code, 0);
  j = json::parse(run_cli({"albedo", dir.file("m.h5"), "--json"}).out);
  EXPECT_NEAR(j["channels"][0]["max_albedo"].get<double>(), 1.0, kCellCosineTol + 1e-6) << "float32 storage: relative rounding 2^-24 per entry";
}

TEST(CliEval, SpectrumFileEvaluatesToTheModelForABrdfInTheSpan) {
  // Minnaert k = 2 is in the span of order 2 (cos = 1 - rho^2); with B and the LUT sampled by the same rule
  // its spectrum is recovered exactly, so evaluating the file at any pair gives (3/(2 pi)) cos_i cos_r.
  TempDir dir;
  const auto pairs = dir.file("pairs.csv");
  std::ofstream(pairs) << "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n30,0,45,90\n89,10,70,-120\n";
  ASSERT_EQ(run_cli({"fit", "model:minnaert:k=2", "--order", "3", "--level", "2", "-o", dir.file("m.h5")}).exit_code, 0);
  const auto r = run_cli({"eval", dir.file("m.h5"), "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "f");
  const double deg = M_PI / 180;
  for (auto [ti, tr] : {std::pair{0.0, 0.0}, std::pair{30.0, 45.0}, std::pair{89.0, 70.0}}) {
    std::getline(in, line);
    EXPECT_NEAR(std::stod(line), 3 / (2 * M_PI) * std::cos(ti * deg) * std::cos(tr * deg), kExactTol) << ti << " " << tr;
  }
}

}  // namespace ICOBRDF_UNITY_ID
