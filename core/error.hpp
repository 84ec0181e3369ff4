#pragma once
// Error kinds raised by icobrdf. Every message is one line: what went wrong, where, expected vs actual.
// The CLI maps each kind to its own exit code (cli/exit_codes.hpp).
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

}  // namespace icobrdf
