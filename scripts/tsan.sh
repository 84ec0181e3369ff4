#!/usr/bin/env bash
# ThreadSanitizer check of code that renderers call from many threads at once (icobrdf/io/render_material.hpp:
# one material shared by several threads for eval / pdf / sample). Not a CI stage: it builds one test program
# of build-tsan (gcc, -O1 with line tables, -fsanitize=thread; the machine's own SIMD target only, no MPI, no
# benchmarks) and runs the tests whose names match the filter; any report makes the run fail (exit 66).
#   scripts/tsan.sh                                 test_io, RenderMaterial.Threads*
#   scripts/tsan.sh TARGET GTEST_FILTER             e.g. scripts/tsan.sh test_core 'HalfAngle*'
# OMP_NUM_THREADS=1: libgomp is not instrumented, so races inside OpenMP regions (the tables the material
# builds once) would be guessed at; the threads under test are the test's own std::threads.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${TSAN_BUILD_DIR:-build-tsan}
target=${1:-test_io}
filter=${2:-RenderMaterial.Threads*}
flags="-O1 -g1 -fsanitize=thread"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Tsan -DCMAKE_C_FLAGS_TSAN="$flags" -DCMAKE_CXX_FLAGS_TSAN="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -DCMAKE_SHARED_LINKER_FLAGS=-fsanitize=thread -DICOBRDF_NATIVE=ON \
  -DICOBRDF_MPI=OFF -DICOBRDF_BUILD_TESTS=ON -DICOBRDF_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$BUILD_DIR" -j"${JOBS:-$(nproc)}" --target "$target"
export TSAN_OPTIONS="halt_on_error=1:exitcode=66:second_deadlock_stack=1${TSAN_OPTIONS:+:$TSAN_OPTIONS}"
OMP_NUM_THREADS=1 "$BUILD_DIR/tests/$target" --gtest_filter="$filter"
