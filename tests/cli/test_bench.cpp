// icobrdf bench project: the JSON contract and the agreement of the two product paths (no timing asserted).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli/cli_runner.hpp"

using icobrdf::test::run_cli;

// Both paths sum the same products of ~170 terms in different orders: agreement to 1e-12 relative.
constexpr double kSameProductTol = 1e-12;

TEST(CliBench, ProjectReportsTheContractKeysAndBothPathsAgree) {
  const auto r = run_cli({"bench", "project", "--level", "2", "--order", "2", "--repeat", "1", "--threads", "1", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* k : {"seconds", "gflops", "peak_gflops", "peak_ratio", "blas_seconds", "blas_ratio"}) ASSERT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["cells"].get<int>(), 168);
  EXPECT_EQ(j["modes"].get<int>(), 6);
  // flops = 2 c^2 m + 2 c m^2 for C = P^T (F P).
  const double flops = 2.0 * 168 * 168 * 6 + 2.0 * 168 * 6 * 6;
  EXPECT_NEAR(j["gflops"].get<double>(), flops / j["seconds"].get<double>() / 1e9, 1e-9 * j["gflops"].get<double>());
  EXPECT_NEAR(j["blas_ratio"].get<double>(), j["blas_seconds"].get<double>() / j["seconds"].get<double>(), 1e-12);
  EXPECT_NEAR(j["peak_ratio"].get<double>(), j["gflops"].get<double>() / j["peak_gflops"].get<double>(), 1e-12);
  EXPECT_LT(j["relative_difference_to_blas"].get<double>(), kSameProductTol);
}

TEST(CliBench, UnsupportedOrderIsRefused) {
  const auto r = run_cli({"bench", "project", "--level", "1", "--order", "8", "--json"});
  EXPECT_EQ(r.exit_code, 4) << r.err;
}
