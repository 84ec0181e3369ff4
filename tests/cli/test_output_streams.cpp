// Every command that prints to the standard output, with that output on /dev/full or closed: one line on the
// standard error and exit 5, never exit 0 with the output lost. The commands that write files, stopped by
// SIGINT or SIGTERM while writing: exit 130 / 143, one line, no temporary left; and under a file-size limit
// (a disk that fills during the write): exit 5, one line, no file, no crash (icobrdf/io/program_end.hpp).
#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::cli_command;
using icobrdf::test::run_cli;
using icobrdf::test::slurp;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

// The exit code of a file system error (cli/exit_codes.hpp, kExitIo).
constexpr int kExitIo = 5;
// The file-size limit of the full-disk test: each command's output is larger (the smallest, the bank of one
// Lambert material at order 4, is about 20 kB), so every one fails part way through its write.
constexpr rlim_t kFileSizeLimitBytes = 4096;
// How often the signal test looks for the output's temporary (the LUT's write takes tens of milliseconds
// or more, so it is seen many times over).
constexpr auto kPollInterval = std::chrono::microseconds(500);

struct CommandRun {
  int code = -1;
  std::string err;
};

// `icobrdf args...` with its standard output redirected by `redirect` (e.g. ">/dev/full", ">&-").
CommandRun run_with_stdout(const std::vector<std::string>& args, const std::string& redirect, const TempDir& d) {
  const std::string err = d.file("stderr.txt");
  const int status = std::system((cli_command(args) + " " + redirect + " 2>" + err + " </dev/null").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(err)};
}

// One command line of each command that prints, with the files it reads made in `d`.
std::vector<std::vector<std::string>> printing_commands(const TempDir& d) {
  std::ofstream(d.file("pairs.csv")) << "theta_i,phi_i,theta_r,phi_r\n10,0,20,180\n30,0,45,90\n";
  std::ofstream(d.file("scene.toml")) << "[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\ntarget = 0.5\n\n"
                                         "[[material]]\nname = \"m\"\nsource = \"model:lambert\"\n";
  EXPECT_EQ(run_cli({"fit", "model:lambert", "--order", "2", "-o", d.file("spec.h5")}).exit_code, 0);
  EXPECT_EQ(run_cli({"bank", "build", d.file("scene.toml"), "-o", d.file("bank.h5"), "--quiet"}).exit_code, 0);
  return {{"models"},
          {"info"},
          {"grid", "--level", "2", "--json"},
          {"eval", "model:lambert", "--at", d.file("pairs.csv")},
          {"sample", "model:lambert", "--theta-i", "30", "-n", "20000"},
          {"modes", "--order", "2", "--at", d.file("pairs.csv")},
          {"spectrum", d.file("spec.h5")},
          {"bank", "info", d.file("bank.h5"), "--json"}};
}

std::string joined(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += (s.empty() ? "" : " ") + a;
  return s;
}

