#pragma once
// Shared by the libFuzzer targets (fuzz/fuzz_<reader>.cpp): the fuzz input as a file on disk, and the rule
// every target checks: a reader returns, or throws InputError / IoError (icobrdf/core/support/error.hpp) with a one-line
// message. Anything else (another exception type, a multi-line message, a crash, a sanitizer report, a hang
// beyond libFuzzer's -timeout) is a finding: the target aborts so that libFuzzer saves the input.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>
#include <utility>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf::fuzz {

// Folder of the temporary input files: /dev/shm (memory, no disk writes) when usable, else $TMPDIR, else /tmp.
inline std::string scratch_folder() {
  if (::access("/dev/shm", W_OK | X_OK) == 0) return "/dev/shm";
  const char* t = std::getenv("TMPDIR");
  return t && *t ? t : "/tmp";
}

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// A file holding the current input; one path per process, rewritten for each input, removed on destruction.
class InputFile {
 public:
  explicit InputFile(const char* stem, const char* suffix)
      : path_(scratch_folder() + "/icobrdf-fuzz-" + stem + "-" + std::to_string(::getpid()) + suffix) {}
  ~InputFile() { ::unlink(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  const std::string& path() const { return path_; }
  // Replaces the file's content by `size` bytes (a fresh inode each time, as a user's new file would be).
  void write(const void* data, size_t size) const {
    ::unlink(path_.c_str());
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) finding("cannot create the scratch file " + path_);
    const auto* p = static_cast<const unsigned char*>(data);
    size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd, p + done, size - done);
      if (n <= 0) finding("cannot write the scratch file " + path_);
      done += static_cast<size_t>(n);
    }
    ::close(fd);
  }

 private:
  std::string path_;
};

inline void check_message(const char* kind, const std::exception& e) {
  const std::string m = e.what();
  if (m.empty()) finding(std::string(kind) + " with an empty message");
  if (m.find('\n') != std::string::npos) finding(std::string(kind) + " message is not one line: " + m);
}

// Runs `call`: returning, or throwing InputError / IoError with a one-line message, is fine; with
// `kUserText` (text a user types on the command line: a SOURCE, a model spec) so are ArgumentError (the
// CLI's usage error) and UnsupportedError. Anything else aborts.
template <bool kUserText, class F>
void expect_errors_of_kind(F&& call) {
  try {
    call();
  } catch (const ArgumentError& e) {
    if (!kUserText) finding(std::string("unexpected ArgumentError: ") + e.what());
    check_message("ArgumentError", e);
  } catch (const UnsupportedError& e) {
    if (!kUserText) finding(std::string("unexpected UnsupportedError: ") + e.what());
    check_message("UnsupportedError", e);
  } catch (const InputError& e) {
    check_message("InputError", e);
  } catch (const IoError& e) {
    check_message("IoError", e);
  } catch (const std::exception& e) {
    finding(std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("unexpected exception of a non-std type");
  }
}

// Readers of files: InputError / IoError only.
template <class F>
void expect_input_errors_only(F&& read) {
  expect_errors_of_kind<false>(std::forward<F>(read));
}

// Parsers of command-line text: also ArgumentError / UnsupportedError.
template <class F>
void expect_user_errors_only(F&& parse) {
  expect_errors_of_kind<true>(std::forward<F>(parse));
}

}  // namespace icobrdf::fuzz
