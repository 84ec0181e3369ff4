#pragma once
// Runs the built icobrdf program in a child process (fork + execv, no shell) and measures it: exit code,
// stderr, and the peak resident memory the kernel reports for it (wait4's ru_maxrss). Optionally with an
// address-space limit (RLIMIT_AS, as `ulimit -v` sets it) and extra environment variables.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "tests/cli/cli_runner.hpp"

namespace icobrdf::test {

// Builds under AddressSanitizer reserve terabytes of address space and double resident memory, so
// neither RLIMIT_AS nor peak-RSS figures mean anything there.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

struct MeasuredRun {
  int exit_code = -1;    // -1: ended by a signal (signal_number says which)
  int signal_number = 0;
  double peak_bytes = 0;  // ru_maxrss of the child
  std::string err;
};

inline MeasuredRun run_measured(const std::vector<std::string>& args, double address_limit_bytes = 0,
                                const std::vector<std::pair<std::string, std::string>>& env = {}) {
  char err_tmpl[] = "/tmp/icobrdf_measured_errXXXXXX";
  const int fe = mkstemp(err_tmpl);
  const pid_t pid = fork();
  if (pid == 0) {
    const int null_fd = ::open("/dev/null", O_RDWR);
    dup2(null_fd, 0);
    dup2(null_fd, 1);
    dup2(fe, 2);
    if (address_limit_bytes > 0) {
      rlimit rl{static_cast<rlim_t>(address_limit_bytes), static_cast<rlim_t>(address_limit_bytes)};
      setrlimit(RLIMIT_AS, &rl);
    }
    for (const auto& [k, v] : env) setenv(k.c_str(), v.c_str(), 1);
    std::vector<std::string> all{ICOBRDF_CLI_PATH};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(ICOBRDF_CLI_PATH, argv.data());
    _exit(127);
  }
  close(fe);
  MeasuredRun r;
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal_number = WTERMSIG(status);
  r.peak_bytes = static_cast<double>(ru.ru_maxrss) * 1024.0;  // Linux reports KiB
  r.err = slurp(err_tmpl);
  std::remove(err_tmpl);
  return r;
}

}  // namespace icobrdf::test
