// icobrdf sample: CSV of importance-sampled directions (cli/cmd_sample.cpp). The sampler's statistics are
// tested in tests/io/test_material_sampler.cpp; here: the output's form, the Lambertian mean weight (the
// albedo), reproducibility by seed, and one-line refusals with their exit codes.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;

namespace ICOBRDF_UNITY_ID {
// The mean of n weights is within 5 standard errors of its expectation (false failure 6e-7, normal mean).
constexpr double kStandardErrors = 5.0;

TEST(CliSample, LambertCsvHasAnglesPdfAndWeightsWithMeanAlbedo) {
  const auto r = run_cli({"sample", "model:lambert:albedo=0.5", "--theta-i", "60", "--phi-i", "10", "-n", "20000", "--level", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto rows = icobrdf::test::parse_value_csv(r.out, header);
  EXPECT_EQ(header, "theta_r,phi_r,pdf,weight");
  ASSERT_EQ(rows.size(), 20000u);
  double sum = 0, sq = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 4u);
    EXPECT_GE(row[0], 0.0);
    EXPECT_LE(row[0], 90.0);
    EXPECT_GT(row[2], 0.0);
    // weight = f cos / pdf with f = 0.5 / pi
    EXPECT_NEAR(row[3], 0.5 / M_PI * std::cos(row[0] * M_PI / 180) / row[2], 1e-12);
    sum += row[3];
    sq += row[3] * row[3];
  }
  const double n = static_cast<double>(rows.size()), mean = sum / n, sd = std::sqrt((sq / n - mean * mean) * n / (n - 1));
  EXPECT_NEAR(mean, 0.5, kStandardErrors * sd / std::sqrt(n));
}

TEST(CliSample, SeedMakesRunsReproducible) {
  const std::vector<std::string> a{"sample", "model:ggx:alpha=0.2", "--theta-i", "30", "-n", "50", "--level", "3"};
  auto b = a;
  b.insert(b.end(), {"--seed", "2"});
  const auto r1 = run_cli(a), r2 = run_cli(a), r3 = run_cli(b);
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  EXPECT_EQ(r1.out, r2.out);
  EXPECT_NE(r1.out, r3.out);
}

TEST(CliSample, RefusalsAreOneLineWithExitCodes) {
  auto r = run_cli({"sample", "model:mirror", "--theta-i", "30", "-n", "5", "--level", "2"});
  EXPECT_EQ(r.exit_code, 4);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("is 0 at every one of the 168 cell centres of level 2 (its delta part cannot be sampled)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  r = run_cli({"sample", "model:lambert", "--theta-i", "95", "-n", "5"});
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli({"sample", "model:lambert", "--theta-i", "30", "-n", "0"});
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli({"sample", "model:lambert", "--theta-i", "30", "-n", "5", "--cell-value", "corner"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--cell-value: expected 'centre' or 'average'"), std::string::npos) << r.err;
}

}  // namespace ICOBRDF_UNITY_ID
