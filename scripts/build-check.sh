#!/usr/bin/env bash
# Configures and builds the instrumented "check" build that scripts/sanitize.sh and scripts/fuzz.sh share:
# clang at -O1 with line tables only (symbolized reports for a fraction of full debug info's compile time),
# AddressSanitizer + UndefinedBehaviorSanitizer everywhere (ICOBRDF_SANITIZE), and the libFuzzer targets of
# fuzz/ with the readers' libraries instrumented for coverage (ICOBRDF_FUZZ). -O1 compiles several times
# faster than -O3 under the instrumentation; without NDEBUG, Eigen's index assertions stay on.
# One build serves both stages, so CI compiles the instrumented code once.
# It is portable (-DICOBRDF_NATIVE=OFF, while the Release build of the test stage is -march=native): a
# native build compiles only the CPU's own SIMD target of the dispatched kernels, so on an AVX-512 machine the
# AVX2 kernels would never be tested. Here one target of each vector width this machine runs is compiled and
# runs its tests under the sanitizers: EMU128 (2 doubles, the portable fallback), AVX2 (4) and, where the CPU
# has AVX-512, AVX3_DL or else AVX3 (8). Left out (ICOBRDF_HWY_DISABLED_TARGETS), since the SIMD kernels are
# this build's most expensive files and each target costs about a sixth of their compile time: targets the
# CPU cannot run (they were compiled and never run); SSSE3 and SSE4, whose 2-double code EMU128's tests cover
# lane for lane (AMD and Intel desktop and server CPUs have had AVX2 since 2013-15); and AVX3 beside AVX3_DL,
# the same 8-double code with fewer instructions (the double-precision kernels use none of AVX3_DL's own).
# The test programs' own code is compiled without the sanitizers (ICOBRDF_SANITIZE_TESTS=OFF; about a third of
# this build's compile time): the libraries and the program the tests exercise stay instrumented, and the
# sanitizer runtime is linked, so every allocation is still checked. The cost: a template or inline function that
# a test file and a library both compile is linked once, and when the test's copy is the one kept, the library's
# calls to it run uninstrumented (functions the compiler inlined into library code keep their checks).
#   scripts/build-check.sh [TARGET...]     default: everything (tests, program, fuzzers); no benchmarks
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${CHECK_BUILD_DIR:-build-check}
# Highway's target bits (hwy/detect_targets.h): AVX3_DL 1<<7, AVX3 1<<8, SSE4 1<<11, SSSE3 1<<12.
disabled=$(((1 << 11) | (1 << 12)))
if grep -qw avx512vnni /proc/cpuinfo 2>/dev/null; then  # AVX3_DL: Ice Lake, Zen 4
  disabled=$((disabled | (1 << 8)))
else
  disabled=$((disabled | (1 << 7)))
  grep -qw avx512f /proc/cpuinfo 2>/dev/null || disabled=$((disabled | (1 << 8)))
fi
gen=()  # Ninja for a new build directory, as scripts/build.sh
[ -f "$BUILD_DIR/CMakeCache.txt" ] || ! command -v ninja >/dev/null || gen=(-G Ninja)
cmake -S . -B "$BUILD_DIR" "${gen[@]}" -DCMAKE_BUILD_TYPE=Check -DCMAKE_C_FLAGS_CHECK="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS_CHECK="-O1 -gline-tables-only" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DICOBRDF_SANITIZE=ON -DICOBRDF_SANITIZE_TESTS=OFF -DICOBRDF_FUZZ=ON -DICOBRDF_NATIVE=OFF -DICOBRDF_HWY_DISABLED_TARGETS=$disabled \
  -DICOBRDF_BUILD_TESTS=ON -DICOBRDF_BUILD_BENCHMARKS=OFF >/dev/null
if [ $# -gt 0 ]; then
  for t in "$@"; do cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}" --target "$t"; done
else
  cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}"
fi
