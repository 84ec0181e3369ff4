// The same scene built on 1 and on 2 threads (OMP_NUM_THREADS, which sets both the OpenMP loops and Eigen's
// products) gives identical bank files: bytes compared with the run-dependent `seconds` figures masked
// (tests/cli/bank_identity.hpp).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
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

// Two threads, the small materials fitted one at a time (--materials-at-once 1) or two at once (one thread
// each): identical banks (the identity scene's materials are all small: levels 2 and 3).
TEST(BankThreads, OneOrTwoMaterialsAtOnceGiveIdenticalBanks) {
  setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
  TempDir d;
  const std::string scene = d.file("scene.toml"), one = d.file("one.h5"), two = d.file("two.h5");
  std::ofstream(scene) << icobrdf::test::identity_scene(false);
  setenv("OMP_NUM_THREADS", "2", 1);
  const auto a = run_cli({"bank", "build", scene, "-o", one, "--quiet", "--materials-at-once", "1"});
  const auto b = run_cli({"bank", "build", scene, "-o", two, "--quiet", "--materials-at-once", "2"});
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(banks_identical(one, two));
  // A negative count is refused before any work, in one line.
  const auto bad = run_cli({"bank", "build", scene, "-o", d.file("bad.h5"), "--materials-at-once", "-1"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--materials-at-once"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

}  // namespace ICOBRDF_UNITY_ID
