#pragma once
// Exit codes of the icobrdf program. Distinct per error kind so scripts can tell them apart.
namespace icobrdf::cli {
inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;        // bad command line (CLI11 parse errors, ArgumentError)
inline constexpr int kExitInput = 3;        // malformed input file (InputError)
inline constexpr int kExitUnsupported = 4;  // request beyond what the numerics support (UnsupportedError)
inline constexpr int kExitIo = 5;           // file system error (IoError)
inline constexpr int kExitResources = 6;   // more memory than the machine offers (ResourceError, bad_alloc)
inline constexpr int kExitTargetsMissed = 7;  // bank build: the bank was written, some targets missed (on_miss = "keep-best")
inline constexpr int kExitInternal = 70;    // anything else: a bug
inline constexpr int kExitInterrupted = 130;  // SIGINT
inline constexpr int kExitTerminated = 143;   // SIGTERM
}  // namespace icobrdf::cli
