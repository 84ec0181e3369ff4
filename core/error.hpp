#pragma once
// Error kinds raised by icobrdf. Every message is one line: what went wrong, where, expected vs actual.
// The CLI maps each kind to its own exit code (cli/exit_codes.hpp).
#include <cstdio>
#include <stdexcept>
#include <string>

namespace icobrdf {

// A call's arguments are invalid (m > n, negative order, unknown model name, ...).
struct ArgumentError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
// The request is valid but exceeds what the numerics support (order beyond what a grid resolves,
// near-singular Gram matrix); the message names the supported limit.
struct UnsupportedError : std::domain_error {
  using std::domain_error::domain_error;
};
// Input data is malformed (file content): the message names the file and the place.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The file system refused (cannot create, write, rename, disk full).
struct IoError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Control bytes (newlines, NUL, ...) of user text or file content as \xHH, so that a message quoting
// them stays one line.
inline std::string printable_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[5];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace icobrdf
