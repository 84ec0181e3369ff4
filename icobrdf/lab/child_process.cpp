#include "icobrdf/lab/child_process.hpp"

#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "icobrdf/core/support/error.hpp"

extern char** environ;

namespace icobrdf::lab {
namespace {

bool is_removed(const char* entry, const std::vector<std::string>& removed) {
  for (const auto& name : removed)
    if (std::strncmp(entry, name.c_str(), name.size()) == 0 && entry[name.size()] == '=') return true;
  return false;
}

// Reads both pipes until each reaches end of file (poll, so that a child filling one pipe never blocks).
void drain(int out_fd, int err_fd, std::string& out, std::string& err) {
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  std::string* dest[2] = {&out, &err};
  int open_fds = 2;
  char buf[65536];
  while (open_fds > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        dest[i]->append(buf, static_cast<size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_fds;
      }
    }
  }
}

}  // namespace

std::string own_executable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

ChildResult run_child(const std::vector<std::string>& argv, const std::vector<std::string>& removed,
                      const std::vector<std::string>& added) {
  if (argv.empty()) throw ArgumentError("child process: no program given");
  for (const auto& a : added) {
    const auto eq = a.find('=');
    if (eq == std::string::npos || eq == 0 || std::find(removed.begin(), removed.end(), a.substr(0, eq)) == removed.end())
      throw ArgumentError("child process: added variable '" + a + "' is not NAME=VALUE with NAME among the removed ones");
  }
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e)
    if (!is_removed(*e, removed)) env.push_back(*e);
  for (const auto& a : added) env.push_back(const_cast<char*>(a.c_str()));
  env.push_back(nullptr);

  int out_pipe[2], err_pipe[2];
  if (::pipe(out_pipe) != 0) throw IoError("child process " + argv[0] + ": cannot create a pipe (" + std::strerror(errno) + ")");
  if (::pipe(err_pipe) != 0) {
    ::close(out_pipe[0]), ::close(out_pipe[1]);
    throw IoError("child process " + argv[0] + ": cannot create a pipe (" + std::strerror(errno) + ")");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, out_pipe[0]);
  posix_spawn_file_actions_addclose(&actions, err_pipe[0]);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  if (rc != 0) {
    ::close(out_pipe[0]), ::close(err_pipe[0]);
    throw IoError("child process " + argv[0] + ": cannot start (" + std::strerror(rc) + ")");
  }
  ChildResult r;
  drain(out_pipe[0], err_pipe[0], r.out, r.err);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

}  // namespace icobrdf::lab
