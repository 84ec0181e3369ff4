#pragma once
// File-system nodes other than regular files, for the output-path tests (io and cli): a UNIX socket made
// with bind(), and what a node is without following links. FIFOs come from mkfifo(); device nodes are not
// made (mknod needs root).
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

namespace icobrdf::test {

inline void make_socket(const std::string& path) {
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof a.sun_path);
  std::strcpy(a.sun_path, path.c_str());
  ASSERT_EQ(::bind(s, reinterpret_cast<const sockaddr*>(&a), sizeof a), 0) << std::strerror(errno);
  ::close(s);
}

// "missing", the S_IFMT bits of a node, or "link to TARGET" for a symbolic link.
inline std::string node_kind(const std::string& path) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) return "missing";
  if (!S_ISLNK(st.st_mode)) return std::to_string(st.st_mode & S_IFMT);
  char buf[4096];
  const ssize_t n = ::readlink(path.c_str(), buf, sizeof buf);
  return "link to " + std::string(buf, n < 0 ? 0 : static_cast<size_t>(n));
}

}  // namespace icobrdf::test
