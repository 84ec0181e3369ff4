// icobrdf bench baselines --quick --json: the figures it reports against expectations derived independently
// of the program (exactness of the polar-Gauss rule, h^2 decay of cell averaging, identity of the direct
// and matrix sums on one-point cells). No timing is asserted.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

// The polar-Gauss rule with r rings and 4r azimuths integrates every K_a K_b of order <= 2r - 1 exactly, so
// its Gram matrix is I up to the rounding of sums of ~700 products bounded by (N + 1)/pi: 1e-13.
constexpr double kExactRuleTol = 1e-13;
// Cell averaging attenuates K_n^l by 1 - O((n h)^2) with h ~ 2^-L, so at fixed order the equal-area Gram
// error falls ~4x per level once n h is small: accept [3, 5] at order 2 from level 2 to 3.
constexpr double kLevelRatioLo = 3.0, kLevelRatioHi = 5.0;
// Direct and matrix paths sum the same ~4e5 products w w' f K_a K_b in different orders (one point per cell):
// rounding ~ sqrt(terms) eps relative to the largest coefficient, 1e-13 with margin.
constexpr double kDirectMatrixTol = 1e-12;

const nlohmann::json& quick_run() {
  static const nlohmann::json j = [] {
    const auto r = run_cli({"bench", "baselines", "--quick", "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  }();
  return j;
}

TEST(CliBenchBaselines, ReportsEveryGridKindAtEveryQuickLevel) {
  const auto& j = quick_run();
  EXPECT_EQ(j["section"], "baselines");
  const auto& grids = j["data"]["grids"];
  // Quick levels 1..3, five kinds each.
  EXPECT_EQ(grids.size(), 15u);
  for (const auto& g : grids) {
    EXPECT_EQ(g["gram_error"].size(), static_cast<size_t>(j["data"]["max_order"].get<int>() + 1));
    if (g["kind"] == "equal-area" || g["kind"] == "geodesic") {
      // cells(L) = 10 4^L + 2^(L+1) (docs/tessellation.md)
      const int L = g["level"];
      EXPECT_EQ(g["cells"].get<int>(), 10 * (1 << (2 * L)) + (1 << (L + 1)));
    }
  }
}

TEST(CliBenchBaselines, PolarGaussGramIsIdentityWhereTheRuleIsExact) {
  for (const auto& g : quick_run()["data"]["grids"]) {
    if (g["kind"] != "polar-gauss") continue;
    const int r = g["rings"];
    ASSERT_EQ(g["azimuths"].get<int>(), 4 * r);
    const auto& e = g["gram_error"];
    for (int n = 0; n < static_cast<int>(e.size()) && n <= 2 * r - 1; ++n) EXPECT_LT(e[n].get<double>(), kExactRuleTol) << r << " rings, order " << n;
  }
}

TEST(CliBenchBaselines, EqualAreaGramErrorFallsWithLevel) {
  std::map<int, std::vector<double>> by_level;
  for (const auto& g : quick_run()["data"]["grids"])
    if (g["kind"] == "equal-area") by_level[g["level"].get<int>()] = g["gram_error"].get<std::vector<double>>();
  ASSERT_EQ(by_level.size(), 3u);
  for (int L = 2; L <= 3; ++L)
    for (size_t n = 1; n < by_level[L].size(); ++n) EXPECT_LT(by_level[L][n], by_level[L - 1][n]) << "level " << L << " order " << n;
  const double ratio = by_level[2][2] / by_level[3][2];
  EXPECT_GT(ratio, kLevelRatioLo);
  EXPECT_LT(ratio, kLevelRatioHi);
}

TEST(CliBenchBaselines, PolarGaussSearchStopsAtTheExactnessRingCount) {
  // With 2N + 1 azimuths and r = floor(N/2) + 1 rings the rule is exact for order N (degree 2r - 1 >= N in t),
  // so the upward search must stop at or before r, with a Gram error within the tolerance.
  int seen = 0;
  for (const auto& c : quick_run()["data"]["cells_needed"]) {
    if (c["kind"] != "polar-gauss") continue;
    ++seen;
    const int n = c["order"], rings = c["rings"];
    EXPECT_GE(rings, 1);
    EXPECT_LE(rings, n / 2 + 1) << "order " << n;
    EXPECT_EQ(c["cells"].get<int>(), rings * (2 * n + 1));
    EXPECT_LE(c["gram_error"].get<double>(), c["tolerance"].get<double>());
  }
  EXPECT_GT(seen, 0);
}

TEST(CliBenchBaselines, DirectQuadratureAgreesWithTheMatrixPath) {
  const auto& d = quick_run()["data"]["direct_vs_matrix"];
  ASSERT_FALSE(d.empty());
  for (const auto& c : d) {
    EXPECT_LT(c["agreement_plain"].get<double>(), kDirectMatrixTol);
    EXPECT_LT(c["agreement_cached_plain"].get<double>(), kDirectMatrixTol);
    // The least-squares comparison multiplies by G^-1 twice: the rounding grows by at most kappa(G)^2.
    EXPECT_LT(c["agreement_least_squares"].get<double>(), kDirectMatrixTol * std::pow(c["condition"].get<double>(), 2));
    EXPECT_GT(c["direct_per_pair_seconds"].get<double>(), 0.0);
    EXPECT_GT(c["matrix_seconds"].get<double>(), 0.0);
  }
}

TEST(CliBenchBaselines, ReportFolderGetsMarkdownJsonAndFigures) {
  TempDir dir;
  const auto r = run_cli({"bench", "baselines", "--levels", "1..2", "--orders", "0..8", "--quick", "--report", dir.path});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("# Baselines measured in the same run"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.file("baselines.md")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("baselines.json")));
  const auto j = nlohmann::json::parse(icobrdf::test::slurp(dir.file("baselines.json")));
  ASSERT_FALSE(j["figures"].empty());
  for (const auto& f : j["figures"]) EXPECT_GT(std::filesystem::file_size(dir.file(f.get<std::string>())), 0u) << f;
}

TEST(CliBenchBaselines, BadLevelsAreRefusedWithoutOutput) {
  const auto r = run_cli({"bench", "baselines", "--levels", "3..x", "--json"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("--levels"), std::string::npos);
}

}  // namespace ICOBRDF_UNITY_ID
