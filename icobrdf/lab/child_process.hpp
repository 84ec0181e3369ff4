#pragma once
// Runs a program as a child process with a few variables removed from its environment, and captures what
// it prints. `bench project` uses it to time OpenBLAS on the kernel OpenBLAS picks for the CPU: OpenBLAS
// reads OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE once, when the library loads, so only a fresh process can
// time it without them; the parent's own environment is never changed.
#include <string>
#include <vector>

namespace icobrdf::lab {

struct ChildResult {
  int exit_code = -1;  // the child's exit status; -1 when it was killed by a signal
  int signal = 0;      // the signal that ended it, 0 when it exited
  std::string out, err;
};

// Runs argv[0] (a path, not searched on PATH) with arguments argv[1..] and the parent's environment minus
// every variable named in `removed`, plus the "NAME=VALUE" entries of `added` (whose names must be among
// `removed`, so that each is set once); waits for it. IoError when the program cannot be started,
// ArgumentError for an `added` entry that is not NAME=VALUE with NAME in `removed`.
ChildResult run_child(const std::vector<std::string>& argv, const std::vector<std::string>& removed,
                      const std::vector<std::string>& added = {});

// Path of the running program (/proc/self/exe).
std::string own_executable();

}  // namespace icobrdf::lab
