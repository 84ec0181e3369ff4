// The same scene built on 1 and on 2 threads (OMP_NUM_THREADS, which sets both the OpenMP loops and Eigen's
// products) gives identical bank files: bytes compared with the run-dependent `seconds` figures masked
// (tests/cli/bank_identity.hpp).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>

#include "tests/cli/bank_identity.hpp"
#include "tests/cli/cli_runner.hpp"

using icobrdf::test::banks_identical;
using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace {

// Several materials on levels 2 and 3 (fits search the level; bank operators at level 3 with P where
// supported); isotropic and anisotropic, pruned and not, float32 and float64 LUTs in two scenes.
const char* kScene = R"(
[bank]
level = 3
levels = [2, 3]
order_max = 8
store_lut = true
lut_float32 = %s
holdout_pairs = 1024

[[material]]
name = "matte"
source = "model:lambert:albedo=0.2"

[[material]]
name = "moon"
source = "model:minnaert:k=2"

[[material]]
name = "clay"
source = "model:oren-nayar:sigma=30,albedo=0.7"
isotropic = false
order = 6
target = 1.0
prune = false

[[material]]
name = "glossy"
source = "model:ggx:alpha=0.6"
target = 0.5
)";

void expect_thread_count_independent(bool float32) {
  setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // fixes the bank's `created` attribute
  TempDir d;
  const std::string scene = d.file("scene.toml"), one = d.file("one.h5"), two = d.file("two.h5");
  char text[2048];
  std::snprintf(text, sizeof text, kScene, float32 ? "true" : "false");
  std::ofstream(scene) << text;
  setenv("OMP_NUM_THREADS", "1", 1);
  const auto a = run_cli({"bank", "build", scene, "-o", one, "--quiet"});
  setenv("OMP_NUM_THREADS", "2", 1);
  const auto b = run_cli({"bank", "build", scene, "-o", two, "--quiet"});
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(banks_identical(one, two));
}

}  // namespace

TEST(BankThreads, OneAndTwoThreadsGiveIdenticalBanksFloat32Luts) { expect_thread_count_independent(true); }

TEST(BankThreads, OneAndTwoThreadsGiveIdenticalBanksFloat64Luts) { expect_thread_count_independent(false); }
