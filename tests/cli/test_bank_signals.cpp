// SIGINT / SIGTERM during `icobrdf bank build`: finished materials are kept in BANK.h5.partial, the bank is
// not written, the exit code is 130 / 143, and --resume completes the bank with the same result as an
// uninterrupted build.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace ICOBRDF_UNITY_ID {

// Four materials, each a few hundred milliseconds of cell-averaged sampling at level 4, so a signal sent when
// the second starts arrives while the build is running.
const char* kScene = R"(
[bank]
level = 2
levels = [4]
order_max = 8
sampling = "average"

[[material]]
name = "a"
source = "model:lambert:albedo=0.2"
order = 8

[[material]]
name = "b"
source = "model:lambert:albedo=0.4"
order = 8

[[material]]
name = "c"
source = "model:minnaert:k=2"
order = 8

[[material]]
name = "d"
source = "model:minnaert:k=3"
order = 8
)";

// Runs `icobrdf bank build`, sends `sig` when the progress line of the second material appears on stderr,
// and returns the exit code.
int build_and_signal(const std::string& scene, const std::string& bank, int sig) {
  int err_pipe[2];
  if (pipe(err_pipe) != 0) return -1;
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(err_pipe[1], 2);
    close(err_pipe[0]);
    close(err_pipe[1]);
    if (!freopen("/dev/null", "w", stdout)) _exit(126);
    execl(ICOBRDF_CLI_PATH, ICOBRDF_CLI_PATH, "bank", "build", scene.c_str(), "-o", bank.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(err_pipe[1]);
  FILE* err = fdopen(err_pipe[0], "r");
  char line[4096];
  bool sent = false;
  while (fgets(line, sizeof line, err)) {
    if (!sent && std::string(line).rfind("[2/4]", 0) == 0) {
      kill(pid, sig);
      sent = true;
    }
  }
  fclose(err);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

json spectrum_of(const std::string& bank, const std::string& name) {
  const auto r = run_cli({"spectrum", bank + "#" + name, "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(r.out);
}

void expect_interrupted_then_resumed(int sig, int expected_code) {
  TempDir d;
  const std::string scene = d.file("scene.toml"), bank = d.file("bank.h5"), ref = d.file("ref.h5");
  std::ofstream(scene) << kScene;
  EXPECT_EQ(build_and_signal(scene, bank, sig), expected_code);
  EXPECT_FALSE(std::ifstream(bank).good()) << "no bank after an interrupted build";
  ASSERT_TRUE(std::ifstream(bank + ".partial").good()) << "finished materials are kept";
  const auto r = run_cli({"bank", "build", scene, "-o", bank, "--resume", "--json", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json report = json::parse(r.out);
  int resumed = 0;
  for (const auto& m : report["materials"]) resumed += m["resumed"].get<bool>() ? 1 : 0;
  EXPECT_GE(resumed, 1) << r.out;
  EXPECT_LT(resumed, 4);
  // The resumed bank holds the same spectra as an uninterrupted build.
  ASSERT_EQ(run_cli({"bank", "build", scene, "-o", ref, "--quiet"}).exit_code, 0);
  for (const char* name : {"a", "b", "c", "d"}) EXPECT_EQ(spectrum_of(bank, name)["coefficients"], spectrum_of(ref, name)["coefficients"]) << name;
}

TEST(BankSignals, SigtermKeepsFinishedMaterialsAndResumeCompletesTheSameBank) { expect_interrupted_then_resumed(SIGTERM, 143); }

TEST(BankSignals, SigintExitsWith130) { expect_interrupted_then_resumed(SIGINT, 130); }

}  // namespace ICOBRDF_UNITY_ID
