// icobrdf bench project: the JSON contract and the agreement of the two product paths (no timing asserted).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <string>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;

namespace ICOBRDF_UNITY_ID {

// The first "flags" line of /proc/cpuinfo (the CPU's instruction-set extensions), or "" where there is none.
std::string cpu_flags() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("flags", 0) == 0) return line.substr(line.find(':') + 1);
  return "";
}

// OpenBLAS cores by the width of their DGEMM kernels (OpenBLAS's kernel/x86_64/KERNEL.<CORE> files): the
// AVX-512 ones, and generic or pre-AVX2 fallbacks that a CPU with AVX2 + FMA outruns.
bool is_avx512_core(const std::string& c) { return c == "SkylakeX" || c == "Cooperlake" || c == "SapphireRapids"; }
bool is_pre_avx2_core(const std::string& c) {
  for (const char* n : {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem", "Sandybridge", "Atom", "Barcelona", "Bulldozer", "Piledriver"})
    if (c == n) return true;
  return false;
}

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
  EXPECT_EQ(j["performed_gflops"].get<double>(), j["gflops"].get<double>()) << "a general F performs the general product's flops";
  EXPECT_LT(j["relative_difference_to_blas"].get<double>(), kSameProductTol);
  // The peak the ratio uses is the measured one; the nominal one is reported beside it.
  EXPECT_EQ(j["peak_source"].get<std::string>(), "measured");
  EXPECT_GT(j["measured_peak_gflops"].get<double>(), 0.0);
  EXPECT_EQ(j["peak_gflops"].get<double>(), j["measured_peak_gflops"].get<double>());
  EXPECT_TRUE(j.contains("nominal_peak_gflops"));
  // The memory floor: the 168 x 168 LUT read once at the measured bandwidth.
  const double bw = j["bandwidth_gbs"].get<double>();
  ASSERT_GT(bw, 0.0);
  EXPECT_NEAR(j["stream_seconds"].get<double>(), 8.0 * 168 * 168 / (bw * 1e9), 1e-12 * j["stream_seconds"].get<double>());
  // The share of F in huge pages, a fraction (0 for this 226 KB LUT under THP "madvise": too small to advise).
  ASSERT_TRUE(j.contains("lut_huge_page_fraction"));
  EXPECT_GE(j["lut_huge_page_fraction"].get<double>(), 0.0);
  EXPECT_LE(j["lut_huge_page_fraction"].get<double>(), 1.0);
  EXPECT_FALSE(j["blas_core"].get<std::string>().empty());
  // OpenBLAS on its own kernel, in a child without OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE. When this process
  // has neither variable, the child's OpenBLAS loads exactly as this one did: it must run and agree.
  // When OpenBLAS's own kernel is narrower than the CPU's widest vectors (a CPU newer than the OpenBLAS build),
  // a second child names the widest kernel, and the faster run is the baseline, the other kept beside it.
  const auto& best = j["blas_best"];
  ASSERT_TRUE(best.is_object());
  const std::string own_env = "without OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE";
  const bool two = best.contains("other");
  const nlohmann::json& own = two && best["environment"] != own_env ? best["other"] : best;
  if (std::getenv("OPENBLAS_CORETYPE") == nullptr && std::getenv("OPENBLAS_L2_SIZE") == nullptr) {
    ASSERT_FALSE(own.contains("error")) << best.dump();
    EXPECT_EQ(own["environment"].get<std::string>(), own_env);
    EXPECT_EQ(own["core"].get<std::string>(), j["blas_core"].get<std::string>());
    // The CPU's widest kernel, from /proc/cpuinfo's flags (not from the program's own CPU test).
    const std::string flags = " " + cpu_flags() + " ";
    const auto has = [&](const char* f) { return flags.find(std::string(" ") + f + " ") != std::string::npos; };
    const bool avx512 = has("avx512f") && has("avx512bw") && has("avx512dq") && has("avx512vl");
    const bool avx2 = has("avx2") && has("fma");
    const std::string core = own["core"].get<std::string>();
    if (is_avx512_core(core)) EXPECT_FALSE(two) << best.dump();
    if (is_pre_avx2_core(core) && (avx512 || avx2)) EXPECT_TRUE(two) << best.dump();
    if (two) {
      const nlohmann::json& forced = &own == &best ? best["other"] : best;
      EXPECT_EQ(forced["environment"].get<std::string>(), std::string("with OPENBLAS_CORETYPE=") + (avx512 ? "SkylakeX" : "Haswell"));
      if (!forced.contains("error")) {
        EXPECT_LE(best["seconds"].get<double>(), best["other"]["seconds"].get<double>());
        EXPECT_LT(forced["relative_difference"].get<double>(), kSameProductTol);
      }
    }
  }
  if (!best.contains("error")) {
    EXPECT_LT(best["relative_difference"].get<double>(), kSameProductTol);
    EXPECT_NEAR(best["ratio"].get<double>(), best["seconds"].get<double>() / j["seconds"].get<double>(), 1e-12);
    EXPECT_FALSE(best["core"].get<std::string>().empty());
  }
}

TEST(CliBench, ProjectOfASymmetricLutAgreesWithTheGeneralProduct) {
  const auto r = run_cli({"bench", "project", "--level", "2", "--order", "2", "--repeat", "1", "--threads", "2", "--symmetric", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["symmetric"].get<bool>());
  // 168 cells are one column block: P^T F over all 168 cells, then two 6 x 168 x 6 products.
  const double performed = 2.0 * 6 * 168 * 168 + 2.0 * 2.0 * 6 * 168 * 6;
  EXPECT_NEAR(j["performed_gflops"].get<double>(), performed / j["seconds"].get<double>() / 1e9, 1e-9 * j["performed_gflops"].get<double>());
  EXPECT_LT(j["relative_difference_to_blas"].get<double>(), kSameProductTol);
  if (!j["blas_best"].contains("error")) { EXPECT_LT(j["blas_best"]["relative_difference"].get<double>(), kSameProductTol); }
}

TEST(CliBench, ProjectTakesTheGivenPeakAndCanSkipTheChildRun) {
  const auto r = run_cli({"bench", "project", "--level", "1", "--order", "1", "--repeat", "1", "--threads", "1", "--peak-gflops", "123.5",
                          "--no-best-blas", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["peak_source"].get<std::string>(), "--peak-gflops");
  EXPECT_EQ(j["peak_gflops"].get<double>(), 123.5);
  EXPECT_NEAR(j["peak_ratio"].get<double>(), j["gflops"].get<double>() / 123.5, 1e-12);
  EXPECT_TRUE(j["blas_best"].is_null());
}

TEST(CliBench, ProjectRunsOnANamedTargetAndRefusesAnUnknownOne) {
  auto r = run_cli({"bench", "project", "--level", "1", "--order", "1", "--repeat", "1", "--no-best-blas", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string best = nlohmann::json::parse(r.out)["simd_target"].get<std::string>();
  const std::string name = best.substr(0, best.find(' '));  // "AVX3 (8 FP64 lanes)"
  r = run_cli({"bench", "project", "--level", "1", "--order", "1", "--repeat", "1", "--no-best-blas", "--simd-target", name, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["simd_target"].get<std::string>(), best);
  r = run_cli({"bench", "project", "--level", "1", "--order", "1", "--simd-target", "NOSUCH"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--simd-target 'NOSUCH': not compiled into this build, expected one of"), std::string::npos) << r.err;
}

TEST(CliBench, UnsupportedOrderIsRefused) {
  const auto r = run_cli({"bench", "project", "--level", "1", "--order", "8", "--json"});
  EXPECT_EQ(r.exit_code, 4) << r.err;
}

}  // namespace ICOBRDF_UNITY_ID
