#include "icobrdf/io/output_path.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf {
namespace {

std::string kind_of(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw IoError(path + ": cannot write: " + what + ", expected a regular file or a new file name");
}

// "'TARGET', a FIFO", or "'TARGET', missing" for a dangling link.
std::string link_description(const std::string& path) {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink(path.c_str(), buf, sizeof buf - 1);
  const std::string target = n < 0 ? std::string("?") : std::string(buf, static_cast<size_t>(n));
  struct stat st;
  return "'" + target + "', " + (::stat(path.c_str(), &st) == 0 ? kind_of(st.st_mode) : std::string("missing"));
}

// The files an input text can name: itself, without a "kind:" prefix, and each without its "#..." suffix.
std::vector<std::string> input_files(const std::string& text) {
  std::vector<std::string> names{text};
  const auto colon = text.find(':');
  if (colon != std::string::npos && text.find('/') > colon) names.push_back(text.substr(colon + 1));
  for (size_t i = 0, n = names.size(); i < n; ++i) {
    const auto hash = names[i].rfind('#');
    if (hash != std::string::npos) names.push_back(names[i].substr(0, hash));
  }
  return names;
}

bool same_file(const struct stat& a, const std::string& path) {
  struct stat b;
  return ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

}  // namespace

void check_output_target(const std::string& path) {
  if (path.empty()) throw IoError("cannot write: empty output path");
  const std::string name = file_name(path);
  if (name.empty() || name == "." || name == "..") throw IoError(path + ": cannot write: the path names a folder, expected a file name");
  struct stat st;
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISLNK(st.st_mode)) refuse(path, "the path is a symbolic link (to " + link_description(path) + ", which the rename would replace)");
    if (S_ISDIR(st.st_mode)) refuse(path, "the path is a folder");
    if (!S_ISREG(st.st_mode)) refuse(path, "the path is " + kind_of(st.st_mode));
  }
  const std::string folder = parent_folder(path);
  if (::stat(folder.c_str(), &st) != 0)
    throw IoError(path + ": cannot write: folder " + folder + ": " + std::strerror(errno));
  if (!S_ISDIR(st.st_mode)) throw IoError(path + ": cannot write: folder " + folder + ": " + std::strerror(ENOTDIR));
}

void check_output_path(const std::string& path, const std::vector<std::string>& inputs) {
  check_output_target(path);
  const std::string folder = parent_folder(path);
  const std::string probe = folder + "/." + file_name(path) + ".probe-" + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0 && errno != EEXIST)
    throw IoError(path + ": cannot write: cannot create a file in folder " + folder + ": " + std::strerror(errno));
  if (fd >= 0) {
    ::close(fd);
    ::unlink(probe.c_str());
  }
  struct stat out;
  if (::stat(path.c_str(), &out) != 0) return;  // a new file cannot be an input
  for (const auto& input : inputs)
    for (const auto& file : input_files(input))
      if (same_file(out, file))
        throw ArgumentError(path + ": is the same file as the input '" + input +
                            "'; writing it would replace that input: choose another output path");
}

}  // namespace icobrdf
