// The same scene built on 1 and on 2 threads (OMP_NUM_THREADS, which sets both the OpenMP loops and Eigen's
// products) gives identical bank files: bytes compared with the run-dependent `seconds` figures masked
// (tests/cli/bank_identity.hpp).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>

#include "tests/cli/bank_identity.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::banks_identical;
using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

void expect_thread_count_independent(bool float32) {
  setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // fixes the bank's `created` attribute
  TempDir d;
  const std::string scene = d.file("scene.toml"), one = d.file("one.h5"), two = d.file("two.h5");
  std::ofstream(scene) << icobrdf::test::identity_scene(float32);
  setenv("OMP_NUM_THREADS", "1", 1);
  const auto a = run_cli({"bank", "build", scene, "-o", one, "--quiet"});
  setenv("OMP_NUM_THREADS", "2", 1);
  const auto b = run_cli({"bank", "build", scene, "-o", two, "--quiet"});
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(banks_identical(one, two));
}

TEST(BankThreads, OneAndTwoThreadsGiveIdenticalBanksFloat32Luts) { expect_thread_count_independent(true); }

TEST(BankThreads, OneAndTwoThreadsGiveIdenticalBanksFloat64Luts) { expect_thread_count_independent(false); }

}  // namespace ICOBRDF_UNITY_ID
