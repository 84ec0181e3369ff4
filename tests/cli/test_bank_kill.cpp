// SIGKILL at random moments of `icobrdf bank build`: after every kill the bank path holds no bank, the
// previous complete bank, or the new complete bank (never a partial one), and `--resume` then completes a bank
// identical to an uninterrupted build (bytes compared with the run-dependent `seconds` figures masked,
// tests/cli/bank_identity.hpp).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>

#include "tests/cli/bank_identity.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::banks_identical;
using icobrdf::test::run_cli;
using icobrdf::test::slurp;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace ICOBRDF_UNITY_ID {

// At least 50 kills, so that the delays drawn below land in every phase of a build and of its write.
constexpr int kKills = 50;
// Kill delays are drawn uniformly from [0, kDelaySpan x the measured duration of one build), so most kills
// land while materials are fitted or files written and some after the build has finished.
constexpr double kDelaySpan = 1.2;

// Four small materials on level 2 (a build takes a fraction of a second on one thread): the resume file is
// rewritten after each material, the bank once at the end; float32 LUTs carry their rounding-error attribute.
const char* kScene = R"(
[bank]
level = 2
levels = [2]
order_max = 6
store_lut = true
holdout_pairs = 512

[[material]]
name = "matte"
source = "model:lambert:albedo=0.2"
order = 4

[[material]]
name = "moon"
source = "model:minnaert:k=2"

[[material]]
name = "clay"
source = "model:oren-nayar:sigma=30,albedo=0.7"
isotropic = false
order = 4
target = 1.0
prune = false

[[material]]
name = "glossy"
source = "model:ggx:alpha=0.6"
order = 4
target = 1.0
prune = false
)";

// The bank that stands at the path before a rebuild, in odd rounds.
const char* kOldScene = R"(
[bank]
level = 2
levels = [2]

[[material]]
name = "old"
source = "model:lambert:albedo=0.9"
order = 2
)";

// Starts `icobrdf bank build`, SIGKILLs it after `delay` (unless it finished first); true when it was killed.
bool build_and_kill(const std::string& scene, const std::string& bank, std::chrono::microseconds delay) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(126);
    execl(ICOBRDF_CLI_PATH, ICOBRDF_CLI_PATH, "bank", "build", scene.c_str(), "-o", bank.c_str(), "--quiet",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(delay);
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFEXITED(status)) {
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the build failed on its own";
  }
  return WIFSIGNALED(status);
}

bool exists(const std::string& path) { return access(path.c_str(), F_OK) == 0; }

TEST(BankKill, SigkillNeverLeavesAPartialBankAndResumeGivesTheUninterruptedBank) {
  // One thread: the build is fast and its duration steady on a busy machine; the file's content does not
  // depend on it (test_bank_threads.cpp).
  setenv("OMP_NUM_THREADS", "1", 1);
  setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // fixes the bank's `created` attribute
  TempDir d;
  const std::string scene = d.file("scene.toml"), old_scene = d.file("old.toml"), bank = d.file("bank.h5");
  const std::string ref = d.file("ref.h5"), old = d.file("old.h5");
  std::ofstream(scene) << kScene;
  std::ofstream(old_scene) << kOldScene;
  ASSERT_EQ(run_cli({"bank", "build", old_scene, "-o", old, "--quiet"}).exit_code, 0);
  const std::string old_bytes = slurp(old);
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run_cli({"bank", "build", scene, "-o", ref, "--quiet"});
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(r.exit_code, 0) << r.err;

  std::mt19937 rng(8);
  std::uniform_real_distribution<double> delay_s(0.0, kDelaySpan * build_s);
  int absent = 0, old_kept = 0, finished = 0, resumed_materials = 0;
  for (int k = 0; k < kKills; ++k) {
    const bool had_old = k % 2 == 1;
    std::remove((bank + ".partial").c_str());
    std::remove(bank.c_str());
    if (had_old) std::ofstream(bank, std::ios::binary) << old_bytes;
    build_and_kill(scene, bank, std::chrono::microseconds(static_cast<long long>(1e6 * delay_s(rng))));
    if (!exists(bank)) {
      EXPECT_FALSE(had_old) << "kill " << k << " removed the previous bank";
      ++absent;
    } else if (had_old && slurp(bank) == old_bytes) {
      ++old_kept;
    } else {
      EXPECT_TRUE(banks_identical(bank, ref)) << "kill " << k << ": the path holds neither the old nor the new complete bank";
      ++finished;
    }
    if (exists(bank + ".partial")) {  // the resume file is written atomically too
      EXPECT_EQ(run_cli({"bank", "info", bank + ".partial"}).exit_code, 0) << "kill " << k << ": partial resume file";
    }
    const auto res = run_cli({"bank", "build", scene, "-o", bank, "--resume", "--quiet", "--json"});
    ASSERT_EQ(res.exit_code, 0) << "kill " << k << ": " << res.err;
    const json report = json::parse(res.out);
    for (const auto& m : report["materials"]) resumed_materials += m["resumed"].get<bool>() ? 1 : 0;
    EXPECT_TRUE(banks_identical(bank, ref)) << "kill " << k << ": resumed bank";
    EXPECT_FALSE(exists(bank + ".partial")) << "kill " << k << ": resume file left after a complete build";
  }
  std::printf("    build %.3f s; %d kills: %d left no bank, %d the previous bank, %d the new bank; %d materials resumed\n",
              build_s, kKills, absent, old_kept, finished, resumed_materials);
  EXPECT_GT(absent + old_kept, 0) << "no kill landed before the bank was written";
  EXPECT_GT(resumed_materials, 0) << "no kill landed between two materials";
}

}  // namespace ICOBRDF_UNITY_ID
