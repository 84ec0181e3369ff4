#!/usr/bin/env bash
# Builds icobrdf with AddressSanitizer + UndefinedBehaviorSanitizer (the compiler CMake picks, gcc on Debian)
# into build-asan and runs the whole CTest suite under them. Any sanitizer report ends the process that made
# it with a non-zero exit, so the test that ran it fails; the script's exit is CTest's.
#   scripts/sanitize.sh                 everything
#   scripts/sanitize.sh -R 'io_|core_'  extra arguments go to ctest (e.g. a subset)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-asan}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DICOBRDF_SANITIZE=ON -DICOBRDF_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}"
# halt_on_error: the first report ends the process (UBSan would otherwise print and go on).
# detect_leaks: LeakSanitizer checks every process at exit (it cannot run under ptrace, e.g. a debugger).
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=0:detect_leaks=1:strict_string_checks=1:check_initialization_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
cd "$BUILD_DIR"
ctest --output-on-failure -j"${JOBS:-$(nproc)}" "$@"
