#include "icobrdf/io/program_end.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/h5_file.hpp"

namespace icobrdf {
namespace {

bool g_stdout_was_closed = false;
std::atomic<int> g_stop_signal_seen{0};

extern "C" void icobrdf_record_stop_signal(int sig) { g_stop_signal_seen.store(sig); }

bool descriptor_closed(int fd) { return ::fcntl(fd, F_GETFD) == -1 && errno == EBADF; }

// Opens `device` on descriptor `fd` (the lowest free number, which is fd when the lower ones are open).
void open_on(int fd, const char* device, int flags) {
  const int got = ::open(device, flags);
  if (got >= 0 && got != fd) {
    ::dup2(got, fd);
    ::close(got);
  }
}

extern "C" void icobrdf_on_program_stop_signal(int sig) {
  // Said only when files were removed: a stop with nothing unfinished ends silently, as programs stopped by a
  // signal do (under mpirun, a usage error on rank 0 makes mpirun terminate the other ranks: one line, not two).
  if (remove_unfinished_temporaries_in_signal_handler() > 0) {
    static const char kInt[] = "icobrdf: interrupted (SIGINT); unfinished output files removed\n";
    static const char kTerm[] = "icobrdf: terminated (SIGTERM); unfinished output files removed\n";
    const char* line = sig == SIGINT ? kInt : kTerm;
    (void)!::write(STDERR_FILENO, line, std::strlen(line));
  }
  ::_exit(128 + sig);
}

}  // namespace

void guard_standard_streams() {
  if (descriptor_closed(STDIN_FILENO)) open_on(STDIN_FILENO, "/dev/null", O_RDONLY);
  if (descriptor_closed(STDOUT_FILENO)) {
    g_stdout_was_closed = true;
    open_on(STDOUT_FILENO, "/dev/full", O_WRONLY);
  }
  if (descriptor_closed(STDERR_FILENO)) open_on(STDERR_FILENO, "/dev/full", O_WRONLY);
}

void install_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = icobrdf_on_program_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // Over the file-size limit (ulimit -f) a write fails with EFBIG, reported as any full disk is, instead of
  // SIGXFSZ ending the process with no line and its temporaries left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  h5::leave_library_at_exit();
}

std::atomic<int>& record_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = icobrdf_record_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  return g_stop_signal_seen;
}

int finish_standard_output(int code, int io_code) {
  errno = 0;
  std::cout.flush();
  const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!failed) return code;
  const int err = errno;
  const std::string why = g_stdout_was_closed ? "it was closed"
                          : err != 0          ? std::string(std::strerror(err))
                                              : "a write to it failed";
  std::cerr << "icobrdf: error: cannot write the standard output (" << why << "): what the command printed is incomplete\n";
  return code == 0 ? io_code : code;
}

}  // namespace icobrdf