TEST(OutputStreams, EveryPrintingCommandFailsOnAFullOrClosedStandardOutput) {
  TempDir d;
  for (const auto& args : printing_commands(d)) {
    SCOPED_TRACE(joined(args));
    const CommandRun ok = run_with_stdout(args, ">" + d.file("out.txt"), d);
    ASSERT_EQ(ok.code, 0) << ok.err;  // the command line itself is valid
    ASSERT_FALSE(slurp(d.file("out.txt")).empty()) << "the command prints something";
    for (const std::string redirect : {">/dev/full", ">&-"}) {
      SCOPED_TRACE(redirect);
      const CommandRun r = run_with_stdout(args, redirect, d);
      EXPECT_EQ(r.code, kExitIo);
      EXPECT_NE(r.err.find("icobrdf: error: cannot write the standard output ("), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
    }
  }
}

// The hidden temporaries of atomic writes in `folder` (".NAME.tmp-PID-N").
std::vector<std::string> temporaries_in(const std::string& folder) {
  std::vector<std::string> found;
  if (DIR* dir = opendir(folder.c_str())) {
    while (const dirent* e = readdir(dir)) {
      const std::string n = e->d_name;
      if (n.size() > 1 && n[0] == '.' && n.find(".tmp-") != std::string::npos) found.push_back(n);
    }
    closedir(dir);
  }
  return found;
}

struct Stopped {
  bool signalled_while_writing = false;
  int status = 0;
  std::string err;
};

// Starts `icobrdf args...` with its standard output on /dev/null, its standard error into `err` and the
// file-size limit `file_size_limit` (RLIMIT_FSIZE); its process id.
pid_t start_program(const std::vector<std::string>& args, const std::string& err, rlim_t file_size_limit = RLIM_INFINITY) {
  const pid_t pid = fork();
  if (pid == 0) {
    const rlimit limit{file_size_limit, file_size_limit};
    if (setrlimit(RLIMIT_FSIZE, &limit) != 0) _exit(125);
    if (!freopen("/dev/null", "w", stdout) || !freopen(err.c_str(), "w", stderr)) _exit(126);
    std::vector<char*> argv{const_cast<char*>(ICOBRDF_CLI_PATH)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(ICOBRDF_CLI_PATH, argv.data());
    _exit(127);
  }
  return pid;
}

// Starts `icobrdf args...`, sends `sig` as soon as a temporary appears in `folder`, and waits.
Stopped stop_while_writing(const std::vector<std::string>& args, const std::string& folder, int sig, const TempDir& d) {
  const std::string err = d.file("stderr.txt");
  const pid_t pid = start_program(args, err);
  Stopped s;
  while (waitpid(pid, &s.status, WNOHANG) == 0) {
    if (!temporaries_in(folder).empty()) {
      kill(pid, sig);
      s.signalled_while_writing = true;
      waitpid(pid, &s.status, 0);
      break;
    }
    std::this_thread::sleep_for(kPollInterval);
  }
  s.err = slurp(err);
  return s;
}

TEST(OutputStreams, LutStoppedWhileWritingExitsWithTheSignalsCodeAndLeavesNoTemporary) {
  for (const int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig == SIGINT ? "SIGINT" : "SIGTERM");
    TempDir d, out;
    const std::string lut = out.file("lut.h5");
    const Stopped s = stop_while_writing({"lut", "model:ggx:alpha=0.3", "--level", "4", "-o", lut}, out.path, sig, d);
    ASSERT_TRUE(s.signalled_while_writing) << "the LUT was written before its temporary was seen: " << s.err;
    ASSERT_TRUE(WIFEXITED(s.status)) << "ended by the signal itself";
    EXPECT_EQ(WEXITSTATUS(s.status), 128 + sig);
    EXPECT_NE(s.err.find(sig == SIGINT ? "icobrdf: interrupted (SIGINT)" : "icobrdf: terminated (SIGTERM)"), std::string::npos) << s.err;
    EXPECT_TRUE(temporaries_in(out.path).empty());
    EXPECT_FALSE(std::ifstream(lut).good()) << "no partial LUT";
  }
}

// `icobrdf args...` with the file-size limit `bytes` (RLIMIT_FSIZE: writes beyond it fail, or SIGXFSZ ends
// a process that does not ignore it); the raw wait status.
Stopped run_with_file_size_limit(const std::vector<std::string>& args, rlim_t bytes, const TempDir& d) {
  const std::string err = d.file("stderr.txt");
  const pid_t pid = start_program(args, err, bytes);
  Stopped s;
  waitpid(pid, &s.status, 0);
  s.err = slurp(err);
  return s;
}

TEST(OutputStreams, AFileSizeLimitReachedWhileWritingGivesOneLineAndNoFile) {
  TempDir d, out;
  std::ofstream(d.file("scene.toml")) << "[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\ntarget = 0.5\n\n"
                                         "[[material]]\nname = \"m\"\nsource = \"model:lambert\"\n";
  const std::vector<std::pair<std::string, std::vector<std::string>>> writers = {
      {"lut.h5", {"lut", "model:lambert", "--level", "3", "--order", "4"}},
      {"spec.h5", {"fit", "model:lambert", "--order", "4"}},
      {"bank.h5", {"bank", "build", d.file("scene.toml"), "--quiet"}},
      {"lambert.binary", {"export", "model:lambert", "--format", "merl"}}};
  for (const auto& [name, command] : writers) {
    auto args = command;
    args.insert(args.end(), {"-o", out.file(name)});
    SCOPED_TRACE(joined(args));
    const Stopped s = run_with_file_size_limit(args, kFileSizeLimitBytes, d);
    // Before: SIGXFSZ ended the process with no line (and left the temporary); with the signal ignored,
    // HDF5's exit handler crashed closing the file whose close had failed (exit 139).
    ASSERT_TRUE(WIFEXITED(s.status)) << "ended by signal " << (WIFSIGNALED(s.status) ? WTERMSIG(s.status) : 0) << ": " << s.err;
    EXPECT_EQ(WEXITSTATUS(s.status), kExitIo) << s.err;
    EXPECT_NE(s.err.find("File too large"), std::string::npos) << "the system's reason: " << s.err;
    EXPECT_EQ(s.err.find('\n'), s.err.size() - 1) << "one line: " << s.err;
    EXPECT_TRUE(temporaries_in(out.path).empty());
    EXPECT_FALSE(std::ifstream(out.file(name)).good()) << "no partial file";
    EXPECT_FALSE(std::ifstream(out.file(name + ".partial")).good()) << "no partial bank";
  }
}

}  // namespace ICOBRDF_UNITY_ID
