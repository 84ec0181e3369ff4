#!/usr/bin/env bash
# Configures and builds the instrumented "check" build that scripts/sanitize.sh and scripts/fuzz.sh share:
# clang at -O1 with line tables only (symbolized reports for a fraction of full debug info's compile time),
# AddressSanitizer + UndefinedBehaviorSanitizer everywhere (ICOBRDF_SANITIZE), and the libFuzzer targets of
# fuzz/ with the readers' libraries instrumented for coverage (ICOBRDF_FUZZ). -O1 compiles several times
# faster than -O3 under the instrumentation; without NDEBUG, Eigen's index assertions stay on.
# One build serves both stages, so CI compiles the instrumented code once.
# It is portable (-DICOBRDF_NATIVE=OFF, while the Release build of the test stage is -march=native): a
# native build compiles only the CPU's own SIMD target of the dispatched kernels, so on an AVX-512 machine the
# AVX2 kernels would never be tested. Here every target Highway compiles (AVX3_DL, AVX3, AVX2, SSE4, SSSE3,
# EMU128) runs its tests on this CPU under the sanitizers, and the portable configuration itself is tested.
#   scripts/build-check.sh [TARGET...]     default: everything (tests, program, fuzzers); no benchmarks
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${CHECK_BUILD_DIR:-build-check}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Check -DCMAKE_C_FLAGS_CHECK="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS_CHECK="-O1 -gline-tables-only" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DICOBRDF_SANITIZE=ON -DICOBRDF_FUZZ=ON -DICOBRDF_NATIVE=OFF \
  -DICOBRDF_BUILD_TESTS=ON -DICOBRDF_BUILD_BENCHMARKS=OFF >/dev/null
if [ $# -gt 0 ]; then
  for t in "$@"; do cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}" --target "$t"; done
else
  cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}"
fi
